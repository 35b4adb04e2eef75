// The free-space polygon (paper IV.B): C_Edge cell centres simplified by Douglas-Peucker with
// the paper's extra stop condition, at most N vertices. The farthest-deviating vertex is
// always split first, so a capped result keeps the most important vertices.
#pragma once

#include <vector>

#include "core/indexed_heap.hpp"
#include "freespace/types.hpp"

namespace freespace {

class PolygonSimplifier {
 public:
  // max_vertices: N (>= 3); epsilon: tolerance in the units of the ring (cells).
  PolygonSimplifier(int max_vertices, double epsilon);

  // Weight of a vertex's distance when it lies on the left of the segment (inside a
  // counter-clockwise ring): 1 (the paper's Douglas-Peucker) or more, so that a vertex the
  // simplified edge would cut off counts that much farther.
  void set_inward_weight(double weight) { inward_weight_ = weight; }

  // Simplifies the closed, counter-clockwise `ring`. Writes the indices of the kept vertices
  // (ring order) into `kept`. First splits edges until `inside` (the vehicle) is left of every
  // edge, then splits the farthest-deviating vertex while its deviation exceeds epsilon and
  // fewer than N vertices are kept; keeps at least three vertices when the ring has them.
  // Returns the largest distance from a dropped vertex to the result's edge that replaced it.
  double Simplify(const std::vector<Vec2>& ring, const Vec2& inside, std::vector<int>* kept);

 private:
  struct Segment {
    int from = 0;            // ring index of the first vertex
    int length = 0;          // steps to the last vertex (wrapping around the ring)
    int worst = -1;          // ring index of the interior vertex to split at first, -1 when none
    double priority = 0.0;   // its distance from the segment, weighted when inward
    double deviation = 0.0;  // the largest distance of an interior vertex from the segment
    int next = -1;           // the following segment in ring order, -1 after the last
  };
  Segment Measure(const std::vector<Vec2>& ring, int from, int length) const;
  // Replaces segment s by two, meeting at ring vertex `vertex`: s keeps the first half, the
  // second is a new segment after it. Returns the new one.
  int Split(const std::vector<Vec2>& ring, int s, int vertex);
  // The first segment from segment `first` on (ring order) with interior vertices that does not
  // pass `inside` on its left, or -1.
  int ContainmentSplit(const std::vector<Vec2>& ring, const Vec2& inside, int first) const;
  // The interior vertex of segment s that leaves `inside` farthest left of both halves.
  int Bisector(const std::vector<Vec2>& ring, int s, const Vec2& inside) const;

  // The heap of segments with interior vertices, the one to split next on top: the highest
  // priority, and of equal ones the first in ring order (the lowest `from`).
  bool Before(int a, int b) const;
  // s's priority changed, or s is new: moves it where it belongs, or out without interior vertices.
  void HeapPlace(int s);

  int max_vertices_;
  double epsilon_;
  double inward_weight_ = 1.0;
  std::vector<Segment> segments_;  // a pool: segment 0 starts at ring vertex 0
  int used_ = 0;
  IndexedHeap heap_;  // the segments with interior vertices
};

// Even-odd point-in-polygon test; a point on the boundary may count either way.
bool PointInPolygon(const std::vector<Vec2>& polygon, const Vec2& p);

// Distance from p to the segment [a, b], and its square (the distance is its square root).
double DistanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b);
double SquaredDistanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b);

}  // namespace freespace
