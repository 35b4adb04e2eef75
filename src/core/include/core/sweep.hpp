// The sensor's motion during one scan (sensor.sweep_s, not in the paper): a scanning sensor
// takes its beams one after the other while the vehicle moves, so a point is placed from where
// the sensor was when that beam was taken, not from the scan's single pose. The motion is the
// constant twist between the sensor's last accepted pose and this scan's (docs/design.md).
#pragma once

#include <cmath>

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
// Inline: Deskew() calls it for every point of a scan.
inline void SweepPoint(const SweepMotion& m, double tau, float* x, float* y) {
  // The constant twist's pose after tau: turned by a = yaw_rate tau, moved by tau times the
  // velocity turned through the arc, (S vx - C vy, C vx + S vy) with S = sin(a) / a and
  // C = (1 - cos(a)) / a. Small turns by their series (|a| below 0.1 rad: exact to 1e-11).
  const double a = m.yaw_rate * tau, a2 = a * a;
  double c, s, sinc, versc;
  if (std::abs(a) < 0.1) {
    c = 1.0 - a2 * (0.5 - a2 * (1.0 / 24.0 - a2 * (1.0 / 720.0)));
    sinc = 1.0 - a2 * (1.0 / 6.0 - a2 * (1.0 / 120.0 - a2 * (1.0 / 5040.0)));
    s = a * sinc;
    versc = a * (0.5 - a2 * (1.0 / 24.0 - a2 * (1.0 / 720.0)));
  } else {
    c = std::cos(a);
    s = std::sin(a);
    sinc = s / a;
    versc = (1.0 - c) / a;
  }
  const double tx = tau * (sinc * m.vx - versc * m.vy), ty = tau * (versc * m.vx + sinc * m.vy);
  const double px = *x, py = *y;
  *x = float(c * px - s * py + tx);
  *y = float(s * px + c * py + ty);
}

}  // namespace freespace
