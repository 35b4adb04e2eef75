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

}  // namespace freespace
