// Obstacles, movers and the bucketed ray caster: see world.hpp.
#include "sim/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace freespace::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct KindName {
  ObstacleKind kind;
  const char* name;
};
constexpr KindName kKindNames[] = {
    {ObstacleKind::kBuilding, "building"},
    {ObstacleKind::kWall, "wall"},
    {ObstacleKind::kGuardRail, "guard_rail"},
    {ObstacleKind::kCar, "car"},
    {ObstacleKind::kTruck, "truck"},
    {ObstacleKind::kPedestrian, "pedestrian"},
    {ObstacleKind::kPole, "pole"},
    {ObstacleKind::kTree, "tree"},
    {ObstacleKind::kHedge, "hedge"},
};

}  // namespace

const char* ToString(ObstacleKind kind) {
  for (const KindName& k : kKindNames) {
    if (k.kind == kind) return k.name;
  }
  return "?";
}

ObstacleKind ObstacleKindFromString(const std::string& name) {
  for (const KindName& k : kKindNames) {
    if (name == k.name) return k.kind;
  }
  throw std::invalid_argument("unknown obstacle kind '" + name + "'");
}

Pose2D Track::PoseAt(double t) const {
  Pose2D p = lane.PoseAt(s0 + speed_mps * t);
  if (speed_mps < 0.0) p.yaw = std::remainder(p.yaw + M_PI, 2.0 * M_PI);
  return p;
}

std::vector<Pose2D> World::MoverPoses(double t) const {
  std::vector<Pose2D> poses;
  poses.reserve(tracks.size());
  for (const Track& track : tracks) poses.push_back(track.PoseAt(t));
  return poses;
}

std::vector<Polygon> World::Place(const std::vector<Pose2D>& mover_poses) const {
  std::vector<Polygon> out;
  out.reserve(obstacles.size());
  for (const Obstacle& o : obstacles) {
    out.push_back(o.mover < 0 ? o.shape : Transform(mover_poses.at(o.mover), o.shape));
  }
  return out;
}

std::vector<std::vector<Vec2>> World::Outlines(const std::vector<Pose2D>& mover_poses) const {
  std::vector<std::vector<Vec2>> out = Place(mover_poses);
  for (std::vector<Vec2>& line : out) {
    if (!line.empty()) line.push_back(line.front());
  }
  return out;
}

RayCaster::RayCaster(const World& world, double bucket_m) : world_(world), bucket_m_(bucket_m) {
  double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  for (std::size_t i = 0; i < world.obstacles.size(); ++i) {
    const Obstacle& o = world.obstacles[i];
    if (o.mover >= 0) continue;
    AddEdges(int(i), o.shape, &static_edges_);
    for (const Vec2& p : o.shape) {
      x0 = std::min(x0, p.x());
      y0 = std::min(y0, p.y());
      x1 = std::max(x1, p.x());
      y1 = std::max(y1, p.y());
    }
  }
  if (static_edges_.empty()) return;
  grid_origin_ = Vec2(x0 - 1.0, y0 - 1.0);
  cols_ = int(std::ceil((x1 + 1.0 - grid_origin_.x()) / bucket_m_));
  rows_ = int(std::ceil((y1 + 1.0 - grid_origin_.y()) / bucket_m_));
  buckets_.assign(std::size_t(cols_) * rows_, {});
  for (std::size_t e = 0; e < static_edges_.size(); ++e) {
    const Edge& edge = static_edges_[e];
    const int c0 = int((std::min(edge.a.x(), edge.b.x()) - grid_origin_.x()) / bucket_m_);
    const int c1 = int((std::max(edge.a.x(), edge.b.x()) - grid_origin_.x()) / bucket_m_);
    const int r0 = int((std::min(edge.a.y(), edge.b.y()) - grid_origin_.y()) / bucket_m_);
    const int r1 = int((std::max(edge.a.y(), edge.b.y()) - grid_origin_.y()) / bucket_m_);
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) buckets_[std::size_t(r) * cols_ + c].push_back(int(e));
    }
  }
  stamp_.assign(static_edges_.size(), -1);
}

void RayCaster::AddEdges(int obstacle, const Polygon& outline, std::vector<Edge>* edges) const {
  const std::size_t n = outline.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = outline[i];
    const Vec2& b = outline[(i + 1) % n];
    const Vec2 d = b - a;
    const double length = d.norm();
    if (length <= 0.0) continue;
    edges->push_back({a, b, Vec2(d.y(), -d.x()) / length, obstacle});
  }
}

