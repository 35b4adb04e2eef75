// The exact border rays of the conservative polygon (polygon.shape inside): straight rays from
// the sensor's position, in fixed point, to the centre of every border cell, walked cell by cell
// through every cell they pass (not a Bresenham line: a ray that cuts the corner of a cell enters
// it). Integer arithmetic only, so every backend finds the same stops: kernels/insight.cl
// mirrors TraceExactRay() line for line.
#pragma once

#include <cstdint>
#include <vector>

#include "core/fixed_point.hpp"
#include "freespace/types.hpp"

namespace freespace {

// The sensor as the conservative polygon's stages see it: its position in map cells, in fixed
// point (kFixedBits), and the cell that holds it (the floor of the position). The position lies
// inside the map.
struct SensorCell {
  std::int32_t x = 0;
  std::int32_t y = 0;
  CellIndex cell;
};

// The sensor at `cells` (map cells), rounded down to fixed point (so that its cell is the floor
// of `cells`) and kept inside a width x height map.
SensorCell MakeSensorCell(const Vec2& cells, int width, int height);

// How an exact ray ended.
enum RayStopKind : std::int32_t {
  kRayEnd = 0,     // it reached the centre of its border cell
  kRayCrossX = 1,  // it entered a blocked cell across a vertical cell edge (x = integer)
  kRayCrossY = 2,  // across a horizontal cell edge (y = integer)
  kRayCorner = 3,  // through a cell corner, a cell beyond which is blocked
};

// Where an exact ray ended: `cell` (row * width + col) is the blocked cell it entered or
// touched (at a corner the diagonal one first, then the one across the vertical edge, then the
// one across the horizontal edge), or its border cell when it reached the end; `line` is the
// cell edge where it stopped: x = line for kRayCrossX and kRayCorner, y = line for kRayCrossY.
struct RayStop {
  std::int32_t cell = 0;
  std::int32_t kind = kRayEnd;
  std::int32_t line = 0;
};

// The ray from `s` to the centre of border cell (target_col, target_row). `allowed(col, row)`
// tells whether the ray may pass a cell; the sensor's own cell never stops it. The ray leaves
// its current cell where its parameter along the ray first reaches a cell edge; the two
// candidates are compared exactly, as products of 64-bit integers.
template <class Allowed>
RayStop TraceExactRay(const Allowed& allowed, int width, const SensorCell& s, int target_col,
                      int target_row) {
  const std::int64_t dx = std::int64_t(target_col) * kFixedOne + kFixedHalf - s.x;
  const std::int64_t dy = std::int64_t(target_row) * kFixedOne + kFixedHalf - s.y;
  const int step_x = dx > 0 ? 1 : (dx < 0 ? -1 : 0), step_y = dy > 0 ? 1 : (dy < 0 ? -1 : 0);
  const std::int64_t adx = dx < 0 ? -dx : dx, ady = dy < 0 ? -dy : dy;
  int cx = s.cell.col, cy = s.cell.row;
  // Distances (fixed point, along each axis) from the sensor to the next edge crossed.
  std::int64_t nx = step_x > 0 ? std::int64_t(cx + 1) * kFixedOne - s.x
                               : std::int64_t(s.x) - std::int64_t(cx) * kFixedOne;
  std::int64_t ny = step_y > 0 ? std::int64_t(cy + 1) * kFixedOne - s.y
                               : std::int64_t(s.y) - std::int64_t(cy) * kFixedOne;
  while (cx != target_col || cy != target_row) {
    // The edge crossed first: t_x = nx / adx against t_y = ny / ady.
    const std::int64_t ex = step_x == 0 ? 1 : nx * ady, ey = step_y == 0 ? 1 : ny * adx;
    const bool cross_x = step_x != 0 && (step_y == 0 || ex < ey);
    const bool cross_y = step_y != 0 && (step_x == 0 || ey < ex);
    // The edges ahead: x = edge_x, y = edge_y.
    const int edge_x = step_x > 0 ? cx + 1 : cx, edge_y = step_y > 0 ? cy + 1 : cy;
    if (cross_x) {
      cx += step_x;
      nx += kFixedOne;
      if (!allowed(cx, cy)) return {cy * width + cx, kRayCrossX, edge_x};
    } else if (cross_y) {
      cy += step_y;
      ny += kFixedOne;
      if (!allowed(cx, cy)) return {cy * width + cx, kRayCrossY, edge_y};
    } else {  // through a corner: the ray touches the three cells beyond it
      const bool diagonal = allowed(cx + step_x, cy + step_y);
      const bool across_x = allowed(cx + step_x, cy), across_y = allowed(cx, cy + step_y);
      if (!diagonal) return {(cy + step_y) * width + cx + step_x, kRayCorner, edge_x};
      if (!across_x) return {cy * width + cx + step_x, kRayCorner, edge_x};
      if (!across_y) return {(cy + step_y) * width + cx, kRayCorner, edge_x};
      cx += step_x;
      cy += step_y;
      nx += kFixedOne;
      ny += kFixedOne;
    }
  }
  return {cy * width + cx, kRayEnd, 0};
}

// The first cell u in [from, to] (from <= to: upwards; from > to: downwards) whose bit in the
// bitset row `line` is 0, or -1.
inline int FirstClearBit(const std::uint64_t* line, int from, int to) {
  if (from <= to) {
    for (int w = from >> 6; w <= to >> 6; ++w) {
      std::uint64_t hits = ~line[w];
      if (w == from >> 6) hits &= ~std::uint64_t{0} << (from & 63);
      if (w == to >> 6) hits &= ~std::uint64_t{0} >> (63 - (to & 63));
      if (hits != 0) return w * 64 + __builtin_ctzll(hits);
    }
  } else {
    for (int w = from >> 6; w >= to >> 6; --w) {
      std::uint64_t hits = ~line[w];
      if (w == from >> 6) hits &= ~std::uint64_t{0} >> (63 - (from & 63));
      if (w == to >> 6) hits &= ~std::uint64_t{0} << (to & 63);
      if (hits != 0) return w * 64 + 63 - __builtin_clzll(hits);
    }
  }
  return -1;
}

// What the walk of an exact ray carries (TraceExactRayRows): its steps and |dx|, |dy| (fixed
// point), nx0 and ny0 the distances from the sensor to the first vertical and horizontal cell
// edges along each axis, a = kFixedOne |dx| and b = kFixedOne |dy| (what crossing a horizontal
// and a vertical edge adds to the error term), q = a / b, r = a % b, and the error term in the
// sensor's cell, e0 = ny0 |dx| - nx0 |dy| (> 0: a vertical edge comes first).
struct ExactRayWalk {
  int step_x = 0, step_y = 0;
  std::int64_t adx = 0, ady = 0, nx0 = 0, ny0 = 0, a = 0, b = 0, q = 0, r = 0, e0 = 0;

