// The conservative free-space polygon (polygon.shape inside): the border rays cast exactly
// from the sensor on the free mask, simplified like the paper's polygon, then pulled toward the
// sensor until it covers free cells only.
#pragma once

#include <tbb/task_arena.h>

#include <cstdint>
#include <vector>

#include "core/simplifier.hpp"
#include "freespace/types.hpp"

namespace freespace {

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

}  // namespace freespace
