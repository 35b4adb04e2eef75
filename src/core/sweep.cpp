// The constant-twist motion of a sensor between two scans, and a point moved by it.
#include "core/sweep.hpp"

#include <cmath>

#include "core/alignment.hpp"

namespace freespace {

bool SweepTracker::Motion(const Pose2D& pose, double t, double max_speed_mps,
                          SweepMotion* motion) const {
  const double dt = t - t_;
  if (!known_ || !(dt > 0.0) || dt > kMaxSweepGapS) return false;
  // A constant twist keeps its velocity in the sensor's own frame, and its chord points along
  // the heading halfway through the turn: the step seen from that heading, over dt.
  const double wx = pose.x - pose_.x, wy = pose.y - pose_.y;
  if (std::hypot(wx, wy) > max_speed_mps * dt) return false;
  const double turn = WrapAngle(pose.yaw - pose_.yaw);
  const double mid = pose_.yaw + 0.5 * turn;
  const double c = std::cos(mid), s = std::sin(mid);
  motion->vx = (c * wx + s * wy) / dt;
  motion->vy = (-s * wx + c * wy) / dt;
  motion->yaw_rate = turn / dt;
  return true;
}

void SweepTracker::Remember(const Pose2D& pose, double t) {
  known_ = true;
  pose_ = pose;
  t_ = t;
}

void SweepPoint(const SweepMotion& m, double tau, float* x, float* y) {
  // The constant twist's pose after tau: turned by a = yaw_rate tau, moved by tau times the
  // velocity turned through the arc, (S vx - C vy, C vx + S vy) with S = sin(a) / a and
  // C = (1 - cos(a)) / a. Small turns by their series (|a| below 0.1 rad: exact to 1e-11).
  const double a = m.yaw_rate * tau, a2 = a * a;
  double c, s, sinc, versc;
  if (std::abs(a) < 0.1) {
    c = 1.0 - a2 * (0.5 - a2 * (1.0 / 24.0 - a2 / 720.0));
    sinc = 1.0 - a2 * (1.0 / 6.0 - a2 * (1.0 / 120.0 - a2 / 5040.0));
    s = a * sinc;
    versc = a * (0.5 - a2 * (1.0 / 24.0 - a2 / 720.0));
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
