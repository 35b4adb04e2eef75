// The safety margin of the conservative polygon (polygon.margin_cells, margin_cone_deg).
#pragma once

#include <cstdint>
#include <vector>

#include "freespace/types.hpp"

namespace freespace {

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

}  // namespace freespace
