// Point set matching for the mover layer: see point_match.hpp.
#include "core/point_match.hpp"

#include <algorithm>
#include <cmath>

namespace freespace {

PointGrid::PointGrid(const std::vector<Vec2>& points) : points_(points) {
  cells_.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    cells_.emplace_back(Key(points[i].x(), points[i].y()), std::uint32_t(i));
  std::sort(cells_.begin(), cells_.end());
}

std::int64_t PointGrid::Key(double x, double y) {
  return (std::int64_t(std::floor(x / kCellM)) + (1 << 20)) * (std::int64_t(1) << 21) +
         (std::int64_t(std::floor(y / kCellM)) + (1 << 20));
}

const Vec2* PointGrid::Nearest(const Vec2& q, double radius) const {
  double best = radius * radius;
  const Vec2* match = nullptr;
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      const std::int64_t k = Key(q.x() + dx * kCellM, q.y() + dy * kCellM);
      auto it = std::lower_bound(cells_.begin(), cells_.end(), std::make_pair(k, std::uint32_t(0)));
      for (; it != cells_.end() && it->first == k; ++it) {
        const double d = (points_[it->second] - q).squaredNorm();
        if (d < best) {
          best = d;
          match = &points_[it->second];
        }
      }
    }
  }
  return match;
}

double MatchedShare(const PointGrid& grid, const std::vector<Vec2>& b, const Vec2& shift,
                    double radius) {
  if (b.empty()) return 0.0;
  int matched = 0;
  for (const Vec2& p : b) matched += grid.Nearest(p - shift, radius) != nullptr;
  return double(matched) / double(b.size());
}

Fit Registered(const PointGrid& a, const std::vector<Vec2>& b, Vec2 guess) {
  constexpr double kMatchM = 1.0, kMinShare = 0.6, kFitM = 0.3;
  constexpr int kRounds = 4, kMinPairs = 5;
  Vec2 s = guess;
  double residual = 0.0;
  int pairs = 0;
  for (int round = 0; round < kRounds; ++round) {
    Vec2 sum = Vec2::Zero();
    residual = 0.0;
    pairs = 0;
    for (const Vec2& p : b) {
      const Vec2* match = a.Nearest(p - s, kMatchM);  // where p was in a
      if (match == nullptr) continue;
      sum += p - *match;
      residual += (p - s - *match).squaredNorm();
      ++pairs;
    }
    if (pairs < kMinPairs) return {};
    s = sum / double(pairs);
  }
  const bool near = residual <= kFitM * kFitM * pairs;
  return {s, pairs, near, near && pairs >= kMinShare * double(b.size())};
}

}  // namespace freespace
