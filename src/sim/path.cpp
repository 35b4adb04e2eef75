// Lines and arcs by arc length: see path.hpp.
#include "sim/path.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace freespace::sim {

Pose2D Advance(const Pose2D& pose, double curvature, double s) {
  const double c0 = std::cos(pose.yaw), s0 = std::sin(pose.yaw);
  if (std::abs(curvature * s) < 1e-9) {
    return {pose.x + c0 * s, pose.y + s0 * s, pose.yaw + curvature * s};
  }
  const double yaw = pose.yaw + curvature * s;
  return {pose.x + (std::sin(yaw) - s0) / curvature, pose.y - (std::cos(yaw) - c0) / curvature,
          yaw};
}

Path& Path::Straight(double length) { return Append({length, 0.0}); }

Path& Path::Arc(double radius, double angle_rad) {
  if (!(radius > 0.0)) throw std::invalid_argument("Path::Arc: radius must be > 0");
  return Append({radius * std::abs(angle_rad), (angle_rad >= 0.0 ? 1.0 : -1.0) / radius});
}

Path& Path::Append(const PathPiece& piece) {
  if (!(piece.length > 0.0)) throw std::invalid_argument("Path: a piece needs a length > 0");
  const Pose2D begin = pieces_.empty() ? start_
                                       : Advance(piece_start_.back(), pieces_.back().curvature,
                                                 pieces_.back().length);
  pieces_.push_back(piece);
  piece_start_.push_back(begin);
  ends_.push_back(length() + piece.length);
  return *this;
}

Pose2D Path::PoseAt(double s) const {
  if (pieces_.empty()) return start_;
  s = std::clamp(s, 0.0, length());
  const std::size_t i = std::min<std::size_t>(
      std::lower_bound(ends_.begin(), ends_.end(), s) - ends_.begin(), pieces_.size() - 1);
  const double begin = i == 0 ? 0.0 : ends_[i - 1];
  return Advance(piece_start_[i], pieces_[i].curvature, s - begin);
}

Vec2 Path::PointAt(double s, double lateral) const {
  const Pose2D p = PoseAt(s);
  return {p.x - std::sin(p.yaw) * lateral, p.y + std::cos(p.yaw) * lateral};
}

Path Path::Offset(double lateral) const {
  const Vec2 origin = PointAt(0.0, lateral);
  Path out(Pose2D{origin.x(), origin.y(), start_.yaw});
  for (const PathPiece& p : pieces_) {
    const double scale = 1.0 - p.curvature * lateral;  // radius (1/k - d) over radius 1/k
    if (!(scale > 0.0)) {
      throw std::invalid_argument("Path::Offset: offset " + std::to_string(lateral) +
                                  " m crosses an arc's centre");
    }
    out.Append({p.length * scale, p.curvature / scale});
  }
  return out;
}

}  // namespace freespace::sim
