// The sensor's motion during one scan (sensor.sweep_s, not in the paper): a scanning sensor
// takes its beams one after the other while the vehicle moves, so a point is placed from where
// the sensor was when that beam was taken, not from the scan's single pose. The motion is the
// constant twist between the sensor's last accepted pose and this scan's (docs/design.md).
#pragma once

#include "freespace/types.hpp"

namespace freespace {

// Beyond this many seconds between two scans of a sensor their poses say too little about the
// motion during the later one: it is placed as the paper places it, at one pose.
inline constexpr double kMaxSweepGapS = 0.5;

// The sensor's velocity (m/s, in its own frame at the scan's timestamp) and yaw rate (rad/s).
struct SweepMotion {
  double vx = 0.0;
  double vy = 0.0;
  double yaw_rate = 0.0;
};

// One sensor's last accepted pose and time.
class SweepTracker {
 public:
  // The constant twist from the remembered pose to `pose` at `t`. False when there is none to
  // give: nothing remembered, t not after the remembered time or more than kMaxSweepGapS after
  // it, or a speed above max_speed_mps (a jump of the odometry).
  bool Motion(const Pose2D& pose, double t, double max_speed_mps, SweepMotion* motion) const;
  void Remember(const Pose2D& pose, double t);
  void Forget() { known_ = false; }

 private:
  bool known_ = false;
  Pose2D pose_;
  double t_ = 0.0;
};

// Where a point taken `tau` seconds after the scan's timestamp lies in the sensor frame at the
// timestamp: the sensor moved along the constant twist `m` for tau seconds meanwhile.
void SweepPoint(const SweepMotion& m, double tau, float* x, float* y);

}  // namespace freespace
