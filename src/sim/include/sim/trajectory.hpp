// The simulated vehicle's true motion: legs along line-and-arc paths, forward or reversing,
// each with a speed profile of constant-acceleration pieces, and standstill waits between
// them. Time-continuous and exact: the pose at any time (needed for the scanner's sweep) is
// evaluated in closed form. The pose is the vehicle's reference point (rear axle centre); the
// scanner sits at the mount offset from it.
#pragma once

#include <vector>

#include "freespace/types.hpp"
#include "sim/path.hpp"

namespace freespace::sim {

// The speed (m/s, >= 0, along the direction of travel) at arc length `s` of a leg; between
// two knots the acceleration is constant (v^2 linear in s).
struct SpeedKnot {
  double s = 0.0;
  double speed = 0.0;
};

struct MotionState {
  Pose2D pose;                // vehicle reference point, world
  double speed = 0.0;         // m/s, negative when reversing
  double acceleration = 0.0;  // m/s^2 along the vehicle heading (braking forward is negative)
  double yaw_rate = 0.0;      // rad/s
  double distance = 0.0;      // metres driven since the start (always increasing)
};

class Trajectory {
 public:
  Trajectory() = default;
  // Starts at `start`, moving forward at `speed` (m/s, >= 0).
  explicit Trajectory(const Pose2D& start, double speed = 0.0)
      : end_pose_(start), end_speed_(speed) {}

  // Appends a leg: from the current pose the reference point follows `shape` (pieces of a
  // path starting there, in the direction of travel: the heading when driving forward, the
  // opposite when reversing) with the speed profile `knots` (first knot at s = 0 with the
  // current speed, last knot at the path's length; speeds >= 0, and two consecutive knots not
  // both 0). A change of direction needs standstill. Throws std::invalid_argument.
  void Drive(const std::vector<PathPiece>& shape, const std::vector<SpeedKnot>& knots,
             bool reverse = false);
  // Appends a standstill of `seconds` (needs the vehicle to be stopped).
  void Wait(double seconds);

  double duration() const { return segments_.empty() ? 0.0 : segments_.back().t1; }
  const Pose2D& end_pose() const { return end_pose_; }
  double end_speed() const { return end_speed_; }

  // The state at time t (clamped to [0, duration]).
  MotionState At(double t) const;

 private:
  struct Segment {
    double t0 = 0.0, t1 = 0.0;
    int leg = -1;            // -1: standstill at `rest`
    double s0 = 0.0;         // arc length along the leg at t0
    double v0 = 0.0;         // speed at t0 (>= 0)
    double a = 0.0;          // constant acceleration along the path
    double distance0 = 0.0;  // total distance at t0
    Pose2D rest;
  };
  struct Leg {
    Path path;
    bool reverse = false;
  };
  std::vector<Leg> legs_;
  std::vector<Segment> segments_;
  Pose2D end_pose_;
  double end_speed_ = 0.0;
  bool end_reverse_ = false;
  double distance_ = 0.0;
};

// Arc length needed to change speed from v0 to v1 at constant acceleration magnitude a.
double RampLength(double v0, double v1, double a);

}  // namespace freespace::sim
