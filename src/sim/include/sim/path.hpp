// Planar paths made of straight lines and circular arcs, parametrised by arc length: the road
// reference lines and lanes of the scenarios, and the way the simulated vehicle travels.
#pragma once

#include <vector>

#include "freespace/types.hpp"

namespace freespace::sim {

// One piece of a path: `length` metres at constant curvature (1/m, positive turning left).
struct PathPiece {
  double length = 0.0;
  double curvature = 0.0;
};

class Path {
 public:
  Path() = default;
  explicit Path(const Pose2D& start) : start_(start) {}

  // Appends a straight line; length > 0.
  Path& Straight(double length);
  // Appends an arc of `radius` (> 0) turning by `angle_rad` (positive left, negative right).
  Path& Arc(double radius, double angle_rad);
  Path& Append(const PathPiece& piece);

  const Pose2D& start() const { return start_; }
  const std::vector<PathPiece>& pieces() const { return pieces_; }
  double length() const { return ends_.empty() ? 0.0 : ends_.back(); }

  // The pose at arc length `s` (clamped to [0, length]); yaw is the tangent.
  Pose2D PoseAt(double s) const;
  // The point `lateral` metres left of the path (right when negative) at arc length `s`.
  Vec2 PointAt(double s, double lateral) const;
  // The parallel path `lateral` metres to the left: arcs keep their centres, so a lane of a
  // curved road is again lines and arcs. Throws std::invalid_argument when an arc's radius is
  // not larger than the offset on its inner side.
  Path Offset(double lateral) const;

 private:
  Pose2D start_;
  std::vector<PathPiece> pieces_;
  std::vector<Pose2D> piece_start_;  // pose where each piece begins
  std::vector<double> ends_;         // cumulative arc length at the end of each piece
};

// Moves `pose` by `s` metres along a piece of constant `curvature` (exact for lines and arcs).
Pose2D Advance(const Pose2D& pose, double curvature, double s);

}  // namespace freespace::sim
