// The conservative free-space polygon (polygon.shape inside): a star-shaped polygon around the
// sensor, at most N vertices, every point of which lies in a cell of the polygon mask (the free
// mask less the safety margin, kernel stage 3b) or on such a cell's edge. It is built from the
// exact border rays of stage 4 (core/exact_ray.hpp), which end where they first meet a cell
// outside the mask: the ring of their end points, pulled toward the sensor where a cell outside
// the mask pokes between two neighbouring rays, simplified by least area given up
// (core/area_simplifier.hpp) and pulled once more where a simplified edge cuts inside the ring.
#pragma once

#include <cstdint>
#include <vector>

#include "core/area_simplifier.hpp"
#include "core/exact_ray.hpp"
#include "core/simplifier.hpp"
#include "freespace/types.hpp"

namespace freespace {

struct FanPull;

// The polygon mask as bitset rows: bit c % 64 of word c / 64 of row r (rows `words` words
// apart) is 1 where cell (r, c) may lie in the polygon.
struct MaskView {
  int width = 0;
  int height = 0;
  int words = 0;
  const std::uint64_t* bits = nullptr;

  bool Allowed(int col, int row) const {
    return (bits[std::size_t(row) * words + (col >> 6)] >> (col & 63)) & 1;
  }
};

class InsidePolygonBuilder {
 public:
  // width, height: the map in cells; max_vertices: N (>= 3); epsilon: tolerance in cells;
  // parts: the rays' ends and the pairs between them are worked in this many runs in parallel (TBB,
  // in the caller's arena); 1: all on the calling thread. The result does not depend on it. All
  // memory is allocated here.
  InsidePolygonBuilder(int width, int height, int max_vertices, double epsilon, int parts = 1);

  // `stops`: the exact rays' stops on `mask`, one per border label (BorderCell order) from the
  // sensor `s`. Writes the polygon (counter-clockwise, map cells) into `polygon` and returns
  // true; or leaves `polygon` empty and returns false when nothing around the sensor is in the
  // mask (every ray ends on the edge of the sensor's own cell), or when the simplified polygon,
  // pulled inside the ring, has fewer than three distinct vertices left (collapsed(): a very
  // small max_vertices). `error`: the simplification error in cells, as
  // PolygonSimplifier::Simplify returns it.
  bool Build(const MaskView& mask, const SensorCell& s, const std::vector<RayStop>& stops,
             std::vector<Vec2>* polygon, double* error);
  // The last Build() found space in the mask but no polygon of max_vertices vertices in it.
  bool collapsed() const { return collapsed_; }

  // The ring of the last Build(): the rays' ends, pulled in or gone round where a cell outside
  // the mask pokes between two of them, straight runs compacted: the union of its fan
  // triangles around the sensor lies in the mask.
  const std::vector<Vec2>& ring() const { return ring_; }

 private:
  // The cells that can reach into the triangle between two neighbouring rays: a box of rows
  // and columns, narrowed to the sensor's side of a cell edge line that both rays stopped on.
  struct NearSide {
    int row_min, row_max, col_min, col_max;
  };
  // At most this many blocked cells between two rays are gone round; beyond, the pair is pulled.
  static constexpr int kMaxBlocked = 16;
  // One pair's pull in the making: the blocked cells that reach into its triangle, and the
  // corner Settle() chose to go round.
  struct PairPull {
    CellIndex blocked[kMaxBlocked];
    int count = 0;
    bool overflow = false;
    bool split = false;  // Settle() went round `at`
    Vec2 at = Vec2::Zero();
    double in = 1.0, out = 1.0;  // the corner's scales
  };
  NearSide Near(const Vec2& sensor, const RayStop& a, const RayStop& b) const;
  // How far a and b may stay of the triangle (sensor, a, b) so that it overlaps no cell outside
  // the mask, where a and b are neighbouring rays' ends: only cells the edge a -> b meets, on
  // the `near` side, can reach inside. `pull` comes fresh (PairPull{}).
  void PullBetweenRays(const MaskView& mask, const Vec2& sensor, const Vec2& a, const Vec2& b,
                       const NearSide& near, PairPull* pull, double* scale_a,
                       double* scale_b) const;
  // Limits `bounds` by a cell outside the mask and keeps it in `pull` when it reaches into
  // the triangle (sensor, sensor + u, sensor + v).
  static void Block(int row, int col, const Vec2& sensor, const Vec2& u, const Vec2& v, double det,
                    FanPull* bounds, PairPull* pull);
  // The pair's scales from `bounds`, or a corner of a blocked cell to go round (pull->split).
  static void Settle(const Vec2& sensor, const Vec2& a, const Vec2& b, const FanPull& bounds,
                     PairPull* pull, double* scale_a, double* scale_b);
  // The same for a simplified edge from ring vertex i to ring vertex j: the triangle must stay
  // inside the ring's fan triangles i .. j.
  void PullInsideRing(const Vec2& sensor, int i, int j, double* scale_a, double* scale_b) const;
  // The end points (end_) of rays [begin, end), one ray per distinct border cell; false when
  // none of them left the sensor's own cell.
  bool RayEnds(const SensorCell& s, const std::vector<RayStop>& stops, int begin, int end);
  // Between ray k and the next: a corner to go round, or how far to pull their ends. Writes only
  // pair k's entries: pairs may be worked in parallel.
  void BetweenRays(const MaskView& mask, const Vec2& sensor, int k);
  // The ring from the ends, pulled, with the corners between them; compacted as it comes.
  void AssembleRing(const Vec2& sensor);
  // Keeps the ring's vertices as they come but those on a straight run along a row or a column
  // line between the last one kept and the next (the ring closed: the first vertex's neighbour
  // before it is `last`, the last vertex that will come).
  class RingCompactor {
   public:
    RingCompactor(std::vector<Vec2>* ring, const Vec2& last) : ring_(ring), last_(last) {}
    void Offer(const Vec2& next);
    void Close();  // decides the last vertex, whose neighbour after it is the first one kept

   private:
    static bool Inner(const Vec2& a, const Vec2& p, const Vec2& b) {
      return (a.x() == p.x() && p.x() == b.x()) || (a.y() == p.y() && p.y() == b.y());
    }
    std::vector<Vec2>* ring_;
    Vec2 last_, first_ = Vec2::Zero(), pending_ = Vec2::Zero();
    bool started_ = false;
  };
  // Drops repeated vertices; false when fewer than three distinct ones remain.
  static bool Distinct(std::vector<Vec2>* polygon);

  int width_, height_;
  AreaSimplifier area_;                  // the ring's simplification
  PolygonSimplifier simplifier_;         // where area_ cannot keep N vertices around the sensor
  std::vector<int> labels_;              // one label per distinct border cell, in label order
  std::vector<Vec2> end_;                // where each ray ended
  std::vector<RayStop> end_stop_;        // and how
  std::vector<double> need_a_, need_b_;  // per pair of rays: the scales of the first / second end
  std::vector<std::uint8_t> corner_;     // per pair of rays: a corner to go round (1), or a
                                         // blocked cell's corner with scales of its own (2)
  std::vector<Vec2> corner_at_;          // and where
  std::vector<double> split_in_at_, split_out_at_;  // (2): the corner's scales
  int parts_;
  bool collapsed_ = false;
  std::vector<char> part_beyond_;  // per part: RayEnds() found a ray beyond the sensor's cell
  std::vector<Vec2> ring_;
  std::vector<int> kept_;
  std::vector<double> scale_;
};

}  // namespace freespace
