// Kernel stage 1 of OpenClBackend, the host side of kernels/rasterize.cl: the job upload, then
// rasterize_edges (the GPU shape) and the row pass (rasterize_rows, or rasterize_bands on a CPU).
// The row pass is deferred until the next call shows whether it can fold in the fusion of its
// rows (stage 2) and a pending map shift: FlushRowsWithFusion(), which Fuse() calls. Split over
// devices, the row pass's bands are split into one part per device.
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "backend_internal.hpp"
#include "opencl/backend.hpp"

namespace freespace {
namespace {

using opencl::Check;
using opencl::Retained;
using opencl::RoundUp;
using opencl::SetArg;

// The kernels' parameters, in the order of their signatures in kernels/rasterize.cl.
namespace rasterize_edges_arg {
constexpr cl_uint kJob = 0;
constexpr cl_uint kToggles = 1;
constexpr cl_uint kOccupied = 2;
constexpr cl_uint kUpdate = 3;
}  // namespace rasterize_edges_arg

namespace rasterize_rows_arg {
constexpr cl_uint kJob = 0;
constexpr cl_uint kToggles = 1;
constexpr cl_uint kOccupied = 2;
constexpr cl_uint kUpdate = 3;
constexpr cl_uint kSrc = 4;
constexpr cl_uint kDst = 5;
constexpr cl_uint kDx = 6;
constexpr cl_uint kDy = 7;
constexpr cl_uint kRowFirst = 8;
constexpr cl_uint kRowEnd = 9;
constexpr cl_uint kStrong = 10;
constexpr cl_uint kWeak = 11;
constexpr cl_uint kSrcStrong = 12;
constexpr cl_uint kSrcWeak = 13;
constexpr cl_uint kShiftLevels = 14;
}  // namespace rasterize_rows_arg

namespace rasterize_bands_arg {
constexpr cl_uint kJob = 0;
constexpr cl_uint kToggles = 1;
constexpr cl_uint kOccupied = 2;
constexpr cl_uint kUpdate = 3;
constexpr cl_uint kSrc = 4;
constexpr cl_uint kDst = 5;
constexpr cl_uint kDx = 6;
constexpr cl_uint kDy = 7;
constexpr cl_uint kRowFirst = 8;
constexpr cl_uint kRowEnd = 9;
constexpr cl_uint kBand = 10;
constexpr cl_uint kStrong = 11;
constexpr cl_uint kWeak = 12;
constexpr cl_uint kSrcStrong = 13;
constexpr cl_uint kSrcWeak = 14;
constexpr cl_uint kShiftLevels = 15;
constexpr cl_uint kFirstBand = 16;
}  // namespace rasterize_bands_arg

// The row pass runs either kernel (bands_ chooses). Their arguments agree up to row_end, which
// the code that runs either sets by row_pass_arg; rasterize_bands then has its band, so the level
// bitsets' indices differ: LevelArgsOf() the kernel in use.
namespace row_pass_arg = rasterize_rows_arg;
static_assert(rasterize_bands_arg::kJob == row_pass_arg::kJob &&
              rasterize_bands_arg::kToggles == row_pass_arg::kToggles &&
              rasterize_bands_arg::kOccupied == row_pass_arg::kOccupied &&
              rasterize_bands_arg::kUpdate == row_pass_arg::kUpdate &&
              rasterize_bands_arg::kSrc == row_pass_arg::kSrc &&
              rasterize_bands_arg::kDst == row_pass_arg::kDst &&
              rasterize_bands_arg::kDx == row_pass_arg::kDx &&
              rasterize_bands_arg::kDy == row_pass_arg::kDy &&
              rasterize_bands_arg::kRowFirst == row_pass_arg::kRowFirst &&
              rasterize_bands_arg::kRowEnd == row_pass_arg::kRowEnd);

struct LevelArgs {
  cl_uint strong, weak, src_strong, src_weak, shift_levels;
};
constexpr LevelArgs kRowsLevelArgs = {rasterize_rows_arg::kStrong, rasterize_rows_arg::kWeak,
                                      rasterize_rows_arg::kSrcStrong, rasterize_rows_arg::kSrcWeak,
                                      rasterize_rows_arg::kShiftLevels};
constexpr LevelArgs kBandsLevelArgs = {
    rasterize_bands_arg::kStrong, rasterize_bands_arg::kWeak, rasterize_bands_arg::kSrcStrong,
    rasterize_bands_arg::kSrcWeak, rasterize_bands_arg::kShiftLevels};
const LevelArgs& LevelArgsOf(bool bands) { return bands ? kBandsLevelArgs : kRowsLevelArgs; }

// rasterize_bands: one band per compute unit (RowPass()).
constexpr std::size_t kBandsPerUnit = 1;

}  // namespace

void OpenClBackend::BindRasterizeArgs() {
  const cl_kernel edges = rasterize_edges_.get();
  SetArg(edges, rasterize_edges_arg::kToggles, toggles_.get());
  SetArg(edges, rasterize_edges_arg::kOccupied, occupied_.get());
  SetArg(edges, rasterize_edges_arg::kUpdate, update_.get());
  // The row pass: the mask only (no map), in place on map_[k], or map_[k] shifted into the
  // other buffer, with the level bitsets of the buffer it writes (and reads).
  const cl_mem no_map = nullptr;
  const LevelArgs& level = LevelArgsOf(bands_);
  for (int k = 0; k < 2; ++k) {
    const cl_kernel kernels[3] = {row_mask_.get(), row_fuse_[k][0].get(), row_fuse_[k][1].get()};
    const cl_mem src[3] = {no_map, map_[k].get(), map_[k].get()};
    const cl_mem dst[3] = {no_map, map_[k].get(), map_[1 - k].get()};
    const int to[3] = {k, k, 1 - k};
    for (int i = 0; i < 3; ++i) {
      SetArgAll(kernels[i], row_pass_arg::kToggles, toggles_.get());
      SetArgAll(kernels[i], row_pass_arg::kOccupied, occupied_.get());
      SetArgAll(kernels[i], row_pass_arg::kUpdate, update_.get());
      SetArgAll(kernels[i], row_pass_arg::kSrc, src[i]);
      SetArgAll(kernels[i], row_pass_arg::kDst, dst[i]);
      SetArgAll(kernels[i], level.strong, strong_[to[i]].get());
      SetArgAll(kernels[i], level.weak, weak_[to[i]].get());
      SetArgAll(kernels[i], level.src_strong, strong_[k].get());
      SetArgAll(kernels[i], level.src_weak, weak_[k].get());
      SetArgAll(kernels[i], level.shift_levels, cl_int(0));
      if (bands_) SetArgAll(kernels[i], rasterize_bands_arg::kFirstBand, cl_int(0));
    }
  }
}

void OpenClBackend::BindRasterizeJob() {
  SetArg(rasterize_edges_.get(), rasterize_edges_arg::kJob, job_.get());
  SetArgAll(row_mask_.get(), row_pass_arg::kJob, job_.get());
  for (const auto& pair : row_fuse_) {
    for (const opencl::Kernel& k : pair) SetArgAll(k.get(), row_pass_arg::kJob, job_.get());
  }
}

void OpenClBackend::Rasterize(const RasterJob& job) {
  if (crew_) crew_->Wake();  // the split stages of this scan follow
  FlushRows();  // a pending shift may wait: the upload and rasterize_edges leave the map alone
  const int r0 = std::max(job.row_begin, 0);
  const int r1 = std::min(job.row_end, params_.height);
  if (r0 >= r1) return;
  const int n = std::max(job.vertex_count, 0), listed = std::max(job.occupied_count, 0);
  const int width = params_.width, rows = r1 - r0;

  // The occupied cells sorted by row (a counting sort), so that a band of rows finds its own:
  // count[j] becomes the first cell of row r0 + j, then the next free place of that row.
  std::int32_t* count = row_counts_.data();
  std::fill(count, count + rows + 1, 0);
  int other = 0;
  for (int i = 0; i < listed; ++i) {
    const int r = job.occupied[i] / width;
    if (r >= r0 && r < r1) {
      ++count[r - r0 + 1];
    } else {
      ++other;
    }
  }
  for (int j = 1; j <= rows; ++j) count[j] += count[j - 1];
  const int m = count[rows];
  const std::size_t ints =
      8 + 2 * std::size_t(n) + std::size_t(m) + std::size_t(rows) + 1 + std::size_t(other);
  std::int32_t* staging = Staging(ints);
  const std::int32_t header[8] = {n, m, r0, r1, other, job.clear_outline ? 1 : 0, 0, 0};
  std::memcpy(staging, header, sizeof header);
  if (n > 0) std::memcpy(staging + 8, job.vertices, 2 * std::size_t(n) * 4);
  std::int32_t* cells = staging + 8 + 2 * std::size_t(n);
  std::int32_t* offsets = cells + m;
  std::int32_t* others = offsets + rows + 1;
  std::memcpy(offsets, count, (std::size_t(rows) + 1) * 4);
  for (int i = 0, o = 0; i < listed; ++i) {
    const std::int32_t cell = job.occupied[i];
    const int r = cell / width;
    if (r >= r0 && r < r1) {
      cells[count[r - r0]++] = cell;
    } else {
      others[o++] = cell;
    }
  }
  opencl::Event begin, end;
  Upload(ints, &begin);
  if (!bands_ && n + listed > 0) {  // rasterize_bands does the edges in its row pass
    const std::size_t global = RoundUp(std::size_t(n + listed), edge_local_);
    Launch(rasterize_edges_.get(), 1, &global, &edge_local_, end.out());
  } else {
    end = Retained(begin.get());
  }
  SetStage(kRasterStage, std::move(begin), std::move(end));
  rows_pending_ = true;
  pending_begin_ = r0;
  pending_end_ = r1;
}

void OpenClBackend::FlushRows() {
  if (!rows_pending_) return;
  rows_pending_ = false;
  RowPass(row_mask_.get(), 0, 0, pending_begin_, pending_end_, end_[kRasterStage].out());
  more_[kRasterStage].clear();
  more_[kRasterStage].swap(split_parts_);
}

void OpenClBackend::FlushRowsWithFusion() {
  // The row pass, the pending shift (the rows that can hold a known cell) or none (the
  // rasterized rows), the fusion.
  const int r0 = pending_begin_, r1 = pending_end_;
  opencl::Event event;
  if (shift_pending_) {
    // Rows outside `rows` are unknown before and after (and on no level), so the pass
    // leaves them alone.
    const int to = 1 - current_;
    const RowSpan fused{r0, r1};
    const RowSpan next = known_[current_].Shifted(pending_dy_, params_.height).Hull(fused);
    const RowSpan rows = unknown_off_levels_ ? next.Hull(known_[to]).Hull(level_rows_[to])
                                             : RowSpan{0, params_.height};
    const cl_kernel kernel = row_fuse_[current_][1].get();
    const LevelArgs& level = LevelArgsOf(bands_);
    SetArgAll(kernel, level.shift_levels, cl_int(levels_valid_ && unknown_off_levels_));
    RowPass(kernel, pending_dx_, pending_dy_, rows.begin, rows.end, event.out());
    levels_valid_ = true;  // it wrote every row with a level bit
    known_[to] = next;
    // The rows it wrote outside `next` got no level bit (their map rows are unknown).
    level_rows_[to] = unknown_off_levels_ ? next : rows;
  } else {
    RowPass(row_fuse_[current_][0].get(), 0, 0, r0, r1, event.out());
    known_[current_] = known_[current_].Hull({r0, r1});
    level_rows_[current_] = level_rows_[current_].Hull({r0, r1});
  }
  if (shift_pending_) current_ = 1 - current_;
  shift_pending_ = rows_pending_ = false;
  opencl::Event again = Retained(event.get());
  SetStage(kFuseStage, std::move(event), std::move(again));
}

void OpenClBackend::RowPass(cl_kernel kernel, int dx, int dy, int first, int end, cl_event* event) {
  SetArgAll(kernel, row_pass_arg::kDx, cl_int(dx));
  SetArgAll(kernel, row_pass_arg::kDy, cl_int(dy));
  SetArgAll(kernel, row_pass_arg::kRowFirst, cl_int(first));
  SetArgAll(kernel, row_pass_arg::kRowEnd, cl_int(end));
  const std::size_t rows = std::size_t(end - first);
  if (bands_ && devices_ > 1) {
    // One band per part, the parts over the devices; every command has one work-item.
    const int count = int(std::min<std::size_t>(rows, std::size_t(devices_)));
    const std::size_t band = (rows + std::size_t(count) - 1) / std::size_t(count);
    SetArgAll(kernel, rasterize_bands_arg::kBand, cl_int(band));
    SplitRun(count, [&](int part, int d, cl_event* e) {
      const cl_kernel twin = Twin(kernel, d);
      SetArg(twin, rasterize_bands_arg::kFirstBand, cl_int(part));
      const std::size_t one = 1;
      Launch(QueueOf(d), twin, 1, &one, &one, e);
    });
    Check(clRetainEvent(split_parts_[0].get()), "clRetainEvent");
    *event = split_parts_[0].get();
    return;
  }
  if (bands_) {
    // One band per compute unit: every band walks every edge of the polygon (a ScaLa scan has
    // over 2000), which costs more than the imbalance of uneven bands saves.
    const std::size_t bands = std::min<std::size_t>(rows, kBandsPerUnit * compute_units_);
    const std::size_t band = (rows + bands - 1) / bands;
    SetArg(kernel, rasterize_bands_arg::kBand, cl_int(band));
    const std::size_t global = (rows + band - 1) / band, local = 1;
    Launch(kernel, 1, &global, &local, event);
  } else {
    const std::size_t global[2] = {raster_local_[0], RoundUp(rows, raster_local_[1])};
    Launch(kernel, 2, global, raster_local_, event);
  }
}

}  // namespace freespace
