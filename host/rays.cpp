// The conventional inverse sensor model on the host (the paper's baseline, section V.B):
// one Bresenham ray per kept echo, every cell on it updated, as often as rays cross it.
// Mirrors kernels/rays.cl. Deltas are summed with atomic adds, then fused once per scan, so
// the result does not depend on the order the rays run in.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "host/host_backend.hpp"

namespace freespace {

void host::AccumulateRay(std::int32_t* delta, int width, int height, int x0, int y0, int x1, int y1,
                         int l_free, int l_occupied) {
  const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  int x = x0, y = y0;
  while (true) {
    const bool end = x == x1 && y == y1;
    if (x >= 0 && x < width && y >= 0 && y < height) {
      __atomic_fetch_add(&delta[y * width + x], end ? l_occupied : l_free, __ATOMIC_RELAXED);
    }
    if (end) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y += sy;
    }
  }
}

void HostBackend::CastRays(const RayJob& job) {
  const int width = params_.width, height = params_.height;
  const int l_free = params_.l_free, l_occ = params_.l_occupied;
  std::int32_t* delta = delta_.data();
  arena_.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, job.ray_count, 64),
                      [&](const tbb::blocked_range<int>& rays) {
                        for (int i = rays.begin(); i != rays.end(); ++i) {
                          host::AccumulateRay(delta, width, height, job.origin_col, job.origin_row,
                                              job.ends[2 * i], job.ends[2 * i + 1], l_free, l_occ);
                        }
                      });
  });
}

void HostBackend::FuseRays(int row_begin, int row_end) {
  const int r0 = std::max(row_begin, 0), r1 = std::min(row_end, params_.height);
  if (r0 >= r1) return;
  known_ = known_.Hull({r0, r1});
  const int width = params_.width, l_min = params_.l_min, l_max = params_.l_max;
  arena_.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(r0, r1, 16),
                      [&](const tbb::blocked_range<int>& rows) {
                        for (int r = rows.begin(); r != rows.end(); ++r) {
                          std::int32_t* __restrict d = delta_.data() + std::size_t(r) * width;
                          LogOdds* __restrict m = map_.data() + std::size_t(r) * width;
                          for (int c = 0; c < width; ++c) {
                            m[c] = LogOdds(std::clamp(int(m[c]) + d[c], l_min, l_max));
                            d[c] = 0;
                          }
                        }
                      });
  });
}

}  // namespace freespace
