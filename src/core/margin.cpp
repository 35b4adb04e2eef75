// The safety margin of the conservative polygon (polygon.margin_cells, margin_cone_deg).
#include "core/margin.hpp"

#include <cmath>

namespace freespace {

PolygonMargin::PolygonMargin(int width, int height, int cells, double cone_deg)
    : width_(width),
      height_(height),
      cos_cone_(std::cos(cone_deg * M_PI / 180.0)),
      all_around_(cone_deg >= 180.0) {
  for (int dy = -cells; dy <= cells; ++dy) {
    for (int dx = -cells; dx <= cells; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const double norm = std::hypot(dx, dy);
      offsets_.push_back({dx, dy, dx / norm, dy / norm});
    }
  }
}

void PolygonMargin::Apply(const LogOdds* log_odds, const Vec2& sensor, std::uint8_t* free) const {
  const int sensor_col = int(std::floor(sensor.x())), sensor_row = int(std::floor(sensor.y()));
  // Within the cone: u . v >= cos * |v|, tested without a root. Rounding must not decide a
  // cone at exactly 90 degrees or at a table direction.
  const double cos_cone = cos_cone_ - 1e-9;
  const double cos2 = cos_cone * cos_cone;
  constexpr int kRun = 16;  // most of a map is not occupied: skipped this many cells at a time
  for (int row = 0; row < height_; ++row) {
    const LogOdds* line = log_odds + std::size_t(row) * width_;
    for (int col = 0; col < width_; ++col) {
      if (col % kRun == 0 && col + kRun <= width_) {
        bool any = false;
        for (int k = 0; k < kRun; ++k) any |= line[col + k] > 0;
        if (!any) {
          col += kRun - 1;
          continue;
        }
      }
      if (line[col] <= 0) continue;
      // An occupied cell: its neighbours within k that see it beyond them leave the mask.
      for (const Offset& o : offsets_) {
        const int x = col - o.dx, y = row - o.dy;
        if (x < 0 || y < 0 || x >= width_ || y >= height_) continue;
        std::uint8_t& cell = free[std::size_t(y) * width_ + x];
        if (!cell || (x == sensor_col && y == sensor_row)) continue;
        if (!all_around_) {
          const double vx = x + 0.5 - sensor.x(), vy = y + 0.5 - sensor.y();
          const double dot = o.ux * vx + o.uy * vy, dot2 = dot * dot, v2 = vx * vx + vy * vy;
          const bool inside =
              cos_cone >= 0 ? dot >= 0 && dot2 >= cos2 * v2 : dot >= 0 || dot2 <= cos2 * v2;
          if (!inside) continue;
        }
        cell = 0;
      }
    }
  }
}

}  // namespace freespace
