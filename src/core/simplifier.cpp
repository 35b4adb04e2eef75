// Capped Douglas-Peucker on a closed ring. The ring is first cut at vertex 0 and the vertex
// farthest from it; then the segment whose farthest vertex deviates most is split, one vertex
// at a time, until every dropped vertex is within epsilon (the classic stop) or N vertices are
// kept (the paper's added stop). With an inward weight above 1 (the conservative polygon) a
// vertex left of its segment deviates that many times its distance. Segments live in a fixed
// pool, linked in ring order, the next to split on top of a heap: no allocation per call, and
// each split costs the length of the segment it measures plus a logarithm of the count.
#include "core/simplifier.hpp"

#include <algorithm>
#include <cmath>

namespace freespace {

double SquaredDistanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 == 0.0) return (p - a).squaredNorm();
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return (p - (a + t * ab)).squaredNorm();
}

double DistanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  return std::sqrt(SquaredDistanceToSegment(p, a, b));
}

bool PointInPolygon(const std::vector<Vec2>& polygon, const Vec2& p) {
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

PolygonSimplifier::PolygonSimplifier(int max_vertices, double epsilon)
    : max_vertices_(max_vertices),
      epsilon_(epsilon),
      segments_(std::size_t(std::max(max_vertices, 3) + 1)),
      heap_(std::max(max_vertices, 3) + 1) {}

PolygonSimplifier::Segment PolygonSimplifier::Measure(const std::vector<Vec2>& ring, int from,
                                                      int length) const {
  const int n = int(ring.size());
  Segment s;
  s.from = from;
  s.length = length;
  // DistanceToSegment of every vertex strictly between its ends, squared (the order is the same),
  // with the segment's direction and length worked out once.
  const Vec2 a = ring[std::size_t(from)];
  const Vec2 ab = ring[std::size_t((from + length) % n)] - a;
  const double len2 = ab.squaredNorm(), inverse = len2 > 0.0 ? 1.0 / len2 : 0.0;
  double farthest = 0.0, first = -1.0;
  const double inward2 = inward_weight_ * inward_weight_;
  const auto visit = [&](int i) {
    const Vec2 ap = ring[std::size_t(i)] - a;
    const double t = std::clamp(ap.dot(ab) * inverse, 0.0, 1.0);
    const double d2 = (ap - t * ab).squaredNorm();
    const double key = ab.x() * ap.y() - ab.y() * ap.x() > 0.0 ? d2 * inward2 : d2;
    farthest = std::max(farthest, d2);
    if (key > first) {
      first = key;
      s.worst = i;
    }
  };
  const int end = from + length;  // exclusive, may run past the ring's end
  for (int i = from + 1; i < std::min(end, n); ++i) visit(i);
  for (int i = 0; i < end - n; ++i) visit(i);
  if (s.worst >= 0) {
    s.priority = std::sqrt(first);
    s.deviation = std::sqrt(farthest);
  }
  return s;
}

int PolygonSimplifier::Split(const std::vector<Vec2>& ring, int s, int vertex) {
  const int n = int(ring.size());
  Segment& old = segments_[std::size_t(s)];
  const int first = (vertex - old.from + n) % n, rest = old.length - first;
  const int next = old.next, t = used_++;
  old = Measure(ring, old.from, first);
  old.next = t;
  segments_[std::size_t(t)] = Measure(ring, vertex, rest);
  segments_[std::size_t(t)].next = next;
  HeapPlace(s);
  HeapPlace(t);
  return t;
}

bool PolygonSimplifier::Before(int a, int b) const {
  const Segment& x = segments_[std::size_t(a)];
  const Segment& y = segments_[std::size_t(b)];
  return x.priority > y.priority || (x.priority == y.priority && x.from < y.from);
}

void PolygonSimplifier::HeapPlace(int s) {
  const auto before = [this](int a, int b) { return Before(a, b); };
  if (segments_[std::size_t(s)].worst < 0) {
    if (heap_.contains(s)) heap_.Remove(s, before);
  } else if (heap_.contains(s)) {
    heap_.Update(s, before);
  } else {
    heap_.Push(s, before);
  }
}

namespace {

// Signed distance of p from the line a -> b: positive when p is on its left.
double LeftOf(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 ab = b - a;
  const double len = ab.norm();
  if (len == 0.0) return -(p - a).norm();
  return (ab.x() * (p.y() - a.y()) - ab.y() * (p.x() - a.x())) / len;
}

}  // namespace

int PolygonSimplifier::ContainmentSplit(const std::vector<Vec2>& ring, const Vec2& inside,
                                        int first) const {
  const int n = int(ring.size());
  for (int s = first; s >= 0; s = segments_[std::size_t(s)].next) {
    const Segment& g = segments_[std::size_t(s)];
    if (g.worst < 0) continue;
    const Vec2& a = ring[g.from];
    const int to = g.from + g.length;
    const Vec2& b = ring[to < n ? to : to - n];
    // A ring through `inside` itself (a ray of the conservative polygon blocked at once) has
    // it on the edges that end there.
    if (LeftOf(a, b, inside) > 0.0 || (a - inside).squaredNorm() <= 1e-18 ||
        (b - inside).squaredNorm() <= 1e-18) {
      continue;
    }
    return s;
  }
  return -1;
}

int PolygonSimplifier::Bisector(const std::vector<Vec2>& ring, int s, const Vec2& inside) const {
  const int n = int(ring.size());
  const Segment& g = segments_[std::size_t(s)];
  const Vec2& a = ring[g.from];
  const Vec2& b = ring[(g.from + g.length) % n];
  int best = -1;
  double best_score = 0.0;
  for (int k = 1; k < g.length; ++k) {
    const int i = (g.from + k) % n;
    const double score = std::min(LeftOf(a, ring[i], inside), LeftOf(ring[i], b, inside));
    if (best < 0 || score > best_score) {
      best = i;
      best_score = score;
    }
  }
  return best;
}

double PolygonSimplifier::Simplify(const std::vector<Vec2>& ring, const Vec2& inside,
                                   std::vector<int>* kept) {
  kept->clear();
  const int n = int(ring.size());
  if (n <= 2) {
    for (int i = 0; i < n; ++i) kept->push_back(i);
    return 0.0;
  }
  int far = 1;
  for (int i = 2; i < n; ++i) {
    if ((ring[i] - ring[0]).squaredNorm() > (ring[far] - ring[0]).squaredNorm()) far = i;
  }
  used_ = 2;
  heap_.Clear();
  for (int s = 0; s < 2; ++s) {
    segments_[std::size_t(s)] = s == 0 ? Measure(ring, 0, far) : Measure(ring, far, n - far);
    segments_[std::size_t(s)].next = s == 0 ? 1 : -1;
    HeapPlace(s);
  }
  int count = 2;

  // The vehicle first: C_Edge is ordered by ray angle around the vehicle, so the polygon of any
  // subset of it contains the vehicle when the vehicle is left of every edge; and splitting an
  // edge that has it on its left keeps it there. So make every edge pass it on the left, with
  // the vertex that best bisects the edge, before spending vertices on shape.
  // The segments before the one split last were checked and did not change: the search goes
  // on from there.
  auto contain = [&] {
    int first = 0;
    while (count < max_vertices_) {
      const int s = ContainmentSplit(ring, inside, first);
      if (s < 0) break;
      Split(ring, s, Bisector(ring, s, inside));
      ++count;
      first = s;
    }
  };
  contain();

  // Douglas-Peucker, farthest deviation first, with the paper's stop at N vertices.
  while (count < max_vertices_ && !heap_.empty()) {
    const int s = heap_.top();
    if (segments_[std::size_t(s)].priority <= epsilon_ && count >= 3) break;
    Split(ring, s, segments_[std::size_t(s)].worst);
    ++count;
  }
  // Rings that are not star-shaped around the vehicle can lose it again; repair if N allows.
  contain();

  double error = 0.0;
  for (int s = 0; s >= 0; s = segments_[std::size_t(s)].next) {
    const Segment& g = segments_[std::size_t(s)];
    kept->push_back(g.from);
    if (g.worst >= 0) error = std::max(error, g.deviation);
  }
  return error;
}

}  // namespace freespace
