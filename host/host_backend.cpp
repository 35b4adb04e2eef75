// HostBackend: construction, buffers and the copies in and out. The stages themselves are in
// rasterize.cpp, fuse.cpp, classify.cpp, insight.cpp and shift.cpp beside this file.
#include "host/host_backend.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <utility>

#include "freespace/errors.hpp"

namespace freespace {

HostBackend::HostBackend(const KernelParams& params, int threads)
    : Backend(params),
      arena_(threads),
      map_(cells(), 0),
      map_scratch_(cells(), 0),
      update_(cells(), kUpdateNone),
      bits_strong_(std::size_t(params.height) * ((params.width + 63) / 64), 0),
      bits_weak_(bits_strong_.size(), 0),
      bits_unconfirmed_(bits_strong_.size(), 0),
      free_(bits_strong_.size(), 0),
      echo_(bits_strong_.size(), 0),
      face_near_(bits_strong_.size(), 0),
      face_seen_(bits_strong_.size(), 0),
      mask_(bits_strong_.size(), 0),
      mask_blocks_(
          std::size_t(params.height >> kBlockShift) * (((params.width >> kBlockShift) + 63) / 64),
          0),
      edge_seen_((cells() + 63) / 64, 0),
      stop_(BorderLabelCount(params.height, params.width), 0),
      delta_(cells(), 0) {
  if (params.width < 1 || params.height < 1 || params.width > 8192 || params.height > 8192) {
    throw BackendError("tbb backend: map of " + std::to_string(params.width) + " x " +
                       std::to_string(params.height) + " cells; each side must be 1 .. 8192");
  }
  echo_words_.reserve(16384);
  const int h = params.opening_radius;
  if (h < 0 || h >= kMaxOpeningWidths) {
    throw BackendError("tbb backend: opening radius of " + std::to_string(h) +
                       " cells; it must be 0 .. " + std::to_string(kMaxOpeningWidths - 1));
  }
  OpeningRows opening = MakeOpeningRows(h);
  opening_widths_ = std::move(opening.widths);
  opening_index_ = std::move(opening.index);
  bits_eroded_.assign(opening_widths_.size() * bits_strong_.size(), 0);
  bits_dilated_.assign(bits_eroded_.size(), 0);
  // The margin's cone per offset (dy, dx) within margin_cells, row by row: fixed by the params.
  const int k = params.margin_cells;
  for (int dy = -k; dy <= k; ++dy) {
    for (int dx = -k; dx <= k; ++dx) margin_cones_.push_back(MarginCone::Of(params, dx, dy));
  }
}

void HostBackend::Clear() {
  std::fill(map_.begin(), map_.end(), LogOdds{0});
  known_ = {};
  std::fill(free_.begin(), free_.end(), std::uint64_t{0});
  free_rows_ = {};
}

void HostBackend::ReadLogOdds(LogOdds* dst) { std::memcpy(dst, map_.data(), cells() * 2); }
void HostBackend::WriteLogOdds(const LogOdds* src) {
  std::memcpy(map_.data(), src, cells() * 2);
  known_ = {0, params_.height};
  // The margin's sources of stage 3b (log-odds >= 0), which Classify() keeps for the maps it
  // classifies.
  const int width = params_.width, nw = words();
  for (int r = 0; r < params_.height; ++r) {
    for (int w = 0; w < nw; ++w) {
      std::uint64_t bits = 0;
      for (int c = w * 64; c < std::min(width, w * 64 + 64); ++c) {
        bits |= std::uint64_t(src[std::size_t(r) * width + c] >= 0) << (c - w * 64);
      }
      bits_unconfirmed_[std::size_t(r) * nw + w] = bits;
    }
  }
  bits_rows_ = {0, params_.height};
}
void HostBackend::ReadUpdateMask(std::uint8_t* dst) { std::memcpy(dst, update_.data(), cells()); }
void HostBackend::WriteUpdateMask(const std::uint8_t* src) {
  std::memcpy(update_.data(), src, cells());
}
void HostBackend::ReadFree(std::uint8_t* dst) {
  // Eight cells at a time: byte k of Spread(b) is bit k of b.
  static const auto spread = [] {
    std::array<std::uint64_t, 256> table{};
    for (int b = 0; b < 256; ++b) {
      for (int k = 0; k < 8; ++k) table[b] |= std::uint64_t((b >> k) & 1) << (8 * k);
    }
    return table;
  }();
  const int width = params_.width, nw = words();
  for (int r = 0; r < params_.height; ++r) {
    const std::uint64_t* bits = free_.data() + std::size_t(r) * nw;
    std::uint8_t* out = dst + std::size_t(r) * width;
    int c = 0;
    for (; c + 8 <= width; c += 8) {
      const std::uint64_t bytes = spread[(bits[c / 64] >> (c % 64)) & 0xFF];
      std::memcpy(out + c, &bytes, 8);
    }
    for (; c < width; ++c) out[c] = (bits[c / 64] >> (c % 64)) & 1;
  }
}
void HostBackend::ReadMaskBits(int row_begin, int row_end, std::uint64_t* dst) {
  const std::size_t nw = std::size_t(words());
  std::copy(mask_.begin() + std::ptrdiff_t(row_begin * nw),
            mask_.begin() + std::ptrdiff_t(row_end * nw), dst + row_begin * nw);
}
void HostBackend::ReadRayDelta(std::int32_t* dst) {
  std::memcpy(dst, delta_.data(), cells() * sizeof(std::int32_t));
}
void HostBackend::WriteFree(const std::uint8_t* src) {
  const int width = params_.width, nw = words();
  std::fill(free_.begin(), free_.end(), std::uint64_t{0});
  free_rows_ = {0, params_.height};
  for (int r = 0; r < params_.height; ++r) {
    for (int c = 0; c < width; ++c) {
      if (src[std::size_t(r) * width + c]) free_[std::size_t(r) * nw + c / 64] |= 1ull << (c % 64);
    }
  }
}

namespace host {

void SetCellBits(const std::int32_t* cells, int count, int width, int words,
                 std::vector<std::int32_t>* held, std::vector<std::uint64_t>* bits) {
  // Each old word to 0 clears every old bit (all of them are this layer's).
  for (const std::int32_t w : *held) (*bits)[std::size_t(w)] = 0;
  held->resize(std::size_t(count));
  // The row without an integer division: (cell + 0.5) / width lies at least 0.5 / width from an
  // integer, far beyond the rounding of the product (below 1e-11 for rows up to 8192).
  const double per_row = 1.0 / width;
  for (int i = 0; i < count; ++i) {
    const std::int32_t row = std::int32_t((cells[i] + 0.5) * per_row);
    const std::int32_t col = cells[i] - row * width;
    const std::int32_t w = row * words + col / 64;
    (*held)[std::size_t(i)] = w;
    (*bits)[std::size_t(w)] |= std::uint64_t{1} << (col % 64);
  }
}

}  // namespace host

}  // namespace freespace
