// HostBackend: construction, buffers and the copies in and out. The stages themselves are in
// rasterize.cpp, fuse.cpp, classify.cpp, insight.cpp and shift.cpp beside this file.
#include "host_backend.hpp"

#include <algorithm>
#include <climits>
#include <cstring>

namespace freespace {

HostBackend::HostBackend(const KernelParams& params, int threads)
    : Backend(params),
      arena_(threads > 0 ? threads : tbb::task_arena::automatic),
      map_(cells(), 0),
      map_scratch_(cells(), 0),
      update_(cells(), kUpdateNone),
      level_(cells(), 0),
      pass_a_(cells(), 0),
      pass_b_(cells(), 0),
      free_(cells(), 0),
      label_(cells(), INT32_MAX),
      stop_(BorderLabelCount(params.height, params.width), 0),
      delta_(cells(), 0) {
  arena_.initialize();
}

void HostBackend::Clear() {
  std::fill(map_.begin(), map_.end(), LogOdds{0});
  std::fill(free_.begin(), free_.end(), std::uint8_t{0});
}

void HostBackend::ReadLogOdds(LogOdds* dst) { std::memcpy(dst, map_.data(), cells() * 2); }
void HostBackend::WriteLogOdds(const LogOdds* src) { std::memcpy(map_.data(), src, cells() * 2); }
void HostBackend::ReadUpdateMask(std::uint8_t* dst) { std::memcpy(dst, update_.data(), cells()); }
void HostBackend::WriteUpdateMask(const std::uint8_t* src) {
  std::memcpy(update_.data(), src, cells());
}
void HostBackend::ReadFree(std::uint8_t* dst) { std::memcpy(dst, free_.data(), cells()); }
void HostBackend::ReadRayDelta(std::int32_t* dst) {
  std::memcpy(dst, delta_.data(), cells() * sizeof(std::int32_t));
}
void HostBackend::WriteFree(const std::uint8_t* src) { std::memcpy(free_.data(), src, cells()); }

}  // namespace freespace