  ExactRayWalk(const SensorCell& s, int target_col, int target_row) {
    const std::int64_t dx = std::int64_t(target_col) * kFixedOne + kFixedHalf - s.x;
    const std::int64_t dy = std::int64_t(target_row) * kFixedOne + kFixedHalf - s.y;
    step_x = dx > 0 ? 1 : (dx < 0 ? -1 : 0);
    step_y = dy > 0 ? 1 : (dy < 0 ? -1 : 0);
    adx = dx < 0 ? -dx : dx;
    ady = dy < 0 ? -dy : dy;
    const int cx = s.cell.col, cy = s.cell.row;
    nx0 = step_x > 0 ? std::int64_t(cx + 1) * kFixedOne - s.x
                     : std::int64_t(s.x) - std::int64_t(cx) * kFixedOne;
    ny0 = step_y > 0 ? std::int64_t(cy + 1) * kFixedOne - s.y
                     : std::int64_t(s.y) - std::int64_t(cy) * kFixedOne;
    if (step_x == 0 || step_y == 0) return;  // along a row or a column: no error term
    a = std::int64_t(kFixedOne) * adx;
    b = std::int64_t(kFixedOne) * ady;
    q = a / b;
    r = a % b;
    e0 = ny0 * adx - nx0 * ady;
  }
  // The error term in cell (cx, cy) of the ray: each vertical edge crossed lowers it by b, each
  // horizontal one raises it by a.
  std::int64_t ErrorAt(const SensorCell& s, int cx, int cy) const {
    return e0 - std::int64_t((cx - s.cell.col) * step_x) * b +
           std::int64_t((cy - s.cell.row) * step_y) * a;
  }
};

// The diagonal ray `k` on from cell (cx, cy) with error term e to the centre of border cell
// (target_col, target_row), as TraceExactRayRows() walks it.
inline RayStop WalkExactRay(const std::uint64_t* bits, int words, int width, const ExactRayWalk& k,
                            int cx, int cy, std::int64_t e, int target_col, int target_row) {
  const int step_x = k.step_x, step_y = k.step_y;
  const std::int64_t a = k.a, b = k.b, q = k.q, r = k.r;
  const auto allowed = [&](int x, int y) {
    return (bits[std::size_t(y) * words + (x >> 6)] >> (x & 63)) & 1;
  };
  // At a corner (e == 0): the three cells beyond it, then the diagonal step.
  const auto corner = [&](RayStop* stop) {
    const int edge_x = step_x > 0 ? cx + 1 : cx;
    if (!allowed(cx + step_x, cy + step_y)) {
      *stop = {(cy + step_y) * width + cx + step_x, kRayCorner, edge_x};
    } else if (!allowed(cx + step_x, cy)) {
      *stop = {cy * width + cx + step_x, kRayCorner, edge_x};
    } else if (!allowed(cx, cy + step_y)) {
      *stop = {(cy + step_y) * width + cx, kRayCorner, edge_x};
    } else {
      cx += step_x;
      cy += step_y;
      return false;
    }
    return true;
  };
  RayStop stop;
  if (q < 4) {  // a cell at a time
    while (cx != target_col || cy != target_row) {
      if (e > 0) {
        cx += step_x;
        e -= b;
        if (!allowed(cx, cy)) return {cy * width + cx, kRayCrossX, step_x > 0 ? cx : cx + 1};
      } else if (e < 0) {
        cy += step_y;
        e += a;
        if (!allowed(cx, cy)) return {cy * width + cx, kRayCrossY, step_y > 0 ? cy : cy + 1};
      } else {
        if (corner(&stop)) return stop;
        e += a - b;
      }
    }
    return {cy * width + cx, kRayEnd, 0};
  }
  std::int64_t crossings = e > 0 ? (e + b - 1) / b : 0;  // vertical edges before the next
  while (true) {
    if (cy == target_row) crossings = step_x > 0 ? target_col - cx : cx - target_col;
    if (crossings > 0) {
      const int to = cx + step_x * int(crossings);
      const int x = FirstClearBit(bits + std::size_t(cy) * words, cx + step_x, to);
      if (x >= 0) return {cy * width + x, kRayCrossX, step_x > 0 ? x : x + 1};
      cx = to;
    }
    if (cy == target_row) return {cy * width + cx, kRayEnd, 0};
    e -= crossings * b;  // in (-b, 0]: 0 when the ray passes a corner next
    std::int64_t carry;  // a - e at the start of the next row
    if (e == 0) {
      if (corner(&stop)) return stop;
      carry = b;
    } else {
      cy += step_y;
      if (!allowed(cx, cy)) return {cy * width + cx, kRayCrossY, step_y > 0 ? cy : cy + 1};
      carry = -e;
    }
    // The next row starts with e = a - carry, carry in (0, b]: it crosses q + ceil((r -
    // carry) / b) vertical edges.
    e = a - carry;
    crossings = q + (r > carry ? 1 : (r - carry == -b ? -1 : 0));
  }
}

// The ray `k` from the sensor's cell, as TraceExactRayRows() walks it.
inline RayStop WalkExactRayFromSensor(const std::uint64_t* bits, int words, int width,
                                      const ExactRayWalk& k, const SensorCell& s, int target_col,
                                      int target_row) {
  int cx = s.cell.col, cy = s.cell.row;
  if (k.step_y == 0 || k.step_x == 0) {  // along a row or a column: no corner on the way
    while (cx != target_col || cy != target_row) {
      cx += k.step_x;
      cy += k.step_y;
      if (!((bits[std::size_t(cy) * words + (cx >> 6)] >> (cx & 63)) & 1)) {
        if (k.step_y == 0) return {cy * width + cx, kRayCrossX, k.step_x > 0 ? cx : cx + 1};
        return {cy * width + cx, kRayCrossY, k.step_y > 0 ? cy : cy + 1};
      }
    }
    return {cy * width + cx, kRayEnd, 0};
  }
  return WalkExactRay(bits, words, width, k, cx, cy, k.e0, target_col, target_row);
}

// TraceExactRay() on a bitset of allowed cells (rows `words` words apart): the same stops,
// faster. The ray carries TraceExactRay's comparison as an error term e = ey - ex (> 0: the
// vertical edge comes first), which a vertical edge crossed lowers by b and a horizontal one
// raises by a, so no step multiplies. A ray that crosses four vertical edges or more between
// two horizontal ones (q = a / b >= 4) takes a row's part at a time, tested 64 cells a word:
// it crosses q or q + 1 of them in each row, as the remainder it carries says.
inline RayStop TraceExactRayRows(const std::uint64_t* bits, int words, int width,
                                 const SensorCell& s, int target_col, int target_row) {
  return WalkExactRayFromSensor(bits, words, width, ExactRayWalk(s, target_col, target_row), s,
                                target_col, target_row);
}

// The blocks of kBlockCells x kBlockCells cells whose cells are all allowed, as bitset rows: bit
// bc % 64 of word bc / 64 of block row br (rows `words` words apart) is 1 when every cell of
// block (br, bc), rows kBlockCells br .. and columns kBlockCells bc .., lies in the map and is
// allowed.
inline constexpr int kBlockShift = 3;
inline constexpr int kBlockCells = 1 << kBlockShift;
struct BlockView {
  int rows = 0, cols = 0, words = 0;
  const std::uint64_t* bits = nullptr;

