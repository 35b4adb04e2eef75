// The TBB host backend: every kernel stage as a parallel loop over rows (or rays) on the CPU,
// inside a task arena sized by backend.threads. It is also the oracle the OpenCL backend is
// tested against, bit for bit. Each stage lives in the file with the kernel's stem.
#pragma once

#include <cstdint>
#include <vector>

#include "core/backend.hpp"
#include "core/thread_arena.hpp"

// Row loops of the host stages are compiled for AVX-512, AVX2 and the baseline, picked at
// load time for the CPU at hand. Integer arithmetic only, so every variant gives the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FREESPACE_ROW_LOOP __attribute__((target_clones("arch=skylake-avx512", "avx2", "default")))
#else
#define FREESPACE_ROW_LOOP
#endif

namespace freespace {

// The most distinct row half-widths the opening's element may have (radius 0 .. 127).
inline constexpr int kMaxOpeningWidths = 128;

// The margin's cone toward one offset (dx, dy) as bounds on the columns of a row (stage 3b,
// host/mask.cpp): InMarginCone()'s two half-planes a v.x + b v.y >= 0 of the line of sight v
// each bound v.x from one side, v.x >= ratio v.y where a > 0 (side 1), v.x <= ratio v.y where
// a < 0 (side -1), by ratio = -b / a. A cone past a right angle, or all around, bounds nothing.
struct MarginCone {
  bool all = false;
  int side[2] = {0, 0};
  double ratio[2] = {0.0, 0.0};

  static MarginCone Of(const KernelParams& p, int dx, int dy);
};

class HostBackend final : public Backend {
 public:
  // threads: 0 = all cores.
  HostBackend(const KernelParams& params, int threads);

  std::string name() const override { return "tbb"; }

  void Rasterize(const RasterJob& job) override;                            // host/rasterize.cpp
  void Fuse(int row_begin, int row_end) override;                           // host/fuse.cpp
  void CastRays(const RayJob& job) override;                                // host/rays.cpp
  void FuseRays(int row_begin, int row_end) override;                       // host/rays.cpp
  void Classify() override;                                                 // host/classify.cpp
  void SetEchoes(const std::int32_t* cells, int count) override;            // host/classify.cpp
  void Mask(const SensorCell& sensor, const MarginViews& views) override;   // host/mask.cpp
  void InSight(CellIndex vehicle, std::vector<CellIndex>* edges) override;  // host/insight.cpp
  void InSightExact(const SensorCell& sensor, std::vector<RayStop>* stops,  // host/insight.cpp
                    std::vector<CellIndex>* edges) override;
  void Shift(int dx, int dy) override;  // host/shift.cpp
  void Clear() override;
  // The face layer's two bitsets (host/mask.cpp).
  void SetFaces(const std::int32_t* near, int near_count, const std::int32_t* seen,
                int seen_count) override;

  void ReadLogOdds(LogOdds* dst) override;
  void WriteLogOdds(const LogOdds* src) override;
  void ReadUpdateMask(std::uint8_t* dst) override;
  void WriteUpdateMask(const std::uint8_t* src) override;
  void ReadFree(std::uint8_t* dst) override;
  void ReadRayDelta(std::int32_t* dst) override;
  void WriteFree(const std::uint8_t* src) override;

  void ReadMaskBits(int row_begin, int row_end, std::uint64_t* dst) override;

  const LogOdds* HostLogOdds() const override { return map_.data(); }
  const std::uint64_t* HostMaskBits() const override { return mask_.data(); }

 private:
  std::size_t cells() const { return std::size_t(params_.width) * params_.height; }
  int words() const { return (params_.width + 63) / 64; }  // bitset words per row

