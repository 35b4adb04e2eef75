// The integer map shift of OpenClBackend (paper III, eqs. 4, 5), the host side of
// kernels/shift.cl. Shift() only records it: the Fuse() of the scan's rows then runs it inside
// the row pass (rasterize.cpp), and any other call first runs it on its own (FlushShift(),
// shift_map from one map buffer into the other).
#include <cstdlib>

#include "backend_internal.hpp"
#include "opencl/backend.hpp"

namespace freespace {
namespace {

using opencl::SetArg;

// The kernel's parameters, in the order of its signature in kernels/shift.cl.
namespace shift_map_arg {
constexpr cl_uint kSrc = 0;
constexpr cl_uint kDst = 1;
constexpr cl_uint kDx = 2;
constexpr cl_uint kDy = 3;
}  // namespace shift_map_arg

}  // namespace

void OpenClBackend::BindShiftArgs() {
  for (int k = 0; k < 2; ++k) {
    SetArg(shift_[k].get(), shift_map_arg::kSrc, map_[k].get());
    SetArg(shift_[k].get(), shift_map_arg::kDst, map_[1 - k].get());
  }
}

void OpenClBackend::Shift(int dx, int dy) {
  if (crew_) crew_->Wake();  // the split stages of this scan follow
  Flush();
  if (dx == 0 && dy == 0) return;
  if (std::abs(dx) >= params_.width || std::abs(dy) >= params_.height) {
    levels_valid_ = false;
    Fill(map_[current_].get(), layout_.cells * sizeof(LogOdds));
    known_[current_] = {};
    return;
  }
  // Deferred: two shifts in a row do not compose (the first one clips), so a second one
  // flushes the first.
  shift_pending_ = true;
  pending_dx_ = dx;
  pending_dy_ = dy;
}

void OpenClBackend::FlushShift() {
  if (!shift_pending_) return;
  shift_pending_ = false;
  const cl_kernel kernel = shift_[current_].get();
  SetArg(kernel, shift_map_arg::kDx, cl_int(pending_dx_));
  SetArg(kernel, shift_map_arg::kDy, cl_int(pending_dy_));
  RowsLaunch(kernel, params_.height, nullptr);
  known_[1 - current_] = known_[current_].Shifted(pending_dy_, params_.height);
  current_ = 1 - current_;
  levels_valid_ = false;
}

}  // namespace freespace
