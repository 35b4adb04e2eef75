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
  struct Drop {
    double cost;       // the area given up, weighted when the vertex is reflex
    double deviation;  // a bound on the distance of the vertices the new edge replaces from it
    double distance;   // the bound, weighted when the vertex is reflex
    int vertex;
    int stamp;  // the vertex's stamp when this was worked out: stale when it changed since
  };
  // The drop of vertex v between its current neighbours; cost infinite when not allowed.
  Drop Cost(const std::vector<Vec2>& ring, const Vec2& centre, int v) const;
  void Push(const Drop& drop);
  bool Pop(Drop* drop);  // the cheapest drop still current; false when none is left

  int max_vertices_;
  double epsilon_;
  double inward_weight_;
  std::vector<int> prev_, next_, stamp_;
  std::vector<double> deviation_;  // per kept vertex: the bound for the edge that starts at it
  std::vector<char> dropped_;
  std::vector<Drop> heap_;
};

}  // namespace freespace
