// Legs, speed knots and waits: see trajectory.hpp.
#include "sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace freespace::sim {

double RampLength(double v0, double v1, double a) { return std::abs(v1 * v1 - v0 * v0) / (2 * a); }

void Trajectory::Drive(const std::vector<PathPiece>& shape, const std::vector<SpeedKnot>& knots,
                       bool reverse) {
  if (shape.empty()) throw std::invalid_argument("Trajectory::Drive: empty shape");
  if (knots.size() < 2) throw std::invalid_argument("Trajectory::Drive: needs two speed knots");
  if (reverse != end_reverse_ && end_speed_ != 0.0) {
    throw std::invalid_argument("Trajectory::Drive: a change of direction needs standstill");
  }
  if (std::abs(knots.front().s) > 1e-9 || std::abs(knots.front().speed - end_speed_) > 1e-9) {
    throw std::invalid_argument(
        "Trajectory::Drive: the first knot must be s = 0 at the current "
        "speed");
  }
  Pose2D travel = end_pose_;
  if (reverse) travel.yaw += M_PI;
  Path path(travel);
  for (const PathPiece& p : shape) path.Append(p);
  if (std::abs(knots.back().s - path.length()) > 1e-6) {
    throw std::invalid_argument("Trajectory::Drive: the last knot must be at the path's end");
  }
  const int leg = int(legs_.size());
  legs_.push_back({path, reverse});

  double t = duration();
  for (std::size_t i = 0; i + 1 < knots.size(); ++i) {
    const SpeedKnot& k0 = knots[i];
    const SpeedKnot& k1 = knots[i + 1];
    const double ds = k1.s - k0.s;
    if (!(ds > 0.0) || k0.speed < 0.0 || k1.speed < 0.0 || !(k0.speed + k1.speed > 0.0)) {
      throw std::invalid_argument(
          "Trajectory::Drive: knots need increasing s, speeds >= 0, not two stops in a row");
    }
    Segment seg;
    seg.t0 = t;
    seg.t1 = t + 2.0 * ds / (k0.speed + k1.speed);
    seg.leg = leg;
    seg.s0 = k0.s;
    seg.v0 = k0.speed;
    seg.a = (k1.speed * k1.speed - k0.speed * k0.speed) / (2.0 * ds);
    seg.distance0 = distance_;
    segments_.push_back(seg);
    distance_ += ds;
    t = seg.t1;
  }
  end_pose_ = path.PoseAt(path.length());
  if (reverse) end_pose_.yaw -= M_PI;
  end_pose_.yaw = std::remainder(end_pose_.yaw, 2.0 * M_PI);
  end_speed_ = knots.back().speed;
  end_reverse_ = reverse;
}

void Trajectory::Wait(double seconds) {
  if (end_speed_ != 0.0) throw std::invalid_argument("Trajectory::Wait: the vehicle is moving");
  if (!(seconds > 0.0)) throw std::invalid_argument("Trajectory::Wait: seconds must be > 0");
  Segment seg;
  seg.t0 = duration();
  seg.t1 = seg.t0 + seconds;
  seg.distance0 = distance_;
  seg.rest = end_pose_;
  segments_.push_back(seg);
}

MotionState Trajectory::At(double t) const {
  MotionState m;
  if (segments_.empty()) {
    m.pose = end_pose_;
    return m;
  }
  t = std::clamp(t, 0.0, duration());
  auto it = std::upper_bound(segments_.begin(), segments_.end(), t,
                             [](double v, const Segment& s) { return v < s.t1; });
  if (it == segments_.end()) --it;
  const Segment& seg = *it;
  const double tau = t - seg.t0;
  m.distance = seg.distance0;
  if (seg.leg < 0) {
    m.pose = seg.rest;
    return m;
  }
  const Leg& leg = legs_[seg.leg];
  const double ds = seg.v0 * tau + 0.5 * seg.a * tau * tau;
  const double v = seg.v0 + seg.a * tau;
  const double s = seg.s0 + ds;
  m.pose = leg.path.PoseAt(s);
  m.distance += ds;
  // Curvature of the piece at s, for the yaw rate.
  double curvature = 0.0, end = 0.0;
  for (const PathPiece& p : leg.path.pieces()) {
    end += p.length;
    curvature = p.curvature;
    if (s <= end) break;
  }
  m.yaw_rate = curvature * v;
  if (leg.reverse) {
    m.pose.yaw += M_PI;
    m.speed = -v;
    m.acceleration = -seg.a;
  } else {
    m.speed = v;
    m.acceleration = seg.a;
  }
  m.pose.yaw = std::remainder(m.pose.yaw, 2.0 * M_PI);
  return m;
}

}  // namespace freespace::sim
