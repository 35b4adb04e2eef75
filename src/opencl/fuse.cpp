// Kernel stage 2 of OpenClBackend, the host side of kernels/fuse.cl: the fusion of the update
// mask into the map. When the deferred row pass of stage 1 covers the same rows, the fusion (and
// a deferred map shift) runs inside it instead (rasterize.cpp), one pass over the map; fuse runs
// on its own otherwise.
#include <algorithm>

#include "backend_internal.hpp"
#include "opencl/backend.hpp"

namespace freespace {
namespace {

using opencl::Retained;
using opencl::SetArg;

// The kernel's parameters, in the order of its signature in kernels/fuse.cl.
namespace fuse_arg {
constexpr cl_uint kMap = 0;
constexpr cl_uint kUpdate = 1;
constexpr cl_uint kRowBegin = 2;
constexpr cl_uint kRowEnd = 3;
}  // namespace fuse_arg

}  // namespace

void OpenClBackend::BindFuseArgs() {
  for (int k = 0; k < 2; ++k) {
    SetArg(fuse_[k].get(), fuse_arg::kMap, map_[k].get());
    SetArg(fuse_[k].get(), fuse_arg::kUpdate, update_.get());
  }
}

void OpenClBackend::Fuse(int row_begin, int row_end) {
  if (crew_) crew_->Wake();
  const int r0 = std::max(row_begin, 0), r1 = std::min(row_end, params_.height);
  if (rows_pending_ && r0 == pending_begin_ && r1 == pending_end_) {
    FlushRowsWithFusion();
    return;
  }
  Flush();
  if (r0 >= r1) return;
  const cl_kernel kernel = fuse_[current_].get();
  levels_valid_ = false;
  known_[current_] = known_[current_].Hull({r0, r1});
  SetArg(kernel, fuse_arg::kRowBegin, cl_int(r0));
  SetArg(kernel, fuse_arg::kRowEnd, cl_int(r1));
  opencl::Event event;
  RowsLaunch(kernel, r1 - r0, event.out());
  opencl::Event again = Retained(event.get());
  SetStage(kFuseStage, std::move(event), std::move(again));
}

}  // namespace freespace
