// The conventional inverse sensor model of OpenClBackend (the paper's baseline), the host side
// of kernels/rays.cl: CastRays() uploads the rays and runs rays_cast, which sums every ray's
// log-odds into the per-cell delta; FuseRays() adds the deltas into the map (rays_fuse).
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "backend_internal.hpp"
#include "opencl/backend.hpp"

namespace freespace {
namespace {

using opencl::Retained;
using opencl::RoundUp;
using opencl::SetArg;

// The kernels' parameters, in the order of their signatures in kernels/rays.cl.
namespace rays_cast_arg {
constexpr cl_uint kJob = 0;
constexpr cl_uint kDelta = 1;
}  // namespace rays_cast_arg

namespace rays_fuse_arg {
constexpr cl_uint kMap = 0;
constexpr cl_uint kDelta = 1;
constexpr cl_uint kRowBegin = 2;
constexpr cl_uint kRowEnd = 3;
}  // namespace rays_fuse_arg

}  // namespace

void OpenClBackend::BindRaysArgs() {
  SetArg(rays_cast_.get(), rays_cast_arg::kDelta, delta_.get());
  for (int k = 0; k < 2; ++k) {
    SetArg(rays_fuse_[k].get(), rays_fuse_arg::kMap, map_[k].get());
    SetArg(rays_fuse_[k].get(), rays_fuse_arg::kDelta, delta_.get());
  }
}

void OpenClBackend::BindRaysJob() { SetArg(rays_cast_.get(), rays_cast_arg::kJob, job_.get()); }

void OpenClBackend::CastRays(const RayJob& job) {
  if (crew_) crew_->Wake();
  Flush();
  const int n = std::max(job.ray_count, 0);
  if (n == 0) return;
  const std::size_t ints = 8 + 2 * std::size_t(n);
  std::int32_t* staging = Staging(ints);
  const std::int32_t header[8] = {n, job.origin_col, job.origin_row, 0, 0, 0, 0, 0};
  std::memcpy(staging, header, sizeof header);
  std::memcpy(staging + 8, job.ends, 2 * std::size_t(n) * 4);
  opencl::Event begin, end;
  Upload(ints, &begin);
  const std::size_t global = RoundUp(std::size_t(n), edge_local_);
  Launch(rays_cast_.get(), 1, &global, &edge_local_, end.out());
  SetStage(kRasterStage, std::move(begin), std::move(end));
}

void OpenClBackend::FuseRays(int row_begin, int row_end) {
  Flush();
  const int r0 = std::max(row_begin, 0), r1 = std::min(row_end, params_.height);
  if (r0 >= r1) return;
  const cl_kernel kernel = rays_fuse_[current_].get();
  levels_valid_ = false;
  known_[current_] = known_[current_].Hull({r0, r1});
  SetArg(kernel, rays_fuse_arg::kRowBegin, cl_int(r0));
  SetArg(kernel, rays_fuse_arg::kRowEnd, cl_int(r1));
  opencl::Event event;
  RowsLaunch(kernel, r1 - r0, event.out());
  opencl::Event again = Retained(event.get());
  SetStage(kFuseStage, std::move(event), std::move(again));
}

}  // namespace freespace
