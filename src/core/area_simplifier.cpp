// Bottom-up simplification by least area given up, on a linked ring with a heap of drops; a
// drop changes its two neighbours' costs, which are pushed again (the old entries go stale).
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

// The heap's order: the cheapest drop on top, of equal ones the lowest vertex's (a functor, so
// that the heap's steps inline it).
struct Later {
  template <class D>
  bool operator()(const D& a, const D& b) const {
    return a.cost > b.cost || (a.cost == b.cost && a.vertex > b.vertex);
  }
};

}  // namespace

AreaSimplifier::AreaSimplifier(int max_vertices, double epsilon, double inward_weight, int capacity)
    : max_vertices_(std::max(max_vertices, 3)),
      epsilon_(epsilon),
      inward_weight_(inward_weight),
      prev_(std::size_t(capacity)),
      next_(std::size_t(capacity)),
      stamp_(std::size_t(capacity)),
      deviation_(std::size_t(capacity)),
      dropped_(std::size_t(capacity)) {
  heap_.reserve(3 * std::size_t(capacity) + 3);  // each vertex once, then two per drop
}

AreaSimplifier::Drop AreaSimplifier::Cost(const std::vector<Vec2>& ring, const Vec2& centre,
                                          int v) const {
  const int before = prev_[std::size_t(v)];
  const Vec2& u = ring[std::size_t(before)];
  const Vec2& w = ring[std::size_t(next_[std::size_t(v)])];
  const Vec2& p = ring[std::size_t(v)];
  Drop drop{kNever, kNever, kNever, v, stamp_[std::size_t(v)]};
  const auto at_centre = [&](const Vec2& q) { return (q - centre).squaredNorm() <= 1e-18; };
  // A vertex at the centre stays; the new edge u -> w must pass the centre on its left, or end
  // at it.
  if (at_centre(p)) return drop;
  if (!at_centre(u) && !at_centre(w) && Cross(w - u, centre - u) <= kAreaTolerance) return drop;
  const double twice = Cross(w - u, p - u);  // > 0: p is left of the new edge, a reflex vertex
  const double weight = twice > 0.0 ? inward_weight_ : 1.0;
  drop.cost = weight * 0.5 * std::abs(twice);
  // The vertices under u -> v and v -> w lie within their bounds of those edges, whose points
  // lie within p's distance of u -> w (the farthest is an end): the sum bounds them all.
  drop.deviation = std::max(deviation_[std::size_t(before)], deviation_[std::size_t(v)]) +
                   DistanceToSegment(p, u, w);
  drop.distance = weight * drop.deviation;
  return drop;
}

void AreaSimplifier::Push(const Drop& drop) {
  heap_.push_back(drop);
  std::push_heap(heap_.begin(), heap_.end(), Later());
}

bool AreaSimplifier::Pop(Drop* drop) {
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), Later());
    *drop = heap_.back();
    heap_.pop_back();
    const std::size_t v = std::size_t(drop->vertex);
    if (!dropped_[v] && drop->stamp == stamp_[v]) return true;
  }
  return false;
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
  heap_.clear();
  for (int i = 0; i < n; ++i) {
    prev_[std::size_t(i)] = i > 0 ? i - 1 : n - 1;
    next_[std::size_t(i)] = i + 1 < n ? i + 1 : 0;
    stamp_[std::size_t(i)] = 0;
    deviation_[std::size_t(i)] = 0.0;
    dropped_[std::size_t(i)] = 0;
  }
  for (int i = 0; i < n; ++i) heap_.push_back(Cost(ring, centre, i));
  std::make_heap(heap_.begin(), heap_.end(), Later());
  int count = n;
  Drop drop;
  while (count > 3 && Pop(&drop)) {
    if (drop.cost == kNever) break;
    if (count <= max_vertices_ && drop.distance > epsilon_) break;
    const int v = drop.vertex, u = prev_[std::size_t(v)], w = next_[std::size_t(v)];
    dropped_[std::size_t(v)] = 1;
    next_[std::size_t(u)] = w;
    prev_[std::size_t(w)] = u;
    deviation_[std::size_t(u)] = drop.deviation;
    --count;
    for (const int k : {u, w}) {
      ++stamp_[std::size_t(k)];
      Push(Cost(ring, centre, k));
    }
  }
  if (count > max_vertices_) return -1.0;
  for (int i = 0; i < n; ++i) {
    if (!dropped_[std::size_t(i)]) kept->push_back(i);
  }
  // The largest distance of a dropped vertex from the kept edge over it.
  double error = 0.0;
  const int m = int(kept->size());
  for (int k = 0; k < m; ++k) {
    const int a = (*kept)[std::size_t(k)], b = (*kept)[std::size_t(k + 1 < m ? k + 1 : 0)];
    for (int i = a + 1 < n ? a + 1 : 0; i != b; i = i + 1 < n ? i + 1 : 0) {
      error = std::max(error, DistanceToSegment(ring[std::size_t(i)], ring[std::size_t(a)],
                                                ring[std::size_t(b)]));
    }
  }
  return error;
}

}  // namespace freespace
