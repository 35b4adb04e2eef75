// Bottom-up simplification by least area given up, on a linked ring with a tournament tree of its
// vertices' drops (core/min_tree.hpp): a drop changes its two neighbours' costs, which the tree
// takes in place.
#include "core/area_simplifier.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/fan_pull.hpp"
#include "core/simplifier.hpp"

namespace freespace {
namespace {

// The conservative polygon's own cross product and area tolerance, where its edges are pulled
// inside the ring: a new edge the pull would not check is not made.
using fan::Cross;
using fan::kAreaTolerance;

constexpr double kNever = std::numeric_limits<double>::infinity();

}  // namespace

AreaSimplifier::AreaSimplifier(int max_vertices, double epsilon, double inward_weight, int capacity)
    : max_vertices_(std::max(max_vertices, 3)),
      epsilon_(epsilon),
      inward_weight_(inward_weight),
      prev_(std::size_t(capacity)),
      next_(std::size_t(capacity)),
      tree_(capacity),
      dropped_(std::size_t(capacity)),
      at_centre_(std::size_t(capacity)),
      cost_(std::size_t(capacity)),
      deviation_(std::size_t(capacity)) {}

double AreaSimplifier::Cost(const std::vector<Vec2>& ring, const Vec2& centre, int v) const {
  const std::size_t before = std::size_t(prev_[std::size_t(v)]);
  const std::size_t after = std::size_t(next_[std::size_t(v)]);
  const Vec2& u = ring[before];
  const Vec2& w = ring[after];
  const Vec2& p = ring[std::size_t(v)];
  // A vertex at the centre stays; the new edge u -> w must pass the centre on its left, or end
  // at it.
  if (at_centre_[std::size_t(v)]) return kNever;
  if (!at_centre_[before] && !at_centre_[after] && Cross(w - u, centre - u) <= kAreaTolerance)
    return kNever;
  const double twice = Cross(w - u, p - u);
  return Weight(twice) * 0.5 * std::abs(twice);
}

double AreaSimplifier::Deviation(const std::vector<Vec2>& ring, int v) const {
  const int before = prev_[std::size_t(v)];
  // The vertices under u -> v and v -> w lie within their bounds of those edges, whose points
  // lie within p's distance of u -> w (the farthest is an end): the sum bounds them all.
  return std::max(deviation_[std::size_t(before)], deviation_[std::size_t(v)]) +
         DistanceToSegment(ring[std::size_t(v)], ring[std::size_t(before)],
                           ring[std::size_t(next_[std::size_t(v)])]);
}

double AreaSimplifier::Simplify(const std::vector<Vec2>& ring, const Vec2& centre,
                                std::vector<int>* kept) {
  kept->clear();
  const int n = int(ring.size());
  if (n > int(prev_.size())) return -1.0;
  if (n <= 3) {
    for (int i = 0; i < n; ++i) kept->push_back(i);
    return 0.0;
  }
  for (int i = 0; i < n; ++i) {
    prev_[std::size_t(i)] = i > 0 ? i - 1 : n - 1;
    next_[std::size_t(i)] = i + 1 < n ? i + 1 : 0;
    deviation_[std::size_t(i)] = 0.0;
    dropped_[std::size_t(i)] = 0;
    at_centre_[std::size_t(i)] = (ring[std::size_t(i)] - centre).squaredNorm() <= 1e-18;
  }
  for (int i = 0; i < n; ++i) cost_[std::size_t(i)] = Cost(ring, centre, i);
  // The cheapest drop first, of equal ones the lowest vertex's.
  tree_.Fill(cost_.data(), n);
  int count = n;
  while (count > 3 && tree_.top_key() != kNever) {
    const int v = tree_.top(), u = prev_[std::size_t(v)], w = next_[std::size_t(v)];
    // The bound is worked out only for the drop taken. It is the one v's cost had: a drop
    // changes only its neighbours' links and the bound of the edge from u, and both neighbours
    // are costed anew at once, so v's inputs are as at its cost's.
    const double deviation = Deviation(ring, v);
    const Vec2& a = ring[std::size_t(u)];
    const double twice = Cross(ring[std::size_t(w)] - a, ring[std::size_t(v)] - a);
    if (count <= max_vertices_ && Weight(twice) * deviation > epsilon_) break;
    tree_.Set(v, MinTree::kNone);
    dropped_[std::size_t(v)] = 1;
    next_[std::size_t(u)] = w;
    prev_[std::size_t(w)] = u;
    deviation_[std::size_t(u)] = deviation;
    --count;
    for (const int k : {u, w}) {
      cost_[std::size_t(k)] = Cost(ring, centre, k);
      tree_.Set(k, cost_[std::size_t(k)]);
    }
  }
  if (count > max_vertices_) return -1.0;
  for (int i = 0; i < n; ++i) {
    if (!dropped_[std::size_t(i)]) kept->push_back(i);
  }
  return KeptError(ring, *kept);
}

// The largest distance of a dropped vertex from the kept edge over it: the root of the largest
// square, which is the same number.
double AreaSimplifier::KeptError(const std::vector<Vec2>& ring, const std::vector<int>& kept) {
  const int n = int(ring.size()), m = int(kept.size());
  double error = 0.0;
  for (int k = 0; k < m; ++k) {
    const int a = kept[std::size_t(k)], b = kept[std::size_t(k + 1 < m ? k + 1 : 0)];
    for (int i = a + 1 < n ? a + 1 : 0; i != b; i = i + 1 < n ? i + 1 : 0) {
      error = std::max(error, SquaredDistanceToSegment(ring[std::size_t(i)], ring[std::size_t(a)],
                                                       ring[std::size_t(b)]));
    }
  }
  return std::sqrt(error);
}

}  // namespace freespace
