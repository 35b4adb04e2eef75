// One full scan of a multi-layer laser scanner, as the estimator consumes it.
#pragma once

#include <cstdint>
#include <vector>

#include "freespace/types.hpp"

namespace freespace {

// One beam of one layer. Angle is horizontal, in the sensor frame (x forward, y left),
// radians, counter-clockwise. A beam without an echo keeps its angle; its range is ignored.
struct ScanPoint {
  std::uint8_t layer = 0;
  bool echo = true;
  float angle_rad = 0.0f;
  float range_m = 0.0f;
};

// A full scan: every layer's beams, the time it was taken and the vehicle's odometry pose in
// world coordinates at that time. The sensor pose is this pose composed with the configured
// mount offset (sensor.mount_*).
struct Scan {
  double timestamp_s = 0.0;
  Pose2D pose;
  std::vector<ScanPoint> points;
};

}  // namespace freespace
