// Kernel stage 3b on the host: the polygon mask of the conservative polygon (polygon.shape
// inside), and the face layer it reads (SetFaces). Mirrors kernels/mask.cl.
//
// The free mask, plus the cells around the sensor the opening took but the scans saw free more
// often than occupied, less the safety margin: a cell with an unconfirmed neighbour (the map's
// log-odds >= 0: occupied, or never seen free; or an echo of this scan) within margin_cells,
// where the line of sight from one of the scanners through the cell runs on toward that
// neighbour (InMarginConeOfAny). The echoes of this scan count, so that a vehicle now in a
// place the map still holds free keeps its margin too. With the face layer, the cells this scan's
// outline touches are no sources, and the cells near its faces are out. A row at a time, as
// bitsets; only the cells next to an unconfirmed one are tested for the cone.
#include <tbb/parallel_for.h>

#include <algorithm>

#include "core/fixed_point.hpp"
#include "host/host_backend.hpp"

namespace freespace {
namespace {

// Bits w * 64 + d .. w * 64 + d + 63 of a bitset row kept from pad[1] on, with a word of zeros
// on either side, for an offset -64 <= d <= 64 given as word = (d >> 6) + 1 and shift = d & 63:
// 0 outside the row.
std::uint64_t OffsetBits(const std::uint64_t* pad, int w, int word, int shift) {
  return (pad[w + word] >> shift) | ((pad[w + word + 1] << (63 - shift)) << 1);
}

// Bits lo .. hi of word w (all 64 where the word lies inside).
std::uint64_t RangeBits(int w, int lo, int hi) {
  const int first = std::max(lo - w * 64, 0), last = std::min(hi - w * 64, 63);
  if (first > last) return 0;
  return (~std::uint64_t{0} << first) & (~std::uint64_t{0} >> (63 - last));
}

// The lines of sight of a row's cells from the margin's views: per view, v.y of the row's cells
// and the view's x less half a cell, in cells.
struct RowViews {
  int count = 0;
  double vy[kMaxSensors];
  double x_less_half[kMaxSensors];

