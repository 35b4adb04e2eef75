// The compute backend interface: one virtual method per kernel stage of the pipeline
// (DESIGN.md: rasterize, fuse, classify + open, in-sight scan, map shift). The TBB host
// backend (host/) and the OpenCL backend (kernels/, src/opencl/) implement it and
// must give bit-identical results; CreateBackend() picks one from the config.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/exact_ray.hpp"
#include "core/fixed_point.hpp"
#include "freespace/config.hpp"
#include "freespace/result.hpp"
#include "freespace/types.hpp"

namespace freespace {

class Crew;

// Values of the per-scan update mask written by stage 1 and read by stage 2.
inline constexpr std::uint8_t kUpdateNone = 0;
inline constexpr std::uint8_t kUpdateFree = 1;
inline constexpr std::uint8_t kUpdateOccupied = 2;

// Everything the kernels need from the config, converted once to integers.
struct KernelParams {
  int width = 0;
  int height = 0;
  LogOdds l_free = 0;      // log-odds added to a free cell (negative)
  LogOdds l_occupied = 0;  // log-odds added to an occupied cell (positive)
  LogOdds l_min = 0;       // clamp bounds of the map
  LogOdds l_max = 0;
  LogOdds t_low = 0;       // free if l <= t_low
  LogOdds t_high = 0;      // weak free if l <= t_high (free when next to a t_low cell)
  int opening_radius = 0;  // the opening's element: a disk 2 * radius + 1 cells across
  // The per-scan veto (classify.veto_current_echoes): this scan's echo cells are not free.
  bool veto_echoes = false;
  // The polygon mask's safety margin (stage 3b): `margin_cells` k (0: none), and the cone's
  // half-angle as its cosine and sine times kConeOne, rounded (the cone's edges are the
  // offset's direction turned by +-half-angle, in integers); all around when margin_all.
  int margin_cells = 0;
  std::int32_t cone_cos = 0;
  std::int32_t cone_sin = 0;
  bool margin_all = true;
};

// The opening's element for KernelParams::opening_radius h: the cells whose centres lie within
// h + 1/2 cells of its centre's, a disk as wide as the odd square of side 2h + 1 across, in every
// direction (a square is wider along its diagonals: it would take out diagonal passages up to
// sqrt 2 times the vehicle's width). Its row dy (|dy| <= h) spans the columns -w .. w, the largest
// w with (2w)^2 + (2dy)^2 <= (2h + 1)^2. kernels/classify.cl gets its rows as build options
// (MakeOpeningRows()).
inline int OpeningHalfWidth(int h, int dy) {
  const std::int64_t room = std::int64_t(2 * h + 1) * (2 * h + 1) - 4 * std::int64_t(dy) * dy;
  int w = h;
  while (w > 0 && 4 * std::int64_t(w) * w > room) --w;
  return w;
}

// The opening's element as its distinct row half-widths: `widths` ascending (the last is h), and
// per |dy| = 0 .. h the place of row dy's half-width among them.
struct OpeningRows {
  std::vector<int> widths, index;
};
inline OpeningRows MakeOpeningRows(int h) {
  OpeningRows rows;
  for (int dy = h; dy >= 0; --dy) {  // the half-widths grow toward the centre row
    const int w = OpeningHalfWidth(h, dy);
    if (rows.widths.empty() || rows.widths.back() != w) rows.widths.push_back(w);
  }
  rows.index.resize(std::size_t(h) + 1);
  for (int dy = 0; dy <= h; ++dy) {
    rows.index[std::size_t(dy)] =
        int(std::find(rows.widths.begin(), rows.widths.end(), OpeningHalfWidth(h, dy)) -
            rows.widths.begin());
  }
  return rows;
}

// The scale of KernelParams::cone_cos and cone_sin.
inline constexpr std::int32_t kConeOne = 1 << 20;

// Converts probabilities to fixed-point log-odds (round to nearest) and thresholds (floor, so
// that "p <= t" and "l <= T" agree on every representable l).
KernelParams MakeKernelParams(const Config& config);
LogOdds LogOddsFromProbability(double p);
LogOdds LogOddsThreshold(double p);
double ProbabilityFromLogOdds(LogOdds l);

// Whether the line of sight from the sensor (fixed point, kFixedBits) through the centre of cell
// (col, row) continues within the margin's cone toward the cell at offset (dx, dy) from it: the
// angle between (dx, dy) and the line of sight is at most the cone's half-angle. Integers only,
// so that every backend decides alike (kernels/mask.cl mirrors it).
inline bool InMarginCone(const KernelParams& p, std::int32_t sensor_x, std::int32_t sensor_y,
                         int col, int row, int dx, int dy) {
  if (p.margin_all) return true;
  const std::int64_t vx = std::int64_t(col) * kFixedOne + kFixedHalf - sensor_x;
  const std::int64_t vy = std::int64_t(row) * kFixedOne + kFixedHalf - sensor_y;
  // The cone's edges: (dx, dy) turned by +half-angle (e1) and by -half-angle (e2).
  const std::int64_t e1x = std::int64_t(dx) * p.cone_cos - std::int64_t(dy) * p.cone_sin;
  const std::int64_t e1y = std::int64_t(dx) * p.cone_sin + std::int64_t(dy) * p.cone_cos;
  const std::int64_t e2x = std::int64_t(dx) * p.cone_cos + std::int64_t(dy) * p.cone_sin;
  const std::int64_t e2y = -std::int64_t(dx) * p.cone_sin + std::int64_t(dy) * p.cone_cos;
  const bool after_e2 = e2x * vy - e2y * vx >= 0;   // counter-clockwise of e2, or on it
  const bool before_e1 = vx * e1y - vy * e1x >= 0;  // clockwise of e1, or on it
  // A cone up to a right angle is the wedge between its edges; a wider one the union of the
  // half-planes they bound.
  return p.cone_cos >= 0 ? (after_e2 && before_e1) : (after_e2 || before_e1);
}

// The points whose lines of sight the margin's cone follows (Backend::Mask): the scanners whose
// scans this map update fused, in fixed-point map cells (SensorCell::x, y). One scanner: the
// sensor itself; a rig: each scanner of the cycle, wherever the polygon's reference point is.
struct MarginViews {
  std::int32_t x[kMaxSensors] = {};
  std::int32_t y[kMaxSensors] = {};
  int count = 0;