  bool Full(int bc, int br) const {
    return bc >= 0 && br >= 0 && bc < cols && br < rows &&
           ((bits[std::size_t(br) * words + (bc >> 6)] >> (bc & 63)) & 1);
  }
};

// The full blocks of a width x height bitset of allowed cells (rows `words` words apart) whose
// set bits all lie in rows [row_begin, row_end), into `blocks`; returns their view.
BlockView FullBlocks(const std::uint64_t* bits, int words, int width, int height, int row_begin,
                     int row_end, std::vector<std::uint64_t>* blocks);

// TraceExactRayRows() with the full blocks of its bitset (FullBlocks()): the same stops. A
// diagonal ray that crosses fewer than four vertical edges between two horizontal ones (q < 4,
// the walk a cell at a time) crosses the full blocks from the sensor's on a block at a time, as
// TraceExactRay() would cross their cells (none of them can stop it; at a block corner the three
// blocks beyond it must be full), then walks on cell by cell from its last cell before the first
// block that is not full or holds its target, the error term worked out for that cell.
inline RayStop TraceExactRayBlocks(const std::uint64_t* bits, int words, int width,
                                   const BlockView& blocks, const SensorCell& s, int target_col,
                                   int target_row) {
  const ExactRayWalk k(s, target_col, target_row);
  int bx = s.cell.col >> kBlockShift, by = s.cell.row >> kBlockShift;
  const int tbx = target_col >> kBlockShift, tby = target_row >> kBlockShift;
  const auto open = [&](int x, int y) { return blocks.Full(x, y) && (x != tbx || y != tby); };
  if (k.step_x == 0 || k.step_y == 0 || k.q >= 4 || !open(bx, by))
    return WalkExactRayFromSensor(bits, words, width, k, s, target_col, target_row);
  // Distances (fixed point, along each axis) from the sensor to the block's next edges.
  constexpr std::int64_t kBlock = std::int64_t(kFixedOne) << kBlockShift;
  std::int64_t nx = k.step_x > 0 ? (bx + 1) * kBlock - s.x : s.x - bx * kBlock;
  std::int64_t ny = k.step_y > 0 ? (by + 1) * kBlock - s.y : s.y - by * kBlock;
  const auto last = [](int block, int step) {  // the block's last cell along a step
    return step > 0 ? (block << kBlockShift) + kBlockCells - 1 : block << kBlockShift;
  };
  while (true) {
    const std::int64_t ex = nx * k.ady, ey = ny * k.adx;  // the block edge crossed first
    int cx, cy;
    if (ex < ey) {
      if (open(bx + k.step_x, by)) {
        bx += k.step_x;
        nx += kBlock;
        continue;
      }
      // The horizontal cell edges crossed before the vertical block edge: j >= 0 with
      // (ny0 + kFixedOne j) |dx| < ex.
      const std::int64_t before = ex - k.ny0 * k.adx;
      cx = last(bx, k.step_x);
      cy = s.cell.row + k.step_y * int(before > 0 ? (before + k.a - 1) / k.a : 0);
    } else if (ey < ex) {
      if (open(bx, by + k.step_y)) {
        by += k.step_y;
        ny += kBlock;
        continue;
      }
      const std::int64_t before = ey - k.nx0 * k.ady;
      cx = s.cell.col + k.step_x * int(before > 0 ? (before + k.b - 1) / k.b : 0);
      cy = last(by, k.step_y);
    } else {  // through a block corner: the three blocks beyond it
      if (open(bx + k.step_x, by + k.step_y) && blocks.Full(bx + k.step_x, by) &&
          blocks.Full(bx, by + k.step_y)) {
        bx += k.step_x;
        by += k.step_y;
        nx += kBlock;
        ny += kBlock;
        continue;
      }
      cx = last(bx, k.step_x);
      cy = last(by, k.step_y);
    }
    return WalkExactRay(bits, words, width, k, cx, cy, k.ErrorAt(s, cx, cy), target_col,
                        target_row);
  }
}

// The point (map cells) where the ray from `s` to the centre of border cell (target_col,
// target_row) ended at `stop`.
inline Vec2 RayStopPoint(const SensorCell& s, int target_col, int target_row, const RayStop& stop) {
  const Vec2 sensor(double(s.x) / kFixedOne, double(s.y) / kFixedOne);
  const Vec2 target(target_col + 0.5, target_row + 0.5);
  const Vec2 d = target - sensor;
  switch (stop.kind) {
    case kRayCrossX:
    case kRayCorner:
      return {double(stop.line), sensor.y() + (stop.line - sensor.x()) / d.x() * d.y()};
    case kRayCrossY:
      return {sensor.x() + (stop.line - sensor.y()) / d.y() * d.x(), double(stop.line)};
    default:
      return target;
  }
}

}  // namespace freespace