  RowViews(const MarginViews& views, int row) : count(views.count) {
    for (int v = 0; v < count; ++v) {
      vy[v] = row + 0.5 - double(views.y[v]) / kFixedOne;
      x_less_half[v] = double(views.x[v]) / kFixedOne - 0.5;
    }
  }
};

// Columns [lo, hi] of a row holding every cell whose line of sight from one of the row's views
// passes `cone`, found in floating point and widened by a column (the exact test
// InMarginConeOfAny() still decides each cell); false when there are none.
bool ConeColumns(const MarginCone& cone, const RowViews& row, int width, int* lo, int* hi) {
  *lo = 0;
  *hi = width - 1;
  if (cone.all) return true;
  double low = width, high = -1.0;  // the hull of the views' ranges
  for (int v = 0; v < row.count; ++v) {
    double c_lo = 0.0, c_hi = width - 1.0;
    for (int i = 0; i < 2; ++i) {
      // The column whose centre lies on the half-plane's edge, give or take a rounding.
      const double edge = cone.ratio[i] * row.vy[v] + row.x_less_half[v];
      if (cone.side[i] > 0) c_lo = std::max(c_lo, edge - 1.0);
      if (cone.side[i] < 0) c_hi = std::min(c_hi, edge + 1.0);
    }
    if (c_lo > c_hi) continue;
    low = std::min(low, c_lo);
    high = std::max(high, c_hi);
  }
  if (low > high) return false;
  *lo = -FloorCell(-low);  // the ceiling, without a library call (core/fixed_point.hpp)
  *hi = FloorCell(high);
  return *lo <= *hi;
}

}  // namespace

MarginCone MarginCone::Of(const KernelParams& p, int dx, int dy) {
  MarginCone cone;
  cone.all = p.margin_all || p.cone_cos < 0;  // past a right angle: no interval of columns
  // InMarginCone()'s two half-planes, a v.x + b v.y >= 0 for the line of sight v.
  const double c = p.cone_cos, s = p.cone_sin;
  const double e1x = dx * c - dy * s, e1y = dx * s + dy * c;
  const double e2x = dx * c + dy * s, e2y = -dx * s + dy * c;
  const double a[2] = {-e2y, e1y}, b[2] = {e2x, -e1x};
  for (int i = 0; i < 2; ++i) {
    cone.side[i] = a[i] > 0 ? 1 : (a[i] < 0 ? -1 : 0);
    cone.ratio[i] = a[i] != 0 ? -b[i] / a[i] : 0.0;
  }
  return cone;
}

void HostBackend::Mask(const SensorCell& sensor, const MarginViews& views) {
  const int width = params_.width, height = params_.height, nw = words();
  const int h = params_.opening_radius, k = params_.margin_cells;
  const RowSpan stand{std::max(0, sensor.cell.row - h), std::min(height, sensor.cell.row + h + 1)};
  const RowSpan span = free_rows_.Hull(stand);
  const RowSpan write = span.Hull(mask_rows_);
  const LogOdds* map = map_.data();
  const std::uint64_t valid_last = (width % 64) ? (~0ull >> (64 - width % 64)) : ~0ull;
  // The margin's sources of row rr, into src (nw words): outside the rows Classify() kept, every
  // cell is unknown.
  const auto sources = [&](int rr, std::uint64_t* src) {
    const std::size_t at = std::size_t(rr) * nw;
    const std::uint64_t* seen = face_seen_.data() + at;
    if (rr < bits_rows_.begin || rr >= bits_rows_.end) {
      for (int w = 0; w < nw; ++w) src[w] = ~seen[w];
      src[nw - 1] &= valid_last;
      return;
    }
    const std::uint64_t* unconfirmed = bits_unconfirmed_.data() + at;
    const std::uint64_t* echo = echo_.data() + at;
    for (int w = 0; w < nw; ++w) src[w] = (unconfirmed[w] | echo[w]) & ~seen[w];
  };
  auto mask_row = [&](int r) {
    std::uint64_t* out = mask_.data() + std::size_t(r) * nw;
    if (r < span.begin || r >= span.end) {
      std::fill(out, out + nw, std::uint64_t{0});
      return;
    }
    std::copy(free_.data() + std::size_t(r) * nw, free_.data() + std::size_t(r + 1) * nw, out);
    const std::uint64_t* echo = echo_.data() + std::size_t(r) * nw;
    const std::uint64_t* near_face = face_near_.data() + std::size_t(r) * nw;
    if (r >= stand.begin && r < stand.end) {
      for (int c = std::max(0, sensor.cell.col - h); c <= std::min(width - 1, sensor.cell.col + h);
           ++c) {
        if (map[std::size_t(r) * width + c] < 0 && !((echo[c >> 6] >> (c & 63)) & 1)) {
          out[c >> 6] |= std::uint64_t{1} << (c & 63);
        }
      }
    }
    if (k > 0) {
      // Room for the widest map; only the row's nw words are used. near from word 1 on, a word
      // of zeros on either side (OffsetBits). Each source row once, each offset's cells of it
      // in the columns its cone can reach against the free cells not yet killed: few of them
      // border a source, and each is tested for the cone as it is.
      std::uint64_t kill[128], near_pad[130];
      std::uint64_t* near = near_pad + 1;
      std::uint64_t free_any = 0;
      for (int w = 0; w < nw; ++w) {
        kill[w] = 0;
        free_any |= out[w];
      }
      near_pad[0] = near_pad[nw + 1] = 0;
      const RowViews lines(views, r);
      for (int dy = -k; dy <= k && free_any != 0; ++dy) {
        const int rr = r + dy;
        if (rr < 0 || rr >= height) continue;
        sources(rr, near);
        for (int dx = -k; dx <= k; ++dx) {
          int lo, hi;
          if ((dx == 0 && dy == 0) ||
              !ConeColumns(margin_cones_[std::size_t((dy + k) * (2 * k + 1) + dx + k)], lines,
                           width, &lo, &hi))
            continue;
          const int shift = dx & 63, word = (dx >> 6) + 1;  // dx >> 6 floors negative dx too
          for (int w = lo >> 6; w <= hi >> 6; ++w) {
            std::uint64_t candidates = out[w] & ~kill[w] & RangeBits(w, lo, hi);
            if (candidates == 0) continue;
            candidates &= OffsetBits(near_pad, w, word, shift);
            while (candidates != 0) {
              const int bit = __builtin_ctzll(candidates);
              candidates &= candidates - 1;
              if (InMarginConeOfAny(params_, views, w * 64 + bit, r, dx, dy)) {
                kill[w] |= std::uint64_t{1} << bit;
              }
            }
          }
        }
      }
      for (int w = 0; w < nw; ++w) out[w] &= ~kill[w];
    }
    for (int w = 0; w < nw; ++w) out[w] &= ~near_face[w];
    if (r == sensor.cell.row)
      out[sensor.cell.col >> 6] |= std::uint64_t{1} << (sensor.cell.col & 63);
  };
  if (!write.empty()) {
    arena_.execute([&] {
      tbb::parallel_for(tbb::blocked_range<int>(write.begin, write.end, 16),
                        [&](const tbb::blocked_range<int>& range) {
                          for (int r = range.begin(); r != range.end(); ++r) mask_row(r);
                        });
    });
  }
  mask_rows_ = span;
}

void HostBackend::SetFaces(const std::int32_t* near, int near_count, const std::int32_t* seen,
                           int seen_count) {
  host::SetCellBits(near, near_count, params_.width, words(), &face_near_words_, &face_near_);
  host::SetCellBits(seen, seen_count, params_.width, words(), &face_seen_words_, &face_seen_);
}

}  // namespace freespace
