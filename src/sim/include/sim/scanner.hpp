// A ScaLa-like multi-layer laser scanner (paper section V.A): 4 layers 0.8 deg apart, 145 deg
// at 0.25 deg, 150 m, 25 Hz, 0.1 m range resolution, mounted 0.3 m high on the front bumper.
// Each beam is an exact ray through the world; a layer sees the first obstacle whose height
// range meets the layer's vertical footprint, or the road when the footprint reaches the
// ground first. On top: range noise and quantisation, the body's pitch (acceleration and road
// unevenness), sparse ground and rain / dust echoes, and beams without echo (open space
// beyond range; echoes too weak from dark, far or glancing surfaces; glass). The mirror sweeps
// the aperture during part of the scan period, so at speed the points are smeared as on the
// real sensor.
#pragma once

#include <cstdint>
#include <vector>

#include "freespace/config.hpp"
#include "freespace/scan.hpp"
#include "sim/random.hpp"
#include "sim/trajectory.hpp"
#include "sim/world.hpp"

namespace freespace::sim {

struct ScannerConfig {
  // Geometry.
  int layers = 4;
  double layer_spacing_deg = 0.8;  // between layer centres, symmetric about the mount pitch
  double beam_height_deg = 0.8;    // vertical divergence of one layer
  double min_angle_deg = -72.5;    // horizontal aperture, sensor frame, counter-clockwise
  double max_angle_deg = 72.5;
  double resolution_deg = 0.25;
  double min_range_m = 0.1;
  double max_range_m = 150.0;
  double range_resolution_m = 0.1;  // ranges are quantised to this
  double range_sigma_m = 0.03;      // range noise before quantisation
  double scan_period_s = 0.04;      // 25 Hz
  double sweep_s = 0.016;           // the mirror crosses the aperture in this time

  // Mount, in the vehicle frame (reference point: rear axle centre).
  double mount_x_m = 3.7;  // front bumper
  double mount_y_m = 0.0;
  double mount_yaw_deg = 0.0;
  double mount_height_m = 0.3;
  double mount_pitch_deg = 0.0;

  // Body pitch: nose up while accelerating, down while braking, plus road unevenness
  // (first-order correlated from scan to scan).
  double pitch_per_accel_deg = 0.1;  // per m/s^2
  double pitch_sigma_deg = 0.05;
  double pitch_correlation = 0.9;  // from one scan to the next, [0, 1)

  // Echo detection. The echo's power goes as reflectivity * cos(incidence) / range^2; a
  // target of reflectivity 0.1 met head-on is detected half the time at detection_range_m,
  // so a surface is detected half the time at R50 = detection_range_m *
  // sqrt(reflectivity * cos(incidence) / 0.1), with probability 1 / (1 + (r / R50)^k) at
  // range r, k = detection_exponent. Dark paint fades first, glancing surfaces next.
  double detection_range_m = 80.0;
  double detection_exponent = 4.0;

  // Clutter.
  double ground_echo_probability = 0.03;  // a beam reaching the road before any obstacle
  double rain_probability = 0.0005;       // per beam and layer
  double rain_min_range_m = 1.0;
  double rain_max_range_m = 40.0;

  // The probability that a surface of `reflectivity` met at `cos_incidence` and `range`
  // returns an echo (obstacles' no_echo_probability aside).
  double DetectionProbability(double reflectivity, double cos_incidence, double range) const;

  int beams() const;                   // per layer
  double beam_angle_deg(int i) const;  // horizontal angle of beam i, sensor frame
  // Centre elevation of layer l (0 = lowest) at body pitch 0, degrees.
  double layer_elevation_deg(int l) const;
  // The sensor geometry the engine is told (the log's SENSOR line).
  SensorConfig EngineSensor() const;
  Pose2D mount() const;  // mount as a pose in the vehicle frame
  // Throws std::invalid_argument naming the first bad field.
  void Validate() const;
};

// What produced a point of a simulated scan (for tests and statistics).
enum class EchoSource : std::uint8_t {
  kObstacle,
  kGround,
  kRain,
  kNoEchoRange,     // nothing within range (or the road swallowed the beam)
  kNoEchoWeak,      // an obstacle was met but its echo was too weak (dark, far, glancing)
  kNoEchoAbsorbed,  // an obstacle was met that lets the beam through (glass)
};

class ScanSimulator {
 public:
  // `world` must outlive the simulator.
  ScanSimulator(const ScannerConfig& config, const World& world, std::uint64_t seed);

  // Simulates the scan stamped `t`: movers at their poses at t, the vehicle moving along
  // `trajectory` during the sweep. Fills every beam of every layer into scan->points (no
  // echo: echo = false) and, when given, the source of each point. The scan's pose is left to
  // the caller (odometry).
  void Simulate(double t, const Trajectory& trajectory, Scan* scan,
                std::vector<EchoSource>* sources = nullptr);

  // The body pitch used by the last Simulate(), degrees.
  double last_pitch_deg() const { return pitch_deg_; }

 private:
  ScannerConfig config_;
  const World& world_;
  RayCaster caster_;
  Rng rng_;
  double unevenness_deg_ = 0.0;
  double pitch_deg_ = 0.0;
  std::vector<RayHit> hits_;
};

// The true visibility polygon of one scan: the sensor origin, then for each beam angle the
// first obstacle face met (any height) or the point at max range. Counter-clockwise, world
// metres. `caster` must have its movers placed for the scan's time.
Polygon VisibilityPolygon(RayCaster& caster, const Pose2D& sensor, const ScannerConfig& config);

// The true visibility all around `origin`: for rays every `step_deg` the first obstacle face
// met or the point at `max_range`. Counter-clockwise, world metres.
Polygon SurroundingVisibility(RayCaster& caster, const Vec2& origin, double step_deg,
                              double max_range);

}  // namespace freespace::sim
