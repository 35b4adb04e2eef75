// The scanner rigs of the simulator: "front", one ScaLa-like scanner on the front bumper (the
// paper's setup), and "surround", four at the corners of the car looking out diagonally, 360 deg
// around it. A rig also says which point of the vehicle the estimator centres its work on and
// the vehicle's footprint (Config::rig).
#pragma once

#include <string>
#include <vector>

#include "freespace/config.hpp"
#include "geometry/geometry.hpp"
#include "sim/scanner.hpp"

namespace freespace::sim {

struct Rig {
  std::string name = "front";
  std::vector<std::string> sensor_names;
  std::vector<ScannerConfig> scanners;  // one for "front"
  RigConfig vehicle;                    // reference point and footprint (surround)

  bool several() const { return scanners.size() > 1; }
};

// The simulated car's body in its own frame (rear axle centre, x forward): the front bumper
// 3.7 m ahead, the rear one 1.0 m behind, 1.8 m wide; grown by `clearance_m` on every side.
// Counter-clockwise.
geometry::Polygon VehicleBody(double clearance_m = 0.0);

// The rig names MakeRig() knows.
const std::vector<std::string>& RigNames();

// Rig `name` built from `scanner` (its sensor model; the mounts are the rig's). "front" is
// `scanner` as it is. Throws std::invalid_argument for an unknown name.
Rig MakeRig(const std::string& name, const ScannerConfig& scanner);

// `config` with the rig's sensors (each the engine's view of its scanner) and vehicle; "front"
// sets `config.sensor` alone.
Config WithRig(Config config, const Rig& rig);

// The engine's view of the rig's scanners (WithRig's sensors, or its one sensor).
std::vector<SensorConfig> EngineSensors(const Rig& rig);

}  // namespace freespace::sim
