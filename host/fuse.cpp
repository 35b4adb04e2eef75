// Kernel stage 2 on the host: Bayes fusion in fixed-point log-odds with clamping. Mirrors
// kernels/fuse.cl. Each cell gets at most one update per scan because stage 1 wrote one value
// per cell.
#include <tbb/parallel_for.h>

#include <algorithm>

#include "host_backend.hpp"

namespace freespace {

void HostBackend::Fuse(int row_begin, int row_end) {
  const int r0 = std::max(row_begin, 0);
  const int r1 = std::min(row_end, params_.height);
  if (r0 >= r1) return;
  const int width = params_.width;
  const int l_free = params_.l_free, l_occ = params_.l_occupied;
  const int l_min = params_.l_min, l_max = params_.l_max;
  arena_.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int>(r0, r1, 16), [&](const tbb::blocked_range<int>& rows) {
          for (int r = rows.begin(); r != rows.end(); ++r) {
            const std::uint8_t* u = update_.data() + std::size_t(r) * width;
            LogOdds* m = map_.data() + std::size_t(r) * width;
            for (int c = 0; c < width; ++c) {
              const int delta =
                  u[c] == kUpdateFree ? l_free : (u[c] == kUpdateOccupied ? l_occ : 0);
              m[c] = LogOdds(std::clamp(int(m[c]) + delta, l_min, l_max));
            }
          }
        });
  });
}

}  // namespace freespace
