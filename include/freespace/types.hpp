// Basic value types shared by the whole public API: poses, cell indices, the log-odds cell
// type and the Eigen names used for positions.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace freespace {

// A position in metres (world frame) or in cells (map frame), as the name of the field says.
using Vec2 = Eigen::Vector2d;

// A planar pose: position in metres, yaw in radians, counter-clockwise from the world x axis.
struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

// A cell of the map. Row 0 is the southern edge (smallest world y) and rows grow towards +y;
// column 0 is the western edge (smallest world x) and columns grow towards +x. Cell (row, col)
// covers [origin.x + col * res, origin.x + (col + 1) * res) x [origin.y + row * res, ...).
struct CellIndex {
  std::int32_t row = 0;
  std::int32_t col = 0;
  friend bool operator==(const CellIndex& a, const CellIndex& b) {
    return a.row == b.row && a.col == b.col;
  }
};

// A cell's occupancy in fixed-point log-odds: value / kLogOddsScale = ln(p / (1 - p)).
// 0 is unknown (p = 0.5). Integer arithmetic makes every backend bit-exact.
using LogOdds = std::int16_t;
inline constexpr int kLogOddsScale = 256;

}  // namespace freespace
