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

#include "host/host_backend.hpp"

namespace freespace {
namespace {

// Bits start .. start + 63 of a bitset row kept from pad[1] on, with a word of zeros on either
// side: 0 outside the row (start from -64 to the row's last bit).
std::uint64_t PaddedBits64(const std::uint64_t* pad, int start) {
  const int w = (start >> 6) + 1, offset = start & 63;  // start >> 6 floors negative starts too
  return (pad[w] >> offset) | ((pad[w + 1] << (63 - offset)) << 1);
}

}  // namespace

void HostBackend::Mask(const SensorCell& sensor, const MarginViews& views) {
  const int width = params_.width, height = params_.height, nw = words();
  const int h = params_.opening_radius, k = params_.margin_cells;
  const RowSpan stand{std::max(0, sensor.cell.row - h), std::min(height, sensor.cell.row + h + 1)};
  const RowSpan span = free_rows_.Hull(stand);
  const RowSpan write = span.Hull(mask_rows_);
  const LogOdds* map = map_.data();
  const std::uint64_t valid_last = (width % 64) ? (~0ull >> (64 - width % 64)) : ~0ull;
  // The margin's sources of row rr: outside the rows Classify() kept, every cell is unknown.
  const auto sources = [&](int rr, int w) -> std::uint64_t {
    const std::size_t i = std::size_t(rr) * nw + w;
    if (rr < bits_rows_.begin || rr >= bits_rows_.end)
      return (w + 1 == nw ? valid_last : ~0ull) & ~face_seen_[i];
    return (bits_unconfirmed_[i] | echo_[i]) & ~face_seen_[i];
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
      // Room for the widest map; only the row's nw words are used, so only they are cleared.
      // near and column from word 1 on, a word of zeros on either side (PaddedBits64).
      std::uint64_t kill[128], near_pad[130], column_pad[130], any[128];
      std::uint64_t* near = near_pad + 1;
      std::uint64_t* column = column_pad + 1;
      std::fill_n(kill, nw, std::uint64_t{0});
      std::fill_n(column_pad, nw + 2, std::uint64_t{0});
      std::fill_n(any, nw, std::uint64_t{0});
      near_pad[0] = near_pad[nw + 1] = 0;
      // The cells with a source within k at all, so that the words without are skipped.
      for (int dy = -k; dy <= k; ++dy) {
        const int rr = r + dy;
        if (rr < 0 || rr >= height) continue;
        for (int w = 0; w < nw; ++w) {
          column[w] |= sources(rr, w);
        }
      }
      bool none = true;
      for (int w = 0; w < nw; ++w) {
        for (int dx = -k; dx <= k; ++dx) any[w] |= PaddedBits64(column_pad, w * 64 + dx);
        none = none && (out[w] & any[w]) == 0;
      }
      for (int dy = -k; dy <= k && !none; ++dy) {
        const int rr = r + dy;
        if (rr < 0 || rr >= height) continue;
        for (int w = 0; w < nw; ++w) near[w] = sources(rr, w);
        for (int dx = -k; dx <= k; ++dx) {
          if (dx == 0 && dy == 0) continue;
          // Few cells border a source: each is tested for the cone as it is, where bounding
          // the cone's columns first, per row and offset, cost more than the tests it saved.
          for (int w = 0; w < nw; ++w) {
            if ((out[w] & any[w]) == 0) continue;
            std::uint64_t candidates = out[w] & ~kill[w] & PaddedBits64(near_pad, w * 64 + dx);
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
