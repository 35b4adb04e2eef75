// The conservative polygon's simplification (polygon.shape inside): the ring's vertices dropped
// one at a time, the drop that gives up the least area first, until at most N are left and no
// further drop stays within epsilon. Dropping a convex vertex cuts off the triangle it makes with
// its neighbours; dropping a reflex one would pass outside the ring, and the edge must then be
// pulled in (core/inside_polygon.hpp), so it costs `inward_weight` times its triangle. A drop
// whose new edge would not pass the centre on its left is never made, nor one of a vertex at the
// centre (where rays were blocked at once, the polygon must pass through it): the result stays
// star-shaped around the centre.
#pragma once

#include <vector>

#include "core/min_tree.hpp"
#include "freespace/types.hpp"

namespace freespace {

class AreaSimplifier {
 public:
  // max_vertices: N (>= 3); epsilon: tolerance in the units of the ring (cells); capacity: the
  // longest ring it will be given (all memory is allocated here).
  AreaSimplifier(int max_vertices, double epsilon, double inward_weight, int capacity);

  // Simplifies the closed, counter-clockwise `ring` around `centre`: the indices of the kept
  // vertices (ring order) into `kept`. Returns the largest distance from a dropped vertex to
  // the kept edge that replaced it (at most epsilon unless N stopped the drops), or -1 when the
  // drops could not get down to N vertices with the centre left of every edge (kept is then
  // empty: the caller simplifies another way).
  double Simplify(const std::vector<Vec2>& ring, const Vec2& centre, std::vector<int>* kept);

 private:
  // The weighted area vertex v's drop between its current neighbours gives up; infinite when
  // not allowed.
  double Cost(const std::vector<Vec2>& ring, const Vec2& centre, int v) const;
  // A bound on the distance from the edge that replaces v of every vertex it replaces.
  double Deviation(const std::vector<Vec2>& ring, int v) const;
  // A drop's weight from twice its signed triangle: > 0, v left of the new edge, is reflex.
  double Weight(double twice) const { return twice > 0.0 ? inward_weight_ : 1.0; }
  static double KeptError(const std::vector<Vec2>& ring, const std::vector<int>& kept);

  int max_vertices_;
  double epsilon_;
  double inward_weight_;
  std::vector<int> prev_, next_;
  MinTree tree_;                   // the costs of the vertices not dropped
  std::vector<char> dropped_;      // per vertex: dropped
  std::vector<char> at_centre_;    // per vertex: at the centre (never dropped)
  std::vector<double> cost_;       // per vertex: its drop's cost
  std::vector<double> deviation_;  // per kept vertex: the bound for the edge that starts at it
};

}  // namespace freespace
