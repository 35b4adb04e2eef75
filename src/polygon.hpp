// The free-space polygon (paper IV.B): C_Edge cell centres simplified by Douglas-Peucker with
// the paper's extra stop condition, at most N vertices. The farthest-deviating vertex is
// always split first, so a capped result keeps the most important vertices. Also the
// conservative variant (polygon.shape inside): the same border rays cast exactly from the
// sensor on the free mask, simplified alike, then pulled toward the sensor until it covers
// free cells only; and its optional safety margin (PolygonMargin).
#pragma once

#include <tbb/task_arena.h>

#include <cstdint>
#include <vector>

#include "freespace/types.hpp"

namespace freespace {

class PolygonSimplifier {
 public:
  // max_vertices: N (>= 3); epsilon: tolerance in the units of the ring (cells).
  PolygonSimplifier(int max_vertices, double epsilon);

  // Simplifies the closed, counter-clockwise `ring`. Writes the indices of the kept vertices
  // (ring order) into `kept`. First splits edges until `inside` (the vehicle) is left of every
  // edge, then splits the farthest-deviating vertex while its deviation exceeds epsilon and
  // fewer than N vertices are kept; keeps at least three vertices when the ring has them.
  // Returns the largest distance from a dropped vertex to the result's edge that replaced it.
  double Simplify(const std::vector<Vec2>& ring, const Vec2& inside, std::vector<int>* kept);

 private:
  struct Segment {
    int from = 0;    // ring index of the first vertex
    int length = 0;  // steps to the last vertex (wrapping around the ring)
    int worst = -1;  // ring index of the farthest vertex strictly inside, -1 when none
    double deviation = 0.0;
  };
  Segment Measure(const std::vector<Vec2>& ring, int from, int length) const;
  // Replaces segment s by two, meeting at ring vertex `vertex`.
  void Split(const std::vector<Vec2>& ring, int s, int vertex);
  // A segment with interior vertices that does not pass `inside` on its left, or -1.
  int ContainmentSplit(const std::vector<Vec2>& ring, const Vec2& inside) const;
  // The interior vertex of segment s that leaves `inside` farthest left of both halves.
  int Bisector(const std::vector<Vec2>& ring, int s, const Vec2& inside) const;

  int max_vertices_;
  double epsilon_;
  std::vector<Segment> segments_;
};

// The conservative free-space polygon (polygon.shape inside) on a free mask, in map cells
// (cell (r, c) spans [c, c+1) x [r, r+1)). Every point of the result lies in a free cell or
// on a free cell's border; the result is star-shaped around the sensor and has at most N
// vertices. All memory is allocated in the constructor.
class InsidePolygonBuilder {
 public:
  // width, height: the map in cells; max_vertices: N (>= 3); epsilon: tolerance in cells;
  // threads: for the rays (0 = all cores).
  InsidePolygonBuilder(int width, int height, int max_vertices, double epsilon, int threads = 0);

  // `free`: width * height bytes, row-major, non-zero where free; `sensor`: the sensor in
  // cells. Writes the vertices (counter-clockwise) into `polygon`. When the sensor's cell is
  // not free, no free area contains the sensor and the polygon is the sensor point, three
  // times. Returns the simplification error as PolygonSimplifier::Simplify does (cells, before
  // the pull toward the sensor).
  double Build(const std::uint8_t* free, const Vec2& sensor, std::vector<Vec2>* polygon);

  // The unsimplified ring of the last Build(): one vertex per border ray where it enters its
  // first not-free cell (or at the border cell's centre).
  const std::vector<Vec2>& ring() const { return ring_; }

 private:
  // Fraction t in [0, 1] of the segment sensor -> target that stays in free cells: the ray
  // stops where it first touches a cell that is not free.
  double Trace(const std::uint8_t* free, const Vec2& sensor, const Vec2& target) const;
  // Scales for a and b toward the sensor such that the triangle (sensor,
  // sensor + scale_a (a - sensor), sensor + scale_b (b - sensor)) overlaps no cell that is not
  // free: of moving both alike, only b, or only a, the one that keeps the most area.
  void EdgePull(const std::uint8_t* free, const Vec2& sensor, const Vec2& a, const Vec2& b,
                double* scale_a, double* scale_b) const;
  // The not-free blocks of kBlock x kBlock cells, as a summed-area table, for skipping free
  // parts of a triangle in EdgePull().
  void CountBlocks(const std::uint8_t* free);
  // Whether any block meeting cells [r0, r1] x [c0, c1] holds a cell that is not free.
  bool BlocksNotFree(int r0, int r1, int c0, int c1) const;

  static constexpr int kBlock = 8;

  int width_, height_;
  PolygonSimplifier simplifier_;
  std::vector<Vec2> ring_;
  std::vector<int> kept_;
  std::vector<double> scale_;
  std::vector<std::uint32_t> block_sat_;
  std::vector<std::uint8_t> block_row_;
  std::vector<Vec2> targets_;  // border cell centres, one per ray
  tbb::task_arena arena_;
};

// The safety margin of the conservative polygon (polygon.margin_cells, margin_cone_deg), applied
// to its free mask before the polygon is built. The map calls free a cell that an obstacle
// covers by a sliver when the echoes of that obstacle land in the next cell (range steps and
// noise along the beam, sparse echoes along a face seen at a grazing angle): such a cell lies
// just in front of a cell the map holds occupied, as seen from the sensor. The cone limits the
// margin to there: beside an obstacle it would only widen the obstacle's shadow in the
// star-shaped polygon. The offsets and their directions are tabled in the constructor.
class PolygonMargin {
 public:
  // width, height: the map in cells; cells: k (>= 1); cone_deg: (0, 180].
  PolygonMargin(int width, int height, int cells, double cone_deg);

  // Clears in `free` (width * height bytes, row-major) every cell within k cells (Chebyshev)
  // of a cell whose log-odds are above 0, where that cell lies within cone_deg of the line of
  // sight from `sensor` (cells) through the cleared cell's centre, continued beyond it: the
  // angle between (occupied centre - cell centre) and (cell centre - sensor) is at most
  // cone_deg. The sensor's own cell is left as it is.
  void Apply(const LogOdds* log_odds, const Vec2& sensor, std::uint8_t* free) const;

 private:
  struct Offset {
    int dx = 0, dy = 0;         // from the kept-out cell to the occupied one
    double ux = 0.0, uy = 0.0;  // the same, unit length
  };
  int width_, height_;
  double cos_cone_;
  bool all_around_;  // cone 180: no direction test
  std::vector<Offset> offsets_;
};

// Even-odd point-in-polygon test; a point on the boundary may count either way.
bool PointInPolygon(const std::vector<Vec2>& polygon, const Vec2& p);

// Distance from p to the segment [a, b].
double DistanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b);

}  // namespace freespace
