// Kernel stage 4 on the host: the "in-sight edges" border-ray scan (paper IV.A, algorithm
// "In-sight Sorted Edges Detection"). Mirrors kernels/insight.cl.
//
// One Bresenham ray per border cell (2H + 2W rays, labels in BorderCell order) from the
// vehicle cell; each stops at its first not-free cell. Where several rays stop at one cell the
// smallest label wins (T keeps the minimum), so C_Edge, the stop cells sorted by their label,
// is the same whatever order the rays run in.
#include <tbb/parallel_for.h>

#include <climits>

#include "host_backend.hpp"

namespace freespace {

void HostBackend::InSight(CellIndex vehicle, std::vector<CellIndex>* edges) {
  const int width = params_.width, height = params_.height;
  const int labels = BorderLabelCount(height, width);
  const std::uint64_t* free = free_.data();
  const int nw = words();
  const auto is_free = [free, nw](int x, int y) {
    return (free[std::size_t(y) * nw + (x >> 6)] >> (x & 63)) & 1;
  };
  std::int32_t* stop = stop_.data();
  arena_.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<int>(0, labels, 32), [&](const tbb::blocked_range<int>& range) {
          for (int l = range.begin(); l != range.end(); ++l) {
            const CellIndex target = BorderCell(l, height, width);
            stop[l] =
                host::CastRay(is_free, width, vehicle.col, vehicle.row, target.col, target.row);
          }
        });
  });
  // T: the smallest label per stop cell. Labels run upwards, so the first one to arrive wins.
  std::int32_t* t = label_.data();
  for (int l = 0; l < labels; ++l) {
    if (t[stop[l]] == INT32_MAX) t[stop[l]] = l;
  }
  edges->clear();
  for (int l = 0; l < labels; ++l) {
    if (t[stop[l]] == l) edges->push_back({stop[l] / width, stop[l] % width});
  }
  for (int l = 0; l < labels; ++l) t[stop[l]] = INT32_MAX;
}

}  // namespace freespace