  ThreadArena arena_;
  std::vector<LogOdds> map_;
  std::vector<LogOdds> map_scratch_;  // the shift writes here, then swaps
  // Every row of map_ (of map_scratch_) with a non-zero cell lies in known_ (scratch_known_).
  RowSpan known_;
  RowSpan scratch_known_;
  // Every row with a set bit in stage 3's intermediate bitsets (the levels, the erosions and the
  // dilations), and in free_.
  RowSpan bits_rows_;
  RowSpan free_rows_;
  std::vector<std::uint8_t> update_;  // stage 1 -> stage 2
  // Stage 3 bitsets, 64 cells a word, rows of (width + 63) / 64 words; bits_unconfirmed_:
  // log-odds >= 0, the margin's sources in stage 3b, on the rows of bits_rows_ (every other row
  // is unknown).
  std::vector<std::uint64_t> bits_strong_, bits_weak_, bits_unconfirmed_;
  // The opening's distinct row half-widths (OpeningHalfWidth(), ascending), each |dy|'s place
  // among them, and per half-width a plane of bitset rows of the rows' erosions and dilations.
  std::vector<int> opening_widths_, opening_index_;
  std::vector<std::uint64_t> bits_eroded_, bits_dilated_;
  std::vector<std::uint64_t> free_;       // stage 3 output, stage 4 input: bitset rows
  std::vector<std::uint64_t> echo_;       // this scan's echo cells (SetEchoes), bitset rows
  std::vector<std::int32_t> echo_words_;  // the words they set, to clear for the next scan
  std::vector<std::uint64_t> face_near_;  // the face layer (SetFaces): near a face, bitset rows
  std::vector<std::int32_t> face_near_words_;  // the words they set
  std::vector<std::uint64_t> face_seen_;       // touched by the outline, bitset rows
  std::vector<std::int32_t> face_seen_words_;  // the words they set
  std::vector<std::uint64_t> mask_;            // stage 3b output: the polygon mask, bitset rows
  RowSpan mask_rows_;                          // every row of mask_ with a set bit
  std::vector<std::uint64_t> mask_blocks_;     // its full 8 x 8 blocks (FullBlocks)
  std::vector<MarginCone> margin_cones_;       // stage 3b: per offset within the margin (fixed)
  std::vector<std::uint64_t> edge_seen_;       // stage 4: stop cells already in C_Edge (bitset)
  std::vector<std::int32_t> stop_;             // stage 4: stop cell per label
  std::vector<std::int32_t> delta_;  // conventional model: per-cell sum of one scan's rays
};

// Row kernels shared by the host backend and the tests. Each computes one row exactly as the
// OpenCL kernel of the same stem does for that row.
namespace host {

// A per-scan layer of cells (the echoes, the face layer): replaces the bits of the words `held`
// last set in the bitset rows `bits` (`words` a row) with `cells` (row * width + col), and holds
// the words those set.
void SetCellBits(const std::int32_t* cells, int count, int width, int words,
                 std::vector<std::int32_t>* held, std::vector<std::uint64_t>* bits);

// Stage 1: toggles parity at each crossing of the polygon's edges with row `row`'s centre
// line and turns the parity into kUpdateFree / kUpdateNone; `out` has `width` cells.
void RasterizeRow(const std::int32_t* vertices, int vertex_count, int width, int row,
                  std::uint8_t* out);

// The cells of rows [r0, r1) of `update` (`width` a row) that the outline of the full-scan
// polygon `vertices` touches, but for its two edges at the sensor (vertex 0), set to kUpdateNone
// (RasterJob::clear_outline). An edge inside one row costs no division (OutlineColumns takes a
// vertex's own x).
void ClearOutline(const std::int32_t* vertices, int vertex_count, int width, int r0, int r1,
                  std::uint8_t* update);

// Conventional model: adds the deltas of the ray from (x0, y0) to (x1, y1) into `delta`
// (width x height): l_free on every in-map cell before the end, l_occupied on the end cell.
// Atomic adds, so rays may run in parallel.
void AccumulateRay(std::int32_t* delta, int width, int height, int x0, int y0, int x1, int y1,
                   int l_free, int l_occupied);

// Stage 4: Bresenham from (x0, y0) to (x1, y1); returns the first cell after the start for
// which is_free(x, y) is false, or the end cell, as row * width + col.
template <class IsFree>
std::int32_t CastRay(const IsFree& is_free, int width, int x0, int y0, int x1, int y1) {
  const int dx = x1 > x0 ? x1 - x0 : x0 - x1, sx = x0 < x1 ? 1 : -1;
  const int dy = -(y1 > y0 ? y1 - y0 : y0 - y1), sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  int x = x0, y = y0;
  while (true) {
    // The vehicle's own cell never stops a ray.
    if ((x != x0 || y != y0) && !is_free(x, y)) break;
    if (x == x1 && y == y1) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y += sy;
    }
  }
  return y * width + x;
}

// The same over a free mask of one byte per cell.
inline std::int32_t CastRay(const std::uint8_t* free, int width, int x0, int y0, int x1, int y1) {
  return CastRay([=](int x, int y) { return free[y * width + x] != 0; }, width, x0, y0, x1, y1);
}

// Stage 4, a ray's steps in closed form: on a ray of n steps along its major axis and d <= n
// steps along the other in all, CastRay's step k (0 .. n) lies floor((2 d k + n) / (2 n)) minor
// steps off the start (by induction over its error term), the integer part of t = k d / n + 1/2.
// With slope = RaySlope(n, d) = ceil(2^32 d / n), RayMinorStep(slope, k) = (2^31 + k slope) /
// 2^32 is exact for n <= 46340: it exceeds 2^32 t by k (slope - 2^32 d / n) < k <= n, and
// 2^32 t lies at least 2^32 / (2 n) below the next integer multiple of 2^32 (t is a multiple
// of 1 / (2 n)), which n < 2^31 / n keeps out of reach. Maps have at most 8192 cells a side.
inline std::uint64_t RaySlope(int n, int d) {
  return ((std::uint64_t(d) << 32) + std::uint64_t(n - 1)) / std::uint64_t(n);
}
inline int RayMinorStep(std::uint64_t slope, int k) {
  return int((std::uint64_t(k) * slope + 0x80000000u) >> 32);
}

using ::freespace::FloorDiv;  // core/backend.hpp

}  // namespace host
}  // namespace freespace
