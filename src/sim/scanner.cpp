// The ScaLa-like scanner model: see scanner.hpp.
#include "sim/scanner.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace freespace::sim {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

void Require(bool ok, const char* field, double value, const char* rule) {
  if (!ok) {
    throw std::invalid_argument(std::string("scanner: ") + field + " = " + std::to_string(value) +
                                ": " + rule);
  }
}

}  // namespace

int ScannerConfig::beams() const {
  return int(std::floor((max_angle_deg - min_angle_deg) / resolution_deg + 0.5)) + 1;
}

double ScannerConfig::beam_angle_deg(int i) const { return min_angle_deg + i * resolution_deg; }

double ScannerConfig::layer_elevation_deg(int l) const {
  return mount_pitch_deg + (l - 0.5 * (layers - 1)) * layer_spacing_deg;
}

SensorConfig ScannerConfig::EngineSensor() const {
  SensorConfig s;
  s.layers = layers;
  s.min_angle_deg = min_angle_deg;
  s.max_angle_deg = max_angle_deg;
  s.angular_resolution_deg = resolution_deg;
  s.min_range_m = min_range_m;
  s.max_range_m = max_range_m;
  s.mount_x_m = mount_x_m;
  s.mount_y_m = mount_y_m;
  s.mount_yaw_deg = mount_yaw_deg;
  return s;
}

double ScannerConfig::DetectionProbability(double reflectivity, double cos_incidence,
                                           double range) const {
  const double power = reflectivity * cos_incidence / 0.1;
  if (!(power > 0.0)) return 0.0;
  const double r50 = detection_range_m * std::sqrt(power);
  return 1.0 / (1.0 + std::pow(range / r50, detection_exponent));
}

Pose2D ScannerConfig::mount() const { return {mount_x_m, mount_y_m, mount_yaw_deg * kDegToRad}; }

void ScannerConfig::Validate() const {
  Require(layers >= 1 && layers <= 255, "layers", layers, "1 .. 255");
  Require(max_angle_deg > min_angle_deg && max_angle_deg - min_angle_deg < 180.0, "max_angle_deg",
          max_angle_deg, "above min_angle_deg, aperture below 180 deg");
  Require(resolution_deg > 0.0, "resolution_deg", resolution_deg, "> 0");
  Require(max_range_m > min_range_m && min_range_m >= 0.0, "max_range_m", max_range_m,
          "> min_range_m >= 0");
  Require(range_resolution_m >= 0.0, "range_resolution_m", range_resolution_m, ">= 0");
  Require(range_sigma_m >= 0.0, "range_sigma_m", range_sigma_m, ">= 0");
  Require(scan_period_s > 0.0, "scan_period_s", scan_period_s, "> 0");
  Require(sweep_s >= 0.0 && sweep_s <= scan_period_s, "sweep_s", sweep_s, "0 .. scan_period_s");
  Require(mount_height_m > 0.0, "mount_height_m", mount_height_m, "> 0");
  Require(pitch_correlation >= 0.0 && pitch_correlation < 1.0, "pitch_correlation",
          pitch_correlation, "[0, 1)");
  Require(detection_range_m > 0.0, "detection_range_m", detection_range_m, "> 0");
  Require(detection_exponent > 0.0, "detection_exponent", detection_exponent, "> 0");
  for (const auto& [name, p] : {std::pair{"ground_echo_probability", ground_echo_probability},
                                {"rain_probability", rain_probability}}) {
    Require(p >= 0.0 && p <= 1.0, name, p, "a probability, 0 .. 1");
  }
  Require(rain_max_range_m >= rain_min_range_m && rain_min_range_m >= 0.0, "rain_max_range_m",
          rain_max_range_m, ">= rain_min_range_m >= 0");
}

ScanSimulator::ScanSimulator(const ScannerConfig& config, const World& world, std::uint64_t seed)
    : config_(config), world_(world), caster_(world), rng_(seed, kStreamSensor) {
  config_.Validate();
}

