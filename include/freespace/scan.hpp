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
// mount offset (sensor.mount_*, or the mount of its sensor in a rig).
struct Scan {
  double timestamp_s = 0.0;  // |t| <= kMaxTimestampS, else the scan is rejected
  Pose2D pose;               // |x|, |y| <= kMaxCoordinateM, else the scan is rejected
  std::vector<ScanPoint> points;
  // Which sensor of a rig took it (index into Config::sensors); 0 for a single sensor.
  int sensor = 0;
};

// The largest timestamp magnitude the estimator takes (s): Unix time in seconds until the
// year 2286. Larger values are almost always another unit (milli- or nanoseconds), and past
// about 1e12 s a double no longer resolves a scan period to the microsecond.
inline constexpr double kMaxTimestampS = 1e10;
// The largest world coordinate magnitude the estimator takes (m): 100,000 km, beyond any
// Earth-fixed frame (UTM northings, ECEF) yet small enough that a double resolves it to 15 nm
// and the map's origin stays an exact integer count of cells.
inline constexpr double kMaxCoordinateM = 1e8;

}  // namespace freespace
