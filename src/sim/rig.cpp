// The simulator's rigs: see rig.hpp.
#include "sim/rig.hpp"

#include <stdexcept>

namespace freespace::sim {
namespace {

// The car of the scenarios: reference point of its odometry the rear axle centre, front bumper
// 3.7 m ahead (ScannerConfig's default mount), rear bumper 1.0 m behind, 1.8 m wide.
constexpr double kFrontX = 3.7;
constexpr double kRearX = -1.0;
constexpr double kHalfWidth = 0.9;

struct Corner {
  const char* name;
  double x, y, yaw_deg;
};

constexpr Corner kSurround[] = {
    {"front_left", kFrontX, kHalfWidth, 45.0},
    {"front_right", kFrontX, -kHalfWidth, -45.0},
    {"rear_left", kRearX, kHalfWidth, 135.0},
    {"rear_right", kRearX, -kHalfWidth, -135.0},
};

}  // namespace

geometry::Polygon VehicleBody(double clearance_m) {
  const double x0 = kRearX - clearance_m, x1 = kFrontX + clearance_m;
  const double y = kHalfWidth + clearance_m;
  return {Vec2(x0, -y), Vec2(x1, -y), Vec2(x1, y), Vec2(x0, y)};
}

const std::vector<std::string>& RigNames() {
  static const std::vector<std::string> names = {"front", "surround"};
  return names;
}

Rig MakeRig(const std::string& name, const ScannerConfig& scanner) {
  Rig rig;
  rig.name = name;
  if (name == "front") {
    rig.sensor_names = {"front"};
    rig.scanners = {scanner};
    return rig;
  }
  if (name != "surround") {
    throw std::invalid_argument("unknown rig '" + name + "' (front, surround)");
  }
  for (const Corner& c : kSurround) {
    ScannerConfig s = scanner;
    s.mount_x_m = c.x;
    s.mount_y_m = c.y;
    s.mount_yaw_deg = c.yaw_deg;
    rig.sensor_names.push_back(c.name);
    rig.scanners.push_back(s);
  }
  rig.vehicle.reference_x_m = 0.5 * (kFrontX + kRearX);
  rig.vehicle.reference_y_m = 0.0;
  rig.vehicle.footprint_length_m = kFrontX - kRearX;
  rig.vehicle.footprint_width_m = 2.0 * kHalfWidth;
  return rig;
}

Config WithRig(Config config, const Rig& rig) {
  if (!rig.several()) {
    config.sensor = rig.scanners.front().EngineSensor();
    config.sensors.clear();
    return config;
  }
  config.sensors.clear();
  for (std::size_t i = 0; i < rig.scanners.size(); ++i) {
    SensorConfig s = rig.scanners[i].EngineSensor();
    s.name = rig.sensor_names[i];
    config.sensors.push_back(s);
  }
  config.rig = rig.vehicle;
  return config;
}

std::vector<SensorConfig> EngineSensors(const Rig& rig) {
  const Config config = WithRig(Config(), rig);
  return config.is_rig() ? config.sensors : std::vector<SensorConfig>{config.sensor};
}

}  // namespace freespace::sim
