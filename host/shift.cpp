// The integer map shift of the vehicle-on-a-circle alignment (paper eqs. 4, 5) on the host.
// Mirrors kernels/shift.cl: new(r, c) = old(r + dy, c + dx), unknown where there is no old
// cell. Written to a second buffer and swapped, so rows never overlap. Only the rows that can
// hold a known cell, before or after, are written (RowSpan in src/backend.hpp).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "host/host_backend.hpp"

namespace freespace {

void HostBackend::Shift(int dx, int dy) {
  if (dx == 0 && dy == 0) return;
  const int width = params_.width, height = params_.height;
  if (std::abs(dx) >= width || std::abs(dy) >= height) {
    std::fill(map_.begin(), map_.end(), LogOdds{0});
    known_ = {};
    return;
  }
  // Rows outside known_ are all unknown, so the shifted map's known rows are known_ moved, and
  // every other row of the result is unknown too. The scratch's rows outside that and outside
  // scratch_known_ are unknown already; the loop writes the rest (copying unknown rows where
  // they lie between).
  const RowSpan next = known_.Shifted(dy, height);
  const RowSpan rows = next.Hull(scratch_known_);
  // Destination columns [c0, c1) come from source columns [c0 + dx, c1 + dx).
  const int c0 = std::max(0, -dx), c1 = std::min(width, width - dx);
  if (!rows.empty()) {
    arena_.execute([&] {
      tbb::parallel_for(tbb::blocked_range<int>(rows.begin, rows.end, 32),
                        [&](const tbb::blocked_range<int>& range) {
                          for (int r = range.begin(); r != range.end(); ++r) {
                            LogOdds* dst = map_scratch_.data() + std::size_t(r) * width;
                            const int sr = r + dy;
                            if (sr < 0 || sr >= height) {
                              std::memset(dst, 0, std::size_t(width) * sizeof(LogOdds));
                              continue;
                            }
                            const LogOdds* src = map_.data() + std::size_t(sr) * width;
                            std::memset(dst, 0, std::size_t(c0) * sizeof(LogOdds));
                            std::memcpy(dst + c0, src + c0 + dx,
                                        std::size_t(c1 - c0) * sizeof(LogOdds));
                            std::memset(dst + c1, 0, std::size_t(width - c1) * sizeof(LogOdds));
                          }
                        });
    });
  }
  map_.swap(map_scratch_);
  scratch_known_ = known_;
  known_ = next;
}

}  // namespace freespace
