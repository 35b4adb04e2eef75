// Kernel stage 3 of OpenClBackend, the host side of kernels/classify.cl: the level bitsets of the
// map (classify_levels, unless the row pass of stage 1 wrote them), then the hysteresis and the
// opening, as classify_bands on a CPU (split over devices: one part per device) or as three
// kernels elsewhere. Only the rows the free mask can have bits on, or had, are computed.
#include <algorithm>

#include "backend_internal.hpp"
#include "opencl/backend.hpp"

namespace freespace {
namespace {

using opencl::kClassifyBandsPerUnit;
using opencl::Retained;
using opencl::SetArg;

// The kernels' parameters, in the order of their signatures in kernels/classify.cl.
namespace classify_levels_arg {
constexpr cl_uint kMap = 0;
constexpr cl_uint kStrong = 1;
constexpr cl_uint kWeak = 2;
}  // namespace classify_levels_arg

namespace classify_hysteresis_erode_rows_arg {
constexpr cl_uint kStrong = 0;
constexpr cl_uint kWeak = 1;
constexpr cl_uint kA = 2;
constexpr cl_uint kB = 3;
}  // namespace classify_hysteresis_erode_rows_arg

namespace classify_erode_cols_dilate_rows_arg {
constexpr cl_uint kB = 0;
constexpr cl_uint kA = 1;
constexpr cl_uint kC = 2;
}  // namespace classify_erode_cols_dilate_rows_arg

namespace classify_dilate_cols_arg {
constexpr cl_uint kC = 0;
constexpr cl_uint kFree = 1;
}  // namespace classify_dilate_cols_arg

namespace classify_bands_arg {
constexpr cl_uint kStrong = 0;
constexpr cl_uint kWeak = 1;
constexpr cl_uint kScratch = 2;
constexpr cl_uint kFree = 3;
constexpr cl_uint kBand = 4;
constexpr cl_uint kRowFirst = 5;
constexpr cl_uint kRowEnd = 6;
constexpr cl_uint kFirstBand = 7;
}  // namespace classify_bands_arg

}  // namespace

void OpenClBackend::BindClassifyArgs() {
  namespace erode_dilate = classify_erode_cols_dilate_rows_arg;
  namespace hysteresis = classify_hysteresis_erode_rows_arg;
  SetArg(erode_dilate_.get(), erode_dilate::kB, bits_b_.get());
  SetArg(erode_dilate_.get(), erode_dilate::kA, bits_a_.get());
  SetArg(erode_dilate_.get(), erode_dilate::kC, bits_c_.get());
  SetArg(dilate_cols_.get(), classify_dilate_cols_arg::kC, bits_c_.get());
  SetArg(dilate_cols_.get(), classify_dilate_cols_arg::kFree, free_.get());
  for (int k = 0; k < 2; ++k) {
    SetArg(levels_[k].get(), classify_levels_arg::kMap, map_[k].get());
    SetArg(levels_[k].get(), classify_levels_arg::kStrong, strong_[k].get());
    SetArg(levels_[k].get(), classify_levels_arg::kWeak, weak_[k].get());
    SetArg(hysteresis_[k].get(), hysteresis::kStrong, strong_[k].get());
    SetArg(hysteresis_[k].get(), hysteresis::kWeak, weak_[k].get());
    SetArg(hysteresis_[k].get(), hysteresis::kA, bits_a_.get());
    SetArg(hysteresis_[k].get(), hysteresis::kB, bits_b_.get());
    const cl_kernel bands = classify_bands_[k].get();
    SetArgAll(bands, classify_bands_arg::kStrong, strong_[k].get());
    SetArgAll(bands, classify_bands_arg::kWeak, weak_[k].get());
    SetArgAll(bands, classify_bands_arg::kScratch, band_rows_.get());
    SetArgAll(bands, classify_bands_arg::kFree, free_.get());
    SetArgAll(bands, classify_bands_arg::kFirstBand, cl_int(0));
  }
}

void OpenClBackend::LevelsWritten() {
  levels_valid_ = true;
  level_rows_[current_] = unknown_off_levels_ ? known_[current_] : RowSpan{0, params_.height};
}

void OpenClBackend::Classify() {
  if (crew_) crew_->Wake();
  Flush();
  opencl::Event begin, end;
  const int height = params_.height;
  const bool levels = !levels_valid_;
  if (levels) {
    BitsLaunch(levels_[current_].get(), height, begin.out());
    LevelsWritten();
  }
  // With unknown_off_levels_ a row without a level bit has no free0 bit and no eroded one, so
  // the free mask is empty outside level_rows_ widened by the opening radius.
  const int h = params_.opening_radius;
  const RowSpan set =
      unknown_off_levels_ ? level_rows_[current_].Widened(h, height) : RowSpan{0, height};
  if (bands_) {
    // The rows the free mask can have bits on, and those it had: the others stay empty.
    RowSpan rows = set.Hull(free_rows_);
    if (rows.empty()) rows = {0, 1};  // one row, so that the stage has its command
    const std::size_t count = std::size_t(rows.end - rows.begin);
    const cl_kernel kernel = classify_bands_[current_].get();
    if (devices_ > 1) {
      // One band per part, the parts over the devices; every command has one work-item.
      const int parts = int(std::min(count, std::size_t(devices_)));
      const std::size_t band = (count + std::size_t(parts) - 1) / std::size_t(parts);
      SetArgAll(kernel, classify_bands_arg::kBand, cl_int(band));
      SetArgAll(kernel, classify_bands_arg::kRowFirst, cl_int(rows.begin));
      SetArgAll(kernel, classify_bands_arg::kRowEnd, cl_int(rows.end));
      SplitRun(parts, [&](int part, int d, cl_event* e) {
        const cl_kernel twin = Twin(kernel, d);
        SetArg(twin, classify_bands_arg::kFirstBand, cl_int(part));
        const std::size_t one = 1;
        Launch(QueueOf(d), twin, 1, &one, &one, e);
      });
      if (!levels) begin = Retained(split_parts_[0].get());
      end = Retained(split_parts_[0].get());
      free_rows_ = set;
      if (params_.veto_echoes) VetoEchoes(set, &end);
      SetStage(kClassifyStage, std::move(begin), std::move(end));
      return;
    }
    const std::size_t bands = std::min(count, kClassifyBandsPerUnit * compute_units_);
    const std::size_t band = (count + bands - 1) / bands, global = (count + band - 1) / band;
    const std::size_t one = 1;
    SetArg(kernel, classify_bands_arg::kBand, cl_int(band));
    SetArg(kernel, classify_bands_arg::kRowFirst, cl_int(rows.begin));
    SetArg(kernel, classify_bands_arg::kRowEnd, cl_int(rows.end));
    Launch(kernel, 1, &global, &one, levels ? end.out() : begin.out());
    if (!levels) end = Retained(begin.get());
  } else {
    BitsLaunch(hysteresis_[current_].get(), height, levels ? nullptr : begin.out());
    BitsLaunch(erode_dilate_.get(), height, nullptr);
    BitsLaunch(dilate_cols_.get(), height, end.out());
  }
  if (params_.veto_echoes) VetoEchoes(set, &end);
  free_rows_ = set;
  SetStage(kClassifyStage, std::move(begin), std::move(end));
}

}  // namespace freespace