  // Adds `s` when there is room (kMaxSensors, the most a rig has).
  void Add(const SensorCell& s) {
    if (count >= kMaxSensors) return;
    x[count] = s.x;
    y[count] = s.y;
    ++count;
  }
};

// InMarginCone() from any of `views`: a margin cell for one scanner's line of sight is one.
inline bool InMarginConeOfAny(const KernelParams& p, const MarginViews& views, int col, int row,
                              int dx, int dy) {
  if (p.margin_all) return true;
  for (int i = 0; i < views.count; ++i) {
    if (InMarginCone(p, views.x[i], views.y[i], col, row, dx, dy)) return true;
  }
  return false;
}

// Input of kernel stage 1 for one scan.
struct RasterJob {
  // Closed ring of the full-scan polygon: x0, y0, x1, y1, ... fixed point (kFixedBits).
  const std::int32_t* vertices = nullptr;
  int vertex_count = 0;
  // Cells holding a kept echo, as row * width + col, all inside the map.
  const std::int32_t* occupied = nullptr;
  int occupied_count = 0;
  // Rows of the update mask this scan rewrites; stage 2 reads the same rows.
  int row_begin = 0;
  int row_end = 0;
  // sensor_model.free_on_outline off: the cells the ring's outline touches get no free update,
  // but for the two edges at vertex 0 (the sensor): OutlineColumns() of edges 1 .. n - 2.
  bool clear_outline = false;
};

// floor(a / b) for b > 0.
inline std::int64_t FloorDiv(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

// The columns [*c_lo, *c_hi] of row r that the edge (x0, y0) -> (x1, y1) (fixed point) touches:
// its x over its part with 256 r <= y <= 256 (r + 1) (closed: an edge through a row boundary
// touches both rows), each end's x floor-divided from the edge's own line or, at a vertex, the
// vertex's; a horizontal edge its whole x range. Returns false when it misses the row or the
// columns [0, width). The same integers on every backend (kernels/rasterize.cl mirrors it).
bool OutlineColumns(std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1, int row,
                    int width, int* c_lo, int* c_hi);

// Input of the conventional inverse sensor model (the paper's baseline) for one scan: one
// Bresenham ray per kept echo from the sensor's cell to the echo's cell.
struct RayJob {
  std::int32_t origin_col = 0;  // the sensor's cell; may lie outside the map
  std::int32_t origin_row = 0;
  // End cells: col0, row0, col1, row1, ...; may lie outside the map.
  const std::int32_t* ends = nullptr;
  int ray_count = 0;
  // Rows the rays can touch; stage 2 of this model reads the same rows.
  int row_begin = 0;
  int row_end = 0;
};

// The in-sight labels (paper IV.A), 1-based as in the paper; label 0 of this function is the
// paper's label 1. Left column top to bottom, bottom row west to east, right column bottom to
// top, top row east to west: counter-clockwise in the world frame.
inline CellIndex BorderCell(int label0, int height, int width) {
  const int l = label0 + 1;
  if (l <= height) return {height - l, 0};
  if (l <= height + width) return {0, l - height - 1};
  if (l <= 2 * height + width) return {l - height - width - 1, width - 1};
  return {height - 1, 2 * height + 2 * width - l};
}
inline int BorderLabelCount(int height, int width) { return 2 * height + 2 * width; }

// C_Edge from the stop cells of the border rays (stop[l] = row * width + col of label l's stop
// cell): each distinct stop cell once, in the order of the smallest label that stopped there.
// Labels run upwards, so a cell's smallest label is the first to reach it. `seen` is a bitset
// over the map's cells (cell i is bit i % 64 of word i / 64), all 0 on entry and again on
// return; it is touched only at the stop cells. Both backends build C_Edge with it from the
// stop cells their stage 4 wrote.
void CollectEdges(const std::int32_t* stop, int labels, int width, std::uint64_t* seen,
                  std::vector<CellIndex>* edges);

// Rows [begin, end) of a map; empty when begin >= end. The backends keep one for each map
// buffer, holding every row with a known (non-zero) cell, so that the map shift copies and
// clears only those instead of the whole map: around a vehicle most of a large map is unknown.
struct RowSpan {
  int begin = 0;
  int end = 0;

  bool empty() const { return begin >= end; }
  // The smallest span holding both.
  RowSpan Hull(RowSpan other) const {
    if (empty()) return other;
    if (other.empty()) return *this;
    return {std::min(begin, other.begin), std::max(end, other.end)};
  }
  // These rows and the `h` on either side, clipped to [0, height).
  RowSpan Widened(int h, int height) const {
    return empty() ? RowSpan{} : RowSpan{std::max(begin - h, 0), std::min(end + h, height)};
  }
  // Where these rows go in the map shift new(r) = old(r + dy), clipped to [0, height).
  RowSpan Shifted(int dy, int height) const {
    const RowSpan moved{std::max(begin - dy, 0), std::min(end - dy, height)};
    return empty() || moved.empty() ? RowSpan{} : moved;
  }
};

class Backend {
 public:
  explicit Backend(const KernelParams& params) : params_(params) {}
  virtual ~Backend() = default;
  Backend(const Backend&) = delete;
  Backend& operator=(const Backend&) = delete;

  virtual std::string name() const = 0;

  // The threads a backend needs besides the calling one to drive its devices (the OpenCL
  // backend split over several CPU devices: one per device but the first), and how long they
  // keep polling after a stage (Crew). The estimator owns that crew, hands it over with
  // UseCrew() and runs the clutter filter's parallel passes on it too, so that the process has
  // one busy thread per core and the helpers are awake when a split stage starts. Without a
  // crew, a backend runs every part on the calling thread.
  struct CrewRequest {
    int helpers = 0;
    std::chrono::microseconds linger{0};
    std::chrono::microseconds window{0};
  };
  virtual CrewRequest WantedCrew() const { return {}; }
  // `crew` (not owned) outlives the backend or is replaced first; nullptr: none.
  virtual void UseCrew(Crew* /*crew*/) {}

  const KernelParams& params() const { return params_; }

  // Kernel stage 1 (enhanced inverse sensor model). Rewrites the update mask on rows
  // [row_begin, row_end): kUpdateFree where the cell centre is inside the polygon (even-odd
  // rule; a centre exactly on an edge counts as left of it), kUpdateOccupied on the listed
  // cells (occupied wins), kUpdateNone elsewhere; with job.clear_outline, a cell the outline
  // touches (RasterJob) is kUpdateNone unless occupied.
  virtual void Rasterize(const RasterJob& job) = 0;

  // Kernel stage 2. On rows [row_begin, row_end): map += l_free / l_occupied where the update
  // mask says so, clamped to [l_min, l_max].
  virtual void Fuse(int row_begin, int row_end) = 0;

  // Conventional model, stage 1: for every ray, each map cell on its Bresenham line before
  // the end cell adds l_free to that cell's delta and the end cell adds l_occupied; a cell
  // crossed by k rays gets k updates. Cells outside the map are skipped. The per-cell sums
  // are order-independent, so every backend gets the same deltas.
  virtual void CastRays(const RayJob& job) = 0;

  // Conventional model, stage 2: on rows [row_begin, row_end), map = clamp(map + delta) and
  // the delta is cleared for the next scan.
  virtual void FuseRays(int row_begin, int row_end) = 0;

  // Kernel stage 3. Whole map: strong = l <= t_low, weak = l <= t_high; free0 = strong, or
  // weak with a strong 8-neighbour; free = opening of free0 by the disk (OpeningHalfWidth();
  // cells outside the map are not free).
  virtual void Classify() = 0;

  // Kernel stage 4. Casts a Bresenham ray from `vehicle` to every border cell (label order);
  // each stops at its first not-free cell (the vehicle's own cell never stops it) or at the
  // border cell. Writes C_Edge into `edges`: the distinct stop cells in the order of the
  // smallest label that stopped there. `edges` must have capacity BorderLabelCount().
  virtual void InSight(CellIndex vehicle, std::vector<CellIndex>* edges) = 0;

  // The per-scan veto layer: the cells holding a kept echo of this scan (row * width + col,
  // inside the map; repeats allowed), in place of the last scan's. With params.veto_echoes the
  // next Classify() keeps them out of the free mask; Mask() counts them as margin sources.
  virtual void SetEchoes(const std::int32_t* cells, int count) = 0;
  // The per-scan face layer (polygon.face_tolerance_m; FaceCells()): the cells near a face of
  // this scan and those its outline touches (row * width + col, inside the map; repeats
  // allowed), in place of the last scan's. Mask() keeps the near ones out and does not count the
  // touched ones as margin sources.
  virtual void SetFaces(const std::int32_t* near, int near_count, const std::int32_t* seen,
                        int seen_count) = 0;

  // Kernel stage 3b, after Classify() (polygon.shape inside): the polygon mask. A cell is in it
  // when it is free in the free mask, or lies within opening_radius (Chebyshev) of the sensor's
  // cell with log-odds below 0 and no echo of this scan; and it is not near a face (SetFaces);
  // and no margin source (a cell with log-odds >= 0: occupied, or never seen free more often
  // than occupied; or an echo of this scan; but not a cell the outline touches) lies within
  // margin_cells of it (Chebyshev) in the margin's cone of one of `views` (InMarginConeOfAny).
  // The sensor's own cell always is.
  virtual void Mask(const SensorCell& sensor, const MarginViews& views) = 0;

  // Kernel stage 4 of the conservative polygon, after Mask(): an exact ray (TraceExactRay) from
  // the sensor to the centre of every border cell, in label order, on the polygon mask. Writes
  // each label's stop into `stops` (resized to BorderLabelCount()) and C_Edge from the stop
  // cells into `edges`, as InSight() does.
  virtual void InSightExact(const SensorCell& sensor, std::vector<RayStop>* stops,
                            std::vector<CellIndex>* edges) = 0;

  // The polygon mask as bitset rows of (width + 63) / 64 words (bit c % 64 of word c / 64): a
  // pointer when the backend keeps it in host memory, else null; and a copy of rows
  // [row_begin, row_end) into the same rows of `dst` (width * height cells of bitset rows).
  virtual const std::uint64_t* HostMaskBits() const { return nullptr; }
  virtual void ReadMaskBits(int row_begin, int row_end, std::uint64_t* dst) = 0;

  // Whether the kernels run on the host's cores on threads of the device's own (an OpenCL CPU
  // device): host work run beside a stage then competes with it for the cores, where the host
  // backend's TBB loops share them and a GPU leaves them free.
  virtual bool KernelsOnHostCores() const { return false; }

  // Moves the map by whole cells: new(r, c) = old(r + dy, c + dx); cells with no old
  // counterpart are unknown (0).
  virtual void Shift(int dx, int dy) = 0;

  // Sets every cell unknown.
  virtual void Clear() = 0;

  // Waits until every stage called so far has finished. Stages may run asynchronously (the
  // OpenCL backend enqueues them); InSight() and the Read*() copies wait on their own. The host
  // backend runs stages synchronously, so this does nothing there.
  virtual void Finish() {}

  // Copies between the backend's buffers and host memory (width * height elements). For
  // views, snapshots and tests; on the per-scan path only ReadFree(), for polygon.shape inside.
  virtual void ReadLogOdds(LogOdds* dst) = 0;
  virtual void WriteLogOdds(const LogOdds* src) = 0;
  virtual void ReadUpdateMask(std::uint8_t* dst) = 0;
  virtual void WriteUpdateMask(const std::uint8_t* src) = 0;
  virtual void ReadFree(std::uint8_t* dst) = 0;
  virtual void ReadRayDelta(std::int32_t* dst) = 0;
  virtual void WriteFree(const std::uint8_t* src) = 0;

  // The map and the free mask in host memory when the backend keeps them there, else null.
  virtual const LogOdds* HostLogOdds() const { return nullptr; }
  virtual const std::uint8_t* HostFree() const { return nullptr; }

  // Replaces the kernel-stage wall times in `times` by the backend's own measurement of the
  // last stages (OpenCL event profiling). Returns false when it has none.
  virtual bool KernelTimes(StageTimes* /*times*/) const { return false; }

 protected:
  KernelParams params_;
};

}  // namespace freespace
