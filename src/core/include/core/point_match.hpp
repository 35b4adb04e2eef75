// Matching two sets of 2-D points (the mover layer's observations of one object at two times):
// nearest neighbours on a grid, and a translation-only registration.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "freespace/types.hpp"

namespace freespace {

// The points of a set by 1 m grid cell, for nearest-neighbour queries within 1 m.
class PointGrid {
 public:
  static constexpr double kCellM = 1.0;

  explicit PointGrid(const std::vector<Vec2>& points);

  // The nearest point within `radius` (<= kCellM) of q, or null.
  const Vec2* Nearest(const Vec2& q, double radius) const;

 private:
  static std::int64_t Key(double x, double y);

  const std::vector<Vec2>& points_;
  std::vector<std::pair<std::int64_t, std::uint32_t>> cells_;  // (cell key, index), sorted
};

// The share of `b`'s points that lie within `radius` of a point of `grid` once moved back by
// `shift`.
double MatchedShare(const PointGrid& grid, const std::vector<Vec2>& b, const Vec2& shift,
                    double radius);

// The shift s that lays point set a (its grid) on b, from `guess`: a few rounds of matching each
// point of b to the nearest point of a moved by s within 1 m and moving s by their mean offset.
// `near`: the pairs lie within 0.3 m of their matches on average; `fits`: and at least 60 % of
// b's points are paired.
struct Fit {
  Vec2 shift = Vec2::Zero();
  int pairs = 0;
  bool near = false;
  bool fits = false;
};
Fit Registered(const PointGrid& a, const std::vector<Vec2>& b, Vec2 guess);

}  // namespace freespace
