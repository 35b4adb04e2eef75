// The per-scan face layer of the conservative polygon (polygon.face_tolerance_m): where this
// scan's outline says the obstacles' faces are, to the sub-cell, so that the polygon mask keeps
// out what lies near a face rather than every cell next to an occupied one (docs/design.md).
#pragma once

#include <cstdint>
#include <vector>

#include "freespace/config.hpp"

namespace freespace {

struct Beam;

struct FaceRule {
  double tolerance_m = 0.0;  // polygon.face_tolerance_m: how close to a face a cell is kept out
  // An outline edge longer than join_m + join_per_m * (the nearer beam's range) joins two
  // surfaces (a shadow's side) rather than running along one: the clutter filter's
  // neighbourhood (clutter.eps_m, eps_per_m).
  double join_m = 0.0;
  double join_per_m = 0.0;
  double resolution_m = 0.2;
  // A run of beams without echo no wider than this is a gap in a surface (echoes the clutter
  // filter took, or a dark or grazing patch), a wider one open space.
  double max_gap_rad = 0.0;

  // The rule `config` sets: tolerance 0 unless polygon.shape is inside.
  static FaceRule Of(const Config& config);
};

// The widest run of beams without echo that counts as a gap in a surface: 8 degrees.
inline constexpr double kMaxGapDeg = 8.0;

// One part's lists of FaceCells(). Each part on a cache line of its own: the parts grow their
// lists from different threads at once.
struct alignas(64) FaceLists {
  std::vector<std::int32_t> near, seen;
};

// From one scan's outline: `vertices` its full-scan polygon's closed ring (fixed point, vertex 0
// the sensor) and `beams` its vertices 1 .. n (the same count, in order). An edge between two
// consecutive beams is a face when it is no longer than the join distance and, where it meets
// virtual beams, their run is a gap (no wider than rule.max_gap_rad, or bounded by real beams
// within the join distance) or this is its first edge from a real beam. Appends to `near` every
// map cell whose square lies within rule.tolerance_m of a face, or of a real beam's point at
// either end of an edge that is not one; to `seen` the cells such a face or point touches. Cells
// outside the map are left out; repeats allowed. The edges are split into parts->size() runs
// worked in parallel (TBB), each into its part (cleared first), then appended in order.
void FaceCells(const std::vector<std::int32_t>& vertices, const std::vector<Beam>& beams,
               const FaceRule& rule, int width, int height, std::vector<FaceLists>* parts,
               std::vector<std::int32_t>* near, std::vector<std::int32_t>* seen);

}  // namespace freespace