void RayCaster::PlaceMovers(const std::vector<Pose2D>& mover_poses) {
  moving_edges_.clear();
  for (std::size_t i = 0; i < world_.obstacles.size(); ++i) {
    const Obstacle& o = world_.obstacles[i];
    if (o.mover < 0) continue;
    AddEdges(int(i), Transform(mover_poses.at(o.mover), o.shape), &moving_edges_);
  }
}

void RayCaster::TestEdge(const Edge& e, int, const Vec2& origin, const Vec2& dir, double max_range,
                         std::vector<RayHit>* hits) {
  const double facing = dir.dot(e.normal);
  if (facing >= 0.0) return;  // a back face: the ray leaves the obstacle there
  const double t = RaySegment(origin, dir, e.a, e.b);
  if (t < 0.0 || t > max_range) return;
  hits->push_back({t, e.obstacle, -facing});
}

void RayCaster::Cast(const Vec2& origin, const Vec2& dir, double max_range,
                     std::vector<RayHit>* hits) {
  hits->clear();
  for (std::size_t e = 0; e < moving_edges_.size(); ++e) {
    TestEdge(moving_edges_[e], int(e), origin, dir, max_range, hits);
  }
  if (cols_ > 0) {
    ++ray_;
    // Clip the ray to the grid's box (slab method), then walk the buckets it crosses.
    const double gx1 = grid_origin_.x() + cols_ * bucket_m_;
    const double gy1 = grid_origin_.y() + rows_ * bucket_m_;
    double t0 = 0.0, t1 = max_range;
    const double lo[2] = {grid_origin_.x(), grid_origin_.y()}, hi[2] = {gx1, gy1};
    const double o[2] = {origin.x(), origin.y()}, d[2] = {dir.x(), dir.y()};
    for (int k = 0; k < 2 && t0 <= t1; ++k) {
      if (d[k] == 0.0) {
        if (o[k] < lo[k] || o[k] > hi[k]) t1 = -1.0;
        continue;
      }
      double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
    if (t0 <= t1) {
      const Vec2 p = origin + dir * t0;
      int c = std::clamp(int(std::floor((p.x() - grid_origin_.x()) / bucket_m_)), 0, cols_ - 1);
      int r = std::clamp(int(std::floor((p.y() - grid_origin_.y()) / bucket_m_)), 0, rows_ - 1);
      const int step_c = dir.x() > 0 ? 1 : -1, step_r = dir.y() > 0 ? 1 : -1;
      double next_c =
          dir.x() != 0.0
              ? (grid_origin_.x() + (c + (step_c > 0)) * bucket_m_ - origin.x()) / dir.x()
              : kInf;
      double next_r =
          dir.y() != 0.0
              ? (grid_origin_.y() + (r + (step_r > 0)) * bucket_m_ - origin.y()) / dir.y()
              : kInf;
      const double delta_c = dir.x() != 0.0 ? bucket_m_ / std::abs(dir.x()) : kInf;
      const double delta_r = dir.y() != 0.0 ? bucket_m_ / std::abs(dir.y()) : kInf;
      while (true) {
        for (const int e : buckets_[std::size_t(r) * cols_ + c]) {
          if (stamp_[e] == ray_) continue;
          stamp_[e] = ray_;
          TestEdge(static_edges_[e], e, origin, dir, max_range, hits);
        }
        if (std::min(next_c, next_r) > t1) break;
        if (next_c < next_r) {
          c += step_c;
          next_c += delta_c;
          if (c < 0 || c >= cols_) break;
        } else {
          r += step_r;
          next_r += delta_r;
          if (r < 0 || r >= rows_) break;
        }
      }
    }
  }
  std::sort(hits->begin(), hits->end(), [](const RayHit& a, const RayHit& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.obstacle < b.obstacle);
  });
}

double RayCaster::FirstHit(const Vec2& origin, const Vec2& dir, double max_range) {
  std::vector<RayHit>& hits = scratch_;
  Cast(origin, dir, max_range, &hits);
  return hits.empty() ? max_range : hits.front().distance;
}

}  // namespace freespace::sim
