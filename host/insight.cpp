// Kernel stage 4 on the host: the "in-sight edges" border-ray scan (paper IV.A, algorithm
// "In-sight Sorted Edges Detection"). Mirrors kernels/insight.cl.
//
// One Bresenham ray per border cell (2H + 2W rays, labels in BorderCell order) from the
// vehicle cell; each stops at its first not-free cell. Each ray writes its own label's stop
// cell, so the rays can run in any order; C_Edge, the distinct stop cells in the order of their
// smallest label, is then collected in label order (CollectEdges, src/backend.hpp).
//
// The rays visit exactly the cells of host::CastRay, with one loop per major axis: on a shallow
// ray every step moves one column, on a steep one one row, so each step does one decision and
// one bit test, and the row's words stay in a pointer. Rays close to a row's direction take
// their cells a run (one row's part of the ray) at a time.
#include <tbb/parallel_for.h>

#include <algorithm>

#include "host_backend.hpp"

namespace freespace {
namespace {

// Bresenham from (x0, y0) over dx = |x1 - x0|, dy = |y1 - y0| cells in directions (sx, sy):
// the first cell after the start whose bit in the free bitset (rows of `words` words) is 0, or
// the end cell. The same cells as host::CastRay: there, a shallow ray (dx >= dy) steps x on
// every iteration and y where 2 err <= dx; a steep one steps y on every iteration and x where
// 2 err >= -dy.
// The first cell u in [from, to] (from <= to: upwards; from > to: downwards) whose bit in
// `line` is 0, or -1.
int FirstNotFree(const std::uint64_t* line, int from, int to) {
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

// A shallow ray (dx >= dy > 0) a row at a time. Step k (0 .. dx) of the ray lies
// floor((2 dy k + dx) / (2 dx)) rows off the start, so the cells of row offset m are the steps
// K(m) = ceil(dx (2m - 1) / (2 dy)) to K(m + 1) - 1, and K(m + 1) - K(m) is q or q + 1 with
// 2 dx = q 2 dy + r. Each run is tested 64 cells at a time.
std::int32_t RunRay(const std::uint64_t* rows, int words, int width, int x0, int y0, int dx, int dy,
                    int sx, int sy) {
  const int q = dx / dy, r = (2 * dx) % (2 * dy);
  int k_next = (dx + 2 * dy - 1) / (2 * dy);  // K(1)
  int rem = (dx + 2 * dy - 1) % (2 * dy);
  int k = 1;  // the vehicle's own cell (k = 0) never stops a ray
  int y = y0;
  while (true) {
    const int k_end = std::min(k_next - 1, dx);
    if (k <= k_end) {
      const int x = FirstNotFree(rows + std::size_t(y) * words, x0 + sx * k, x0 + sx * k_end);
      if (x >= 0) return y * width + x;
    }
    if (k_end == dx) return y * width + x0 + sx * dx;
    k = k_end + 1;
    y += sy;
    k_next += q;
    rem += r;
    if (rem >= 2 * dy) {
      rem -= 2 * dy;
      ++k_next;
    }
  }
}

std::int32_t Ray(const std::uint64_t* rows, int words, int width, int x0, int y0, int dx, int dy,
                 int sx, int sy) {
  // Rays within about 14 degrees of a row: runs of 4 cells or more, a run at a time.
  if (dy > 0 && dx >= 4 * dy) return RunRay(rows, words, width, x0, y0, dx, dy, sx, sy);
  int err = dx - dy, x = x0, y = y0;
  const std::ptrdiff_t row_step = std::ptrdiff_t(sy) * words;
  const std::uint64_t* line = rows + std::size_t(y0) * words;
  if (dx >= dy) {
    for (int k = 0; k < dx; ++k) {
      const bool y_step = 2 * err <= dx;
      err -= dy;
      x += sx;
      if (y_step) {
        err += dx;
        y += sy;
        line += row_step;
      }
      if (!((line[x >> 6] >> (x & 63)) & 1)) break;
    }
  } else {
    for (int k = 0; k < dy; ++k) {
      const bool x_step = 2 * err >= -dy;
      err += dx;
      y += sy;
      line += row_step;
      if (x_step) {
        err -= dy;
        x += sx;
      }
      if (!((line[x >> 6] >> (x & 63)) & 1)) break;
    }
  }
  return y * width + x;
}

}  // namespace

void HostBackend::InSight(CellIndex vehicle, std::vector<CellIndex>* edges) {
  const int width = params_.width, height = params_.height;
  const int labels = BorderLabelCount(height, width);
  const int nw = words();
  const std::uint64_t* rows = free_.data();
  std::int32_t* stop = stop_.data();
  arena_.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, labels, 32), [&](const tbb::blocked_range<int>& range) {
          for (int l = range.begin(); l != range.end(); ++l) {
            const CellIndex target = BorderCell(l, height, width);
            const int dx = target.col - vehicle.col, dy = target.row - vehicle.row;
            stop[l] = Ray(rows, nw, width, vehicle.col, vehicle.row, dx < 0 ? -dx : dx,
                          dy < 0 ? -dy : dy, dx < 0 ? -1 : 1, dy < 0 ? -1 : 1);
          }
        });
  });
  CollectEdges(stop, labels, width, edge_seen_.data(), edges);
}

}  // namespace freespace
