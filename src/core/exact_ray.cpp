// The end points of the exact border rays (core/exact_ray.hpp), from their integer stops.
#include "core/exact_ray.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace freespace {

// Rounded down, not to the nearest: the fixed-point sensor stays in the cell the sensor is in
// (Result::vehicle_cell), the one cell the polygon mask keeps whatever the map holds there.
SensorCell MakeSensorCell(const Vec2& cells, int width, int height) {
  const auto fixed = [](double v, int cells_across) {
    return std::int32_t(
        std::floor(std::clamp(v * kFixedOne, 0.0, cells_across * double(kFixedOne) - 1.0)));
  };
  SensorCell s;
  s.x = fixed(cells.x(), width);
  s.y = fixed(cells.y(), height);
  s.cell = {FixedFloorCell(s.y), FixedFloorCell(s.x)};
  return s;
}

BlockView FullBlocks(const std::uint64_t* bits, int words, int width, int height, int row_begin,
                     int row_end, std::vector<std::uint64_t>* blocks) {
  BlockView view;
  view.rows = height >> kBlockShift;  // partial blocks at the map's edges are never full
  view.cols = width >> kBlockShift;
  view.words = (view.cols + 63) / 64;
  blocks->assign(std::size_t(view.rows) * view.words, 0);
  std::uint64_t all[128];  // room for the widest map (map.width_cells <= 8192)
  for (int br = std::max(0, row_begin >> kBlockShift); br < view.rows; ++br) {
    const int r0 = br << kBlockShift;
    if (r0 >= row_end) break;
    std::fill_n(all, words, ~std::uint64_t{0});
    for (int r = r0; r < r0 + kBlockCells; ++r) {
      for (int w = 0; w < words; ++w) all[w] &= bits[std::size_t(r) * words + w];
    }
    std::uint64_t* out = blocks->data() + std::size_t(br) * view.words;
    for (int bc = 0; bc < view.cols; ++bc) {
      const int c0 = bc << kBlockShift;
      const std::uint64_t cells =
          (all[c0 >> 6] >> (c0 & 63)) & ((std::uint64_t{1} << kBlockCells) - 1);
      if (cells == (std::uint64_t{1} << kBlockCells) - 1)
        out[bc >> 6] |= std::uint64_t{1} << (bc & 63);
    }
  }
  view.bits = blocks->data();
  return view;
}

}  // namespace freespace
