// Kernel stage 4 on the host: the "in-sight edges" border-ray scan (paper IV.A, algorithm
// "In-sight Sorted Edges Detection"). Mirrors kernels/insight.cl.
//
// One Bresenham ray per border cell (2H + 2W rays, labels in BorderCell order) from the
// vehicle cell; each stops at its first not-free cell. Each ray writes its own label's stop
// cell, so the rays can run in any order; C_Edge, the distinct stop cells in the order of their
// smallest label, is then collected in label order (CollectEdges, src/backend.hpp).
//
// The rays visit exactly the cells of host::CastRay: every step moves one cell along the ray's
// major axis (a column on a shallow ray, a row on a steep one) and takes its offset on the
// other axis in closed form (host::RaySlope), so no step waits for the decision of the one
// before. Rays close to a row's direction take their cells a run (one row's part of the ray)
// at a time.
#include <tbb/parallel_for.h>

#include <algorithm>

#include "host/host_backend.hpp"

namespace freespace {
namespace {

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
      const int x = FirstClearBit(rows + std::size_t(y) * words, x0 + sx * k, x0 + sx * k_end);
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

// A ray of n steps (major_x, major_y) with d <= n steps (minor_x, minor_y) in all, the minor
// offset of each step from host::RaySlope.
std::int32_t StepRay(const std::uint64_t* rows, int words, int width, int x0, int y0, int n, int d,
                     int major_x, int major_y, int minor_x, int minor_y) {
  if (n == 0) return y0 * width + x0;
  const std::uint64_t slope = host::RaySlope(n, d);
  std::uint64_t sum = 0x80000000u;  // host::RayMinorStep(slope, 0), summed up step by step
  for (int k = 1; k <= n; ++k) {
    sum += slope;
    const int m = int(sum >> 32);
    const int x = x0 + major_x * k + minor_x * m, y = y0 + major_y * k + minor_y * m;
    if (!((rows[std::size_t(y) * words + (x >> 6)] >> (x & 63)) & 1)) return y * width + x;
  }
  return (y0 + major_y * n + minor_y * d) * width + x0 + major_x * n + minor_x * d;
}

// The stop cell of the ray from (x0, y0) over dx = |x1 - x0|, dy = |y1 - y0| cells in
// directions (sx, sy): the first cell after the start whose bit in the free bitset (rows of
// `words` words) is 0, or the end cell. Shallow rays (dx >= dy) step along x, steep ones along y.
std::int32_t Ray(const std::uint64_t* rows, int words, int width, int x0, int y0, int dx, int dy,
                 int sx, int sy) {
  // Rays within about 14 degrees of a row: runs of 4 cells or more, a run at a time.
  if (dy > 0 && dx >= 4 * dy) return RunRay(rows, words, width, x0, y0, dx, dy, sx, sy);
  if (dx >= dy) return StepRay(rows, words, width, x0, y0, dx, dy, sx, 0, 0, sy);
  return StepRay(rows, words, width, x0, y0, dy, dx, 0, sy, sx, 0);
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

void HostBackend::InSightExact(const SensorCell& sensor, std::vector<RayStop>* stops,
                               std::vector<CellIndex>* edges) {
  const int width = params_.width, height = params_.height, nw = words();
  const int labels = BorderLabelCount(height, width);
  stops->resize(std::size_t(labels));
  const std::uint64_t* rows = mask_.data();
  const BlockView blocks =
      FullBlocks(rows, nw, width, height, mask_rows_.begin, mask_rows_.end, &mask_blocks_);
  std::int32_t* stop = stop_.data();
  RayStop* out = stops->data();
  arena_.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, labels, 32), [&](const tbb::blocked_range<int>& range) {
          for (int l = range.begin(); l != range.end(); ++l) {
            const CellIndex target = BorderCell(l, height, width);
            out[l] = TraceExactRayBlocks(rows, nw, width, blocks, sensor, target.col, target.row);
            stop[l] = out[l].cell;
          }
        });
  });
  CollectEdges(stop, labels, width, edge_seen_.data(), edges);
}

}  // namespace freespace
