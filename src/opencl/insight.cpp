// Kernel stage 4 of OpenClBackend, the host side of kernels/insight.cl: the border rays from the
// vehicle cell (insight_cast, one work-item per label; split over devices, insight_claim, one
// work-item per device claiming chunks of labels), the read-back of their stop cells, the wait
// for it, and C_Edge from the stop cells on the host (CollectEdges, as the host backend does).
#include "backend_internal.hpp"
#include "opencl/backend.hpp"

namespace freespace {
namespace {

using opencl::Check;
using opencl::Retained;
using opencl::SetArg;

// The kernels' parameters, in the order of their signatures in kernels/insight.cl.
namespace insight_cast_arg {
constexpr cl_uint kFree = 0;
constexpr cl_uint kStop = 1;
constexpr cl_uint kVehicleCol = 2;
constexpr cl_uint kVehicleRow = 3;
}  // namespace insight_cast_arg

namespace insight_claim_arg {
constexpr cl_uint kFree = 0;
constexpr cl_uint kStop = 1;
constexpr cl_uint kVehicleCol = 2;
constexpr cl_uint kVehicleRow = 3;
constexpr cl_uint kNext = 4;
constexpr cl_uint kChunk = 5;
}  // namespace insight_claim_arg

// insight_claim (the in-sight scan split over devices): about this many chunks of labels per
// device, so that the devices even out within a chunk's time (at 1500 x 1500 cells, 94 rays:
// a few microseconds) for a few dozen claims of the shared counter.
constexpr std::size_t kClaimsPerDevice = 32;

}  // namespace

void OpenClBackend::BindInSightArgs() {
  SetArg(insight_cast_.get(), insight_cast_arg::kFree, free_.get());
  SetArg(insight_cast_.get(), insight_cast_arg::kStop, stop_.get());
  const cl_kernel claim = insight_claim_.get();
  const std::size_t chunks = kClaimsPerDevice * devices_;
  SetArgAll(claim, insight_claim_arg::kFree, free_.get());
  SetArgAll(claim, insight_claim_arg::kStop, stop_.get());
  SetArgAll(claim, insight_claim_arg::kNext, claims_.get());
  SetArgAll(claim, insight_claim_arg::kChunk, cl_int((labels() + chunks - 1) / chunks));
}

void OpenClBackend::InSight(CellIndex vehicle, std::vector<CellIndex>* edges) {
  if (crew_) crew_->Wake();
  Flush();
  opencl::Event begin, end;
  if (devices_ > 1) {
    // One work-item per device, each claiming chunks of labels until none is left (the rays'
    // lengths differ by side and by map, the devices' speeds by what else runs); the claim
    // counter starts at 0 (the fill runs at SplitRun's finish of queue_).
    const cl_kernel claim = insight_claim_.get();
    SetArgAll(claim, insight_claim_arg::kVehicleCol, cl_int(vehicle.col));
    SetArgAll(claim, insight_claim_arg::kVehicleRow, cl_int(vehicle.row));
    Fill(claims_.get(), 4);
    SplitRun(devices_, [&](int, int d, cl_event* e) {
      const std::size_t one = 1;
      Launch(QueueOf(d), Twin(claim, d), 1, &one, &one, e);
    });
    begin = Retained(split_parts_[0].get());
  } else {
    const cl_kernel cast = insight_cast_.get();
    SetArg(cast, insight_cast_arg::kVehicleCol, cl_int(vehicle.col));
    SetArg(cast, insight_cast_arg::kVehicleRow, cl_int(vehicle.row));
    Launch(cast, 1, &cast_global_, &cast_local_, begin.out());
  }
  Check(clEnqueueReadBuffer(queue_.get(), stop_.get(), CL_FALSE, 0, stop_host_.size() * 4,
                            stop_host_.data(), 0, nullptr, end.out()),
        "clEnqueueReadBuffer");
  WaitForResult(end.get());
  if (crew_) crew_->Rest();  // until the next scan
  SetStage(kInSightStage, std::move(begin), std::move(end));
  CollectEdges(stop_host_.data(), int(stop_host_.size()), params_.width, edge_seen_.data(), edges);
}

}  // namespace freespace
