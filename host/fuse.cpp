// Kernel stage 2 on the host: Bayes fusion in fixed-point log-odds with clamping. Mirrors
// kernels/fuse.cl. Each cell gets at most one update per scan because stage 1 wrote one value
// per cell.
#include <tbb/parallel_for.h>

#include <algorithm>

#include "host/host_backend.hpp"

namespace freespace {

namespace {

FREESPACE_ROW_LOOP void FuseRow(const std::uint8_t* __restrict update, LogOdds* __restrict map,
                                int width, LogOdds l_free, LogOdds l_occupied, LogOdds l_min,
                                LogOdds l_max) {
  for (int c = 0; c < width; ++c) {
    const int delta =
        update[c] == kUpdateFree ? l_free : (update[c] == kUpdateOccupied ? l_occupied : 0);
    map[c] = LogOdds(std::clamp(int(map[c]) + delta, int(l_min), int(l_max)));
  }
}

}  // namespace

void HostBackend::Fuse(int row_begin, int row_end) {
  const int r0 = std::max(row_begin, 0);
  const int r1 = std::min(row_end, params_.height);
  if (r0 >= r1) return;
  known_ = known_.Hull({r0, r1});
  const int width = params_.width;
  const KernelParams p = params_;
  const std::uint8_t* update = update_.data();
  LogOdds* map = map_.data();
  arena_.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int>(r0, r1, 16), [=](const tbb::blocked_range<int>& rows) {
          for (int r = rows.begin(); r != rows.end(); ++r) {
            const std::size_t at = std::size_t(r) * width;
            FuseRow(update + at, map + at, width, p.l_free, p.l_occupied, p.l_min, p.l_max);
          }
        });
  });
}

}  // namespace freespace
