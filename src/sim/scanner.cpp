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

// The tangents of each layer's vertical footprint edges at body pitch `pitch_deg`.
void LayerSlopes(const ScannerConfig& c, double pitch_deg, double* lower, double* upper) {
  for (int l = 0; l < c.layers; ++l) {
    const double e = c.layer_elevation_deg(l) + pitch_deg;
    lower[l] = std::tan((e - 0.5 * c.beam_height_deg) * kDegToRad);
    upper[l] = std::tan((e + 0.5 * c.beam_height_deg) * kDegToRad);
  }
}

// The first face along the beam whose height range meets the layer's footprint (edge slopes
// `lower`, `upper`) above the road; null when none does.
const RayHit* FirstFace(const std::vector<RayHit>& hits, const World& world, double height,
                        double lower, double upper) {
  for (const RayHit& h : hits) {
    const Obstacle& o = world.obstacles[h.obstacle];
    const double z_low = std::max(0.0, height + h.distance * lower);
    const double z_high = height + h.distance * upper;
    if (z_high >= 0.0 && z_low <= o.z_max_m && z_high >= o.z_min_m) return &h;
  }
  return nullptr;
}

// What one layer of one beam sees before range noise: its source and true range.
struct Echo {
  EchoSource source = EchoSource::kNoEchoRange;
  double range = 0.0;
};

// The layer's echo along the beam whose faces are `hits`: a ground echo where the footprint
// reaches the road first (the road swallows the beam beyond where it covers the footprint),
// else the first face met unless it absorbs the beam or its echo is too weak; rain or dust
// nearer than either replaces it.
Echo LayerEcho(const ScannerConfig& c, const World& world, const std::vector<RayHit>& hits,
               double lower, double upper, Rng& rng) {
  const double height = c.mount_height_m;
  const RayHit* hit = FirstFace(hits, world, height, lower, upper);
  double end = hit != nullptr ? hit->distance : c.max_range_m;
  // The road: the footprint's lower edge reaches it at `near`, the whole footprint at
  // `far`; beyond `far` nothing else can be seen.
  const double near = lower < 0.0 ? height / -lower : INFINITY;
  const double far = upper < 0.0 ? height / -upper : INFINITY;
  Echo echo;
  if (near < end) {
    const bool swallowed = far < end;
    if (swallowed) {
      end = far;
      hit = nullptr;
    }
    if (rng.Bernoulli(c.ground_echo_probability)) {
      // The echo comes from a random elevation within the footprint's part below -0.05 deg.
      const double top = std::min(upper, std::tan(-0.05 * kDegToRad));
      const double slope = top > lower ? rng.Uniform(lower, top) : lower;
      const double r = height / -slope;
      if (r < end) {
        echo = {EchoSource::kGround, r};
        hit = nullptr;
      }
    }
  }
  if (echo.source != EchoSource::kGround && hit != nullptr) {
    const Obstacle& o = world.obstacles[hit->obstacle];
    if (rng.Bernoulli(o.no_echo_probability)) {
      echo.source = EchoSource::kNoEchoAbsorbed;
    } else if (!rng.Bernoulli(
                   c.DetectionProbability(o.reflectivity, hit->cos_incidence, hit->distance))) {
      echo.source = EchoSource::kNoEchoWeak;
    } else {
      echo = {EchoSource::kObstacle, hit->distance};
    }
  }
  if (rng.Bernoulli(c.rain_probability)) {
    const double r = rng.Uniform(c.rain_min_range_m, c.rain_max_range_m);
    const bool returned =
        echo.source == EchoSource::kObstacle || echo.source == EchoSource::kGround;
    if (r < (returned ? echo.range : end)) echo = {EchoSource::kRain, r};
  }
  return echo;
}

// The point the sensor reports for `echo` on layer `layer` at `deg`: range noise and
// quantisation; a range outside the sensor's turns the echo into kNoEchoRange.
ScanPoint Measure(const ScannerConfig& c, int layer, double deg, Echo* echo, Rng& rng) {
  ScanPoint p;
  p.layer = std::uint8_t(layer);
  p.angle_rad = float(deg * kDegToRad);
  p.echo = false;
  if (echo->source == EchoSource::kObstacle || echo->source == EchoSource::kGround ||
      echo->source == EchoSource::kRain) {
    double r = echo->range + c.range_sigma_m * rng.Normal();
    if (c.range_resolution_m > 0.0) {
      r = std::round(r / c.range_resolution_m) * c.range_resolution_m;
    }
    if (r >= c.min_range_m && r < c.max_range_m) {
      p.echo = true;
      p.range_m = float(r);
    } else {
      echo->source = EchoSource::kNoEchoRange;
    }
  }
  return p;
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
  s.sweep_s = sweep_s;  // beam 0 (min_angle_deg) first, as Scan() takes them
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
  double lower[256], upper[256];
  LayerSlopes(c, pitch_deg_, lower, upper);
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
      Echo echo = LayerEcho(c, world_, hits_, lower[l], upper[l], rng_);
      scan->points.push_back(Measure(c, l, deg, &echo, rng_));
      if (sources != nullptr) sources->push_back(echo.source);
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
