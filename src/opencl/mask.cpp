// Stage 3b of OpenClBackend and the exact rays, the host side of kernels/mask.cl and of
// insight_exact in kernels/insight.cl: the per-scan veto (this scan's echo cells, a bitset
// built here and uploaded, out of the free mask), the polygon mask (the margin's sources from the
// map, then the mask a row per work-item), the exact border rays on it and their stops read back.
#include <algorithm>

#include "backend_internal.hpp"
#include "opencl/backend.hpp"

namespace freespace {
namespace {

static_assert(kMaxSensors == 16, "mask_rows takes the margin's views as two int16");

using opencl::Check;
using opencl::RoundUp;
using opencl::SetArg;

// The kernels' parameters, in the order of their signatures in kernels/mask.cl and insight.cl.
namespace mask_veto_arg {
constexpr cl_uint kFree = 0;
constexpr cl_uint kEcho = 1;
constexpr cl_uint kFirstRow = 2;
constexpr cl_uint kEndRow = 3;
}  // namespace mask_veto_arg

namespace mask_unconfirmed_arg {
constexpr cl_uint kMap = 0;
constexpr cl_uint kUnconfirmed = 1;
constexpr cl_uint kFirstRow = 2;
constexpr cl_uint kEndRow = 3;
}  // namespace mask_unconfirmed_arg

namespace mask_rows_arg {
constexpr cl_uint kFree = 0;
constexpr cl_uint kEcho = 1;
constexpr cl_uint kFaceNear = 2;
constexpr cl_uint kFaceSeen = 3;
constexpr cl_uint kUnconfirmed = 4;
constexpr cl_uint kMap = 5;
constexpr cl_uint kMask = 6;
constexpr cl_uint kFirstRow = 7;
constexpr cl_uint kEndRow = 8;
constexpr cl_uint kSpanBegin = 9;
constexpr cl_uint kSpanEnd = 10;
constexpr cl_uint kSensorCol = 11;
constexpr cl_uint kSensorRow = 12;
constexpr cl_uint kViewX = 13;
constexpr cl_uint kViewY = 14;
constexpr cl_uint kViewCount = 15;
}  // namespace mask_rows_arg

namespace insight_exact_arg {
constexpr cl_uint kMask = 0;
constexpr cl_uint kStops = 1;
constexpr cl_uint kSensorX = 2;
constexpr cl_uint kSensorY = 3;
constexpr cl_uint kSensorCol = 4;
constexpr cl_uint kSensorRow = 5;
}  // namespace insight_exact_arg

constexpr std::size_t kExactGroup = 64;
// Work-groups of the kernels with one work-item per row: one row on a CPU (which runs a group's
// items in turn), a few rows on a GPU. Fixed, so that PoCL builds each kernel for one size only.
constexpr std::size_t kCpuRowGroup = 1, kGpuRowGroup = 32;

}  // namespace

void OpenClBackend::SetUpMask() {
  mask_veto_ = MakeKernel("mask_veto");
  mask_unconfirmed_ = MakeKernel("mask_unconfirmed");
  mask_rows_ = MakeKernel("mask_rows");
  insight_exact_ = MakeKernel("insight_exact");
  const std::size_t words = std::size_t(BitWords()) * std::size_t(params_.height);
  auto buffer = [&](std::size_t bytes) {
    cl_int status = CL_SUCCESS;
    opencl::Mem mem(clCreateBuffer(device_->context(), CL_MEM_READ_WRITE, bytes, nullptr, &status));
    Check(status, "clCreateBuffer");
    return mem;
  };
  for (CellLayer* layer : {&echo_, &face_near_, &face_seen_}) {
    layer->bits = buffer(words * 8);
    Fill(layer->bits.get(), words * 8);
    layer->host.assign(words, 0);
    layer->cells.reserve(16384);
  }
  unconfirmed_bits_ = buffer(words * 8);
  mask_ = buffer(words * 8);
  exact_stops_ = buffer(labels() * 12);
  Fill(unconfirmed_bits_.get(), words * 8);
  Fill(mask_.get(), words * 8);
  exact_host_.assign(labels() * 3, 0);
  SetArg(mask_veto_.get(), mask_veto_arg::kFree, free_.get());
  SetArg(mask_veto_.get(), mask_veto_arg::kEcho, echo_.bits.get());
  SetArg(mask_unconfirmed_.get(), mask_unconfirmed_arg::kUnconfirmed, unconfirmed_bits_.get());
  SetArg(mask_rows_.get(), mask_rows_arg::kFree, free_.get());
  SetArg(mask_rows_.get(), mask_rows_arg::kEcho, echo_.bits.get());
  SetArg(mask_rows_.get(), mask_rows_arg::kFaceNear, face_near_.bits.get());
  SetArg(mask_rows_.get(), mask_rows_arg::kFaceSeen, face_seen_.bits.get());
  SetArg(mask_rows_.get(), mask_rows_arg::kUnconfirmed, unconfirmed_bits_.get());
  SetArg(mask_rows_.get(), mask_rows_arg::kMask, mask_.get());
  SetArg(insight_exact_.get(), insight_exact_arg::kMask, mask_.get());
  SetArg(insight_exact_.get(), insight_exact_arg::kStops, exact_stops_.get());
  exact_local_ = LocalSize(insight_exact_.get(), kExactGroup);
  row_local_ = bands_ ? kCpuRowGroup : kGpuRowGroup;
  for (const cl_kernel k : {mask_veto_.get(), mask_unconfirmed_.get(), mask_rows_.get()}) {
    row_local_ = LocalSize(k, row_local_);
  }
  exact_global_ = RoundUp(labels(), exact_local_);
  Finish();
}

void OpenClBackend::UploadCells(CellLayer* layer, const std::int32_t* cells, int count) {
  // The staging buffer may still be read by the last upload.
  if (layer->upload) {
    const cl_event last = layer->upload.get();
    Check(clWaitForEvents(1, &last), "clWaitForEvents");
  }
  const int width = params_.width, nw = BitWords();
  for (const std::int32_t c : layer->cells)
    layer->host[std::size_t(c / width) * nw + (c % width) / 64] = 0;
  RowSpan rows;
  layer->cells.assign(cells, cells + count);
  for (const std::int32_t c : layer->cells) {
    const int row = c / width;
    layer->host[std::size_t(row) * nw + (c % width) / 64] |= std::uint64_t{1} << ((c % width) % 64);
    rows = rows.Hull({row, row + 1});
  }
  // The rows that held cells and those that hold them now.
  const RowSpan upload = rows.Hull(layer->rows);
  layer->rows = rows;
  if (upload.empty()) return;
  const std::size_t offset = std::size_t(upload.begin) * nw * 8;
  const std::size_t bytes = std::size_t(upload.end - upload.begin) * nw * 8;
  Check(clEnqueueWriteBuffer(queue_.get(), layer->bits.get(), CL_FALSE, offset, bytes,
                             layer->host.data() + std::size_t(upload.begin) * nw, 0, nullptr,
                             layer->upload.out()),
        "clEnqueueWriteBuffer");
}

void OpenClBackend::SetEchoes(const std::int32_t* cells, int count) {
  UploadCells(&echo_, cells, count);
}

void OpenClBackend::SetFaces(const std::int32_t* near, int near_count, const std::int32_t* seen,
                             int seen_count) {
  UploadCells(&face_near_, near, near_count);
  UploadCells(&face_seen_, seen, seen_count);
}

void OpenClBackend::VetoEchoes(RowSpan rows, opencl::Event* end) {
  const RowSpan veto{std::max(rows.begin, echo_.rows.begin), std::min(rows.end, echo_.rows.end)};
  if (veto.empty()) return;
  SetArg(mask_veto_.get(), mask_veto_arg::kFirstRow, cl_int(veto.begin));
  SetArg(mask_veto_.get(), mask_veto_arg::kEndRow, cl_int(veto.end));
  const std::size_t global = RoundUp(std::size_t(veto.end - veto.begin), row_local_);
  Launch(mask_veto_.get(), 1, &global, &row_local_, end->out());
}

void OpenClBackend::Mask(const SensorCell& sensor, const MarginViews& views) {
  Flush();
  const int height = params_.height, h = params_.opening_radius, k = params_.margin_cells;
  const RowSpan stand{std::max(0, sensor.cell.row - h), std::min(height, sensor.cell.row + h + 1)};
  const RowSpan span = free_rows_.Hull(stand);
  const RowSpan write = span.Hull(mask_span_);
  mask_span_ = span;
  if (write.empty()) return;
  opencl::Event begin, end;
  const RowSpan sources = write.Widened(k, height);
  SetArg(mask_unconfirmed_.get(), mask_unconfirmed_arg::kMap, map_[current_].get());
  SetArg(mask_unconfirmed_.get(), mask_unconfirmed_arg::kFirstRow, cl_int(sources.begin));
  SetArg(mask_unconfirmed_.get(), mask_unconfirmed_arg::kEndRow, cl_int(sources.end));
  std::size_t global = RoundUp(std::size_t(sources.end - sources.begin), row_local_);
  Launch(mask_unconfirmed_.get(), 1, &global, &row_local_, begin.out());
  const cl_kernel rows = mask_rows_.get();
  SetArg(rows, mask_rows_arg::kMap, map_[current_].get());
  SetArg(rows, mask_rows_arg::kFirstRow, cl_int(write.begin));
  SetArg(rows, mask_rows_arg::kEndRow, cl_int(write.end));
  SetArg(rows, mask_rows_arg::kSpanBegin, cl_int(span.begin));
  SetArg(rows, mask_rows_arg::kSpanEnd, cl_int(span.end));
  SetArg(rows, mask_rows_arg::kSensorCol, cl_int(sensor.cell.col));
  SetArg(rows, mask_rows_arg::kSensorRow, cl_int(sensor.cell.row));
  cl_int16 view_x{}, view_y{};  // kMaxSensors == 16 lanes
  for (int i = 0; i < views.count; ++i) {
    view_x.s[i] = views.x[i];
    view_y.s[i] = views.y[i];
  }
  SetArg(rows, mask_rows_arg::kViewX, view_x);
  SetArg(rows, mask_rows_arg::kViewY, view_y);
  SetArg(rows, mask_rows_arg::kViewCount, cl_int(views.count));
  global = RoundUp(std::size_t(write.end - write.begin), row_local_);
  Launch(rows, 1, &global, &row_local_, end.out());
  SetStage(kMaskStage, std::move(begin), std::move(end));
}

void OpenClBackend::InSightExact(const SensorCell& sensor, std::vector<RayStop>* stops,
                                 std::vector<CellIndex>* edges) {
  Flush();
  opencl::Event begin, end;
  const cl_kernel exact = insight_exact_.get();
  SetArg(exact, insight_exact_arg::kSensorX, cl_int(sensor.x));
  SetArg(exact, insight_exact_arg::kSensorY, cl_int(sensor.y));
  SetArg(exact, insight_exact_arg::kSensorCol, cl_int(sensor.cell.col));
  SetArg(exact, insight_exact_arg::kSensorRow, cl_int(sensor.cell.row));
  Launch(exact, 1, &exact_global_, &exact_local_, begin.out());
  Check(clEnqueueReadBuffer(queue_.get(), exact_stops_.get(), CL_FALSE, 0, exact_host_.size() * 4,
                            exact_host_.data(), 0, nullptr, end.out()),
        "clEnqueueReadBuffer");
  WaitForResult(end.get());
  if (crew_) crew_->Rest();  // until the next scan
  SetStage(kInSightStage, std::move(begin), std::move(end));
  const std::size_t labels = exact_host_.size() / 3;
  stops->resize(labels);
  for (std::size_t l = 0; l < labels; ++l) {
    (*stops)[l] = {exact_host_[3 * l], exact_host_[3 * l + 1], exact_host_[3 * l + 2]};
    stop_host_[l] = exact_host_[3 * l];
  }
  CollectEdges(stop_host_.data(), int(stop_host_.size()), params_.width, edge_seen_.data(), edges);
}

void OpenClBackend::ReadMaskBits(int row_begin, int row_end, std::uint64_t* dst) {
  if (row_end <= row_begin) return;
  Flush();
  const std::size_t nw = std::size_t(BitWords());
  Check(clEnqueueReadBuffer(queue_.get(), mask_.get(), CL_TRUE, std::size_t(row_begin) * nw * 8,
                            std::size_t(row_end - row_begin) * nw * 8,
                            dst + std::size_t(row_begin) * nw, 0, nullptr, nullptr),
        "clEnqueueReadBuffer");
}

}  // namespace freespace