void ScanSimulator::Simulate(double t, const Trajectory& trajectory, Scan* scan,
                             std::vector<EchoSource>* sources) {
  const ScannerConfig& c = config_;
  caster_.PlaceMovers(world_.MoverPoses(t));
  const MotionState at_t = trajectory.At(t);
  // Body pitch: the load transfer follows the acceleration; the unevenness is correlated.
  const double rho = c.pitch_correlation;
  unevenness_deg_ =
      rho * unevenness_deg_ + std::sqrt(1.0 - rho * rho) * c.pitch_sigma_deg * rng_.Normal();
  pitch_deg_ = c.pitch_per_accel_deg * at_t.acceleration + unevenness_deg_;

  const int beams = c.beams();
  const double height = c.mount_height_m;
  double lower[256], upper[256];
  for (int l = 0; l < c.layers; ++l) {
    const double e = c.layer_elevation_deg(l) + pitch_deg_;
    lower[l] = std::tan((e - 0.5 * c.beam_height_deg) * kDegToRad);
    upper[l] = std::tan((e + 0.5 * c.beam_height_deg) * kDegToRad);
  }
  const Pose2D mount = c.mount();

  scan->timestamp_s = t;
  scan->points.clear();
  scan->points.reserve(std::size_t(beams) * c.layers);
  if (sources != nullptr) {
    sources->clear();
    sources->reserve(scan->points.capacity());
  }
  for (int i = 0; i < beams; ++i) {
    // Where the sensor is when the mirror points at beam i.
    const double fraction = beams > 1 ? double(i) / (beams - 1) - 0.5 : 0.0;
    const Pose2D vehicle = trajectory.At(t + fraction * c.sweep_s).pose;
    const Pose2D sensor = Compose(vehicle, mount);
    const double deg = c.beam_angle_deg(i);
    const double azimuth = sensor.yaw + deg * kDegToRad;
    const Vec2 origin(sensor.x, sensor.y), dir(std::cos(azimuth), std::sin(azimuth));
    caster_.Cast(origin, dir, c.max_range_m, &hits_);

    for (int l = 0; l < c.layers; ++l) {
      // The first face whose height range meets the layer's footprint above the road.
      const RayHit* hit = nullptr;
      for (const RayHit& h : hits_) {
        const Obstacle& o = world_.obstacles[h.obstacle];
        const double z_low = std::max(0.0, height + h.distance * lower[l]);
        const double z_high = height + h.distance * upper[l];
        if (z_high >= 0.0 && z_low <= o.z_max_m && z_high >= o.z_min_m) {
          hit = &h;
          break;
        }
      }
      double end = hit != nullptr ? hit->distance : c.max_range_m;
      // The road: the footprint's lower edge reaches it at `near`, the whole footprint at
      // `far`; beyond `far` nothing else can be seen.
      const double near = lower[l] < 0.0 ? height / -lower[l] : INFINITY;
      const double far = upper[l] < 0.0 ? height / -upper[l] : INFINITY;
      EchoSource source = EchoSource::kNoEchoRange;
      double range = 0.0;
      if (near < end) {
        const bool swallowed = far < end;
        if (swallowed) {
          end = far;
          hit = nullptr;
        }
        if (rng_.Bernoulli(c.ground_echo_probability)) {
          // The echo comes from a random elevation within the footprint's part below -0.05 deg.
          const double top = std::min(upper[l], std::tan(-0.05 * kDegToRad));
          const double slope = top > lower[l] ? rng_.Uniform(lower[l], top) : lower[l];
          const double r = height / -slope;
          if (r < end) {
            source = EchoSource::kGround;
            range = r;
            hit = nullptr;
          }
        }
      }
      if (source != EchoSource::kGround && hit != nullptr) {
        const Obstacle& o = world_.obstacles[hit->obstacle];
        if (rng_.Bernoulli(o.no_echo_probability)) {
          source = EchoSource::kNoEchoAbsorbed;
        } else if (!rng_.Bernoulli(
                       c.DetectionProbability(o.reflectivity, hit->cos_incidence, hit->distance))) {
          source = EchoSource::kNoEchoWeak;
        } else {
          source = EchoSource::kObstacle;
          range = hit->distance;
        }
      }
      if (rng_.Bernoulli(c.rain_probability)) {
        const double r = rng_.Uniform(c.rain_min_range_m, c.rain_max_range_m);
        const bool echo = source == EchoSource::kObstacle || source == EchoSource::kGround;
        if (r < (echo ? range : end)) {
          source = EchoSource::kRain;
          range = r;
        }
      }

      ScanPoint p;
      p.layer = std::uint8_t(l);
      p.angle_rad = float(deg * kDegToRad);
      p.echo = false;
      if (source == EchoSource::kObstacle || source == EchoSource::kGround ||
          source == EchoSource::kRain) {
        double r = range + c.range_sigma_m * rng_.Normal();
        if (c.range_resolution_m > 0.0) {
          r = std::round(r / c.range_resolution_m) * c.range_resolution_m;
        }
        if (r >= c.min_range_m && r < c.max_range_m) {
          p.echo = true;
          p.range_m = float(r);
        } else {
          source = EchoSource::kNoEchoRange;
        }
      }
      scan->points.push_back(p);
      if (sources != nullptr) sources->push_back(source);
    }
  }
}

Polygon VisibilityPolygon(RayCaster& caster, const Pose2D& sensor, const ScannerConfig& config) {
  Polygon out;
  const int beams = config.beams();
  out.reserve(beams + 1);
  out.emplace_back(sensor.x, sensor.y);
  const Vec2 origin(sensor.x, sensor.y);
  for (int i = 0; i < beams; ++i) {
    const double a = sensor.yaw + config.beam_angle_deg(i) * kDegToRad;
    const Vec2 dir(std::cos(a), std::sin(a));
    out.push_back(origin + dir * caster.FirstHit(origin, dir, config.max_range_m));
  }
  return out;
}

Polygon SurroundingVisibility(RayCaster& caster, const Vec2& origin, double step_deg,
                              double max_range) {
  const int rays = std::max(3, int(std::lround(360.0 / step_deg)));
  Polygon out;
  out.reserve(rays);
  for (int i = 0; i < rays; ++i) {
    const double a = 2.0 * M_PI * i / rays;
    const Vec2 dir(std::cos(a), std::sin(a));
    out.push_back(origin + dir * caster.FirstHit(origin, dir, max_range));
  }
  return out;
}

}  // namespace freespace::sim
