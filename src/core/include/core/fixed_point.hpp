// Fixed-point map coordinates shared by the kernel stages: positions in 1/256 of a cell, so that
// the geometry every backend computes is integer and exact.
#pragma once

#include <cstdint>

namespace freespace {

// Polygon vertices reach the kernels in fixed point: 1/256 of a cell, in map cell coordinates
// (x = column axis, y = row axis). Integer geometry keeps every backend exact.
inline constexpr int kFixedBits = 8;
inline constexpr std::int32_t kFixedOne = 1 << kFixedBits;
inline constexpr std::int32_t kFixedHalf = kFixedOne / 2;

// Cells to fixed point, rounding half away from zero (as llround), inline: it runs for every
// point of every scan.
inline std::int32_t ToFixed(double cells) {
  const double v = cells * kFixedOne;
  return std::int32_t(v >= 0.0 ? v + 0.5 : v - 0.5);
}

// The cell holding a fixed-point coordinate: its floor.
inline std::int32_t FixedFloorCell(std::int32_t fixed) {
  return fixed >= 0 ? fixed / kFixedOne : -((-fixed + kFixedOne - 1) / kFixedOne);
}

// floor(x) for |x| < 2^31 (map cells), without a library call: the baseline x86-64 target has
// no rounding instruction, and std::floor is a call there.
inline int FloorCell(double x) {
  const int i = int(x);
  return i - (x < i);
}

}  // namespace freespace
