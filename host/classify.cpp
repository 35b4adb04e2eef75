// Kernel stage 3 on the host: normalisation to free / not free with neighbourhood hysteresis,
// then morphological opening of the free mask (paper IV.A). Mirrors kernels/classify.cl.
//
// Thresholds are fixed-point log-odds (p <= t  <=>  l <= T), so "normalising" is a compare.
// The opening uses a square element of side 2h + 1, separable into row and column passes;
// cells outside the map count as not free, so the result is the union of all squares of
// free cells that fit inside the map.
//
// The row functions take their sizes by value and their rows as restrict pointers: byte
// stores may alias anything, and without that the compiler reloads every size from memory in
// the inner loops instead of vectorising them.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>

#include "host_backend.hpp"

namespace freespace {
namespace {

constexpr std::uint8_t kStrong = 1;
constexpr std::uint8_t kWeak = 2;

// Pass 1: bit 0 = strong (l <= t_low), bit 1 = weak (l <= t_high).
void LevelRow(const LogOdds* __restrict m, std::uint8_t* __restrict out, int width, LogOdds t_low,
              LogOdds t_high) {
  for (int c = 0; c < width; ++c) {
    const std::uint8_t strong = m[c] <= t_low;
    const std::uint8_t weak = m[c] <= t_high;
    out[c] = std::uint8_t(strong | (weak << 1));
  }
}

// Pass 2a: free0 = strong, or weak with a strong cell among its 8 neighbours. `lo` / `hi` are
// the rows below / above (null at the map's edge); `near` is scratch.
void HysteresisRow(const std::uint8_t* __restrict lo, const std::uint8_t* __restrict mid,
                   const std::uint8_t* __restrict hi, std::uint8_t* __restrict near,
                   std::uint8_t* __restrict out, int width) {
  for (int c = 0; c < width; ++c) near[c] = mid[c] & kStrong;
  if (lo != nullptr) {
    for (int c = 0; c < width; ++c) near[c] |= lo[c] & kStrong;
  }
  if (hi != nullptr) {
    for (int c = 0; c < width; ++c) near[c] |= hi[c] & kStrong;
  }
  // Interior without branches (vectorises); the two edge cells apart.
  auto cell = [&](int c, std::uint8_t around) {
    return std::uint8_t((mid[c] & kStrong) | ((mid[c] >> 1) & around));
  };
  for (int c = 1; c + 1 < width; ++c) {
    out[c] = cell(c, std::uint8_t(near[c - 1] | near[c] | near[c + 1]));
  }
  out[0] = cell(0, std::uint8_t(near[0] | (width > 1 ? near[1] : 0)));
  if (width > 1) out[width - 1] = cell(width - 1, std::uint8_t(near[width - 2] | near[width - 1]));
}

// out[c] = AND of in[c - h .. c + h]; 0 where the window leaves the row.
void ErodeRow(const std::uint8_t* __restrict in, std::uint8_t* __restrict out, int width, int h) {
  if (2 * h + 1 > width) {
    std::memset(out, 0, width);
    return;
  }
  std::memset(out, 0, h);
  std::memset(out + width - h, 0, h);
  std::memcpy(out + h, in, width - 2 * h);
  for (int d = 1; d <= 2 * h; ++d) {
    const std::uint8_t* __restrict shifted = in + d - h;
    for (int c = h; c < width - h; ++c) out[c] &= shifted[c];
  }
}

// out[c] = OR of in[c - h .. c + h] inside the row.
void DilateRow(const std::uint8_t* __restrict in, std::uint8_t* __restrict out, int width, int h) {
  std::memcpy(out, in, width);
  for (int d = 1; d <= h; ++d) {
    for (int c = 0; c + d < width; ++c) out[c] |= in[c + d];
    for (int c = d; c < width; ++c) out[c] |= in[c - d];
  }
}

// out = AND (erode) or OR (dilate) of `count` rows starting at `first`, `stride` apart.
void CombineRows(const std::uint8_t* first, std::size_t stride, int count,
                 std::uint8_t* __restrict out, int width, bool erode) {
  std::memcpy(out, first, width);
  for (int k = 1; k < count; ++k) {
    const std::uint8_t* __restrict in = first + k * stride;
    if (erode) {
      for (int c = 0; c < width; ++c) out[c] &= in[c];
    } else {
      for (int c = 0; c < width; ++c) out[c] |= in[c];
    }
  }
}

}  // namespace

void HostBackend::Classify() {
  const int width = params_.width, height = params_.height, h = params_.opening_radius;
  const LogOdds t_low = params_.t_low, t_high = params_.t_high;
  const std::size_t w = std::size_t(width);
  const LogOdds* map = map_.data();
  std::uint8_t* level = level_.data();
  std::uint8_t* a = pass_a_.data();
  std::uint8_t* b = pass_b_.data();
  std::uint8_t* f = free_.data();

  auto rows = [this, height](auto&& body) {
    arena_.execute([&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, height, 16),
                        [&](const tbb::blocked_range<int>& range) {
                          for (int r = range.begin(); r != range.end(); ++r) body(r);
                        });
    });
  };

  rows([=](int r) { LevelRow(map + r * w, level + r * w, width, t_low, t_high); });

  // Hysteresis into b (f as scratch), then the row erosion into a.
  rows([=](int r) {
    HysteresisRow(r > 0 ? level + (r - 1) * w : nullptr, level + r * w,
                  r + 1 < height ? level + (r + 1) * w : nullptr, f + r * w, b + r * w, width);
    ErodeRow(b + r * w, a + r * w, width, h);
  });

  // Column erosion of a into b, then the row dilation into f.
  rows([=](int r) {
    if (r < h || r + h >= height) {
      std::memset(b + r * w, 0, w);
    } else {
      CombineRows(a + (r - h) * w, w, 2 * h + 1, b + r * w, width, true);
    }
    DilateRow(b + r * w, f + r * w, width, h);
  });

  // Column dilation of f into a; a becomes the free mask.
  rows([=](int r) {
    const int d0 = std::max(0, r - h), d1 = std::min(height - 1, r + h);
    CombineRows(f + d0 * w, w, d1 - d0 + 1, a + r * w, width, false);
  });
  free_.swap(pass_a_);
}

}  // namespace freespace
