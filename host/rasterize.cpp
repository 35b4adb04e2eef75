// Kernel stage 1 on the host: the enhanced inverse sensor model's full-scan polygon (paper II)
// rasterized into the per-scan update mask. Mirrors kernels/rasterize.cl bit for bit.
//
// A cell is free when its centre is inside the polygon by the even-odd rule. Each edge
// toggles a parity bit at the first column whose centre lies right of the edge's crossing
// with the row's centre line; a prefix XOR along the row then yields inside / outside. All
// geometry is integer (1/256 cell), so the crossing column is exact on every device.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>

#include "host/host_backend.hpp"

namespace freespace {
namespace host {
namespace {

// The column whose parity the edge (x0, y0) -> (x1, y1) toggles on the centre line yc, or
// `width` when the crossing is right of every centre in the row.
inline std::int64_t CrossingColumn(std::int64_t x0, std::int64_t y0, std::int64_t x1,
                                   std::int64_t y1, std::int64_t yc, int width) {
  // crossing x = x0 + (yc - y0) * (x1 - x0) / (y1 - y0); the first column c with centre
  // 256 c + 128 > x is floor((x - 128) / 256) + 1.
  std::int64_t num = (x0 - kFixedHalf) * (y1 - y0) + (yc - y0) * (x1 - x0);
  std::int64_t den = (y1 - y0) * kFixedOne;
  if (den < 0) {
    num = -num;
    den = -den;
  }
  const std::int64_t k = FloorDiv(num, den) + 1;
  return std::clamp<std::int64_t>(k, 0, width);
}

// In-place prefix XOR of 0/1 bytes, eight at a time: byte i becomes the XOR of bytes 0..i.
void PrefixXorRow(std::uint8_t* row, int width) {
  std::uint64_t carry = 0;
  int c = 0;
  for (; c + 8 <= width; c += 8) {
    std::uint64_t w;
    std::memcpy(&w, row + c, 8);
    w ^= w << 8;
    w ^= w << 16;
    w ^= w << 32;
    w ^= carry;
    std::memcpy(row + c, &w, 8);
    carry = (w >> 56) ? 0x0101010101010101ull : 0;
  }
  std::uint8_t p = carry ? 1 : 0;
  for (; c < width; ++c) {
    p ^= row[c];
    row[c] = p;
  }
}

}  // namespace

void RasterizeRow(const std::int32_t* v, int n, int width, int row, std::uint8_t* out) {
  std::memset(out, 0, width);
  const std::int64_t yc = std::int64_t(row) * kFixedOne + kFixedHalf;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1 == n) ? 0 : i + 1;
    const std::int64_t y0 = v[2 * i + 1];
    const std::int64_t y1 = v[2 * j + 1];
    if ((y0 <= yc) == (y1 <= yc)) continue;
    const std::int64_t k = CrossingColumn(v[2 * i], y0, v[2 * j], y1, yc, width);
    if (k < width) out[k] ^= 1;
  }
  PrefixXorRow(out, width);
}

}  // namespace host

namespace host {

void ClearOutline(const std::int32_t* v, int vertex_count, int width, int r0, int r1,
                  std::uint8_t* update) {
  for (int i = 1; i + 1 < vertex_count; ++i) {
    const std::int64_t x0 = v[2 * i], y0 = v[2 * i + 1], x1 = v[2 * i + 2], y1 = v[2 * i + 3];
    // Rows ra .. rb (inclusive) with 256 r <= max y and 256 (r + 1) >= min y.
    const std::int64_t ra = FloorDiv(std::min(y0, y1) + kFixedOne - 1, kFixedOne) - 1;
    const std::int64_t rb = FloorDiv(std::max(y0, y1), kFixedOne);
    for (std::int64_t r = std::max<std::int64_t>(ra, r0); r <= std::min<std::int64_t>(rb, r1 - 1);
         ++r) {
      int lo = 0, hi = -1;
      if (!OutlineColumns(x0, y0, x1, y1, int(r), width, &lo, &hi)) continue;
      std::uint8_t* row = update + std::size_t(r) * width;
      std::fill(row + lo, row + hi + 1, kUpdateNone);
    }
  }
}

}  // namespace host

void HostBackend::Rasterize(const RasterJob& job) {
  const int width = params_.width;
  const int r0 = std::max(job.row_begin, 0);
  const int r1 = std::min(job.row_end, params_.height);
  if (r0 >= r1) return;
  std::uint8_t* update = update_.data();
  std::memset(update + std::size_t(r0) * width, 0, std::size_t(r1 - r0) * width);

  // Toggles: walk each edge over the rows it crosses. The work is the polygon's perimeter in
  // rows, far less than rows x edges, so one thread does it.
  const std::int32_t* v = job.vertices;
  const int n = job.vertex_count;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1 == n) ? 0 : i + 1;
    const std::int64_t x0 = v[2 * i], y0 = v[2 * i + 1];
    const std::int64_t x1 = v[2 * j], y1 = v[2 * j + 1];
    if (y0 == y1) continue;
    const std::int64_t ylo = std::min(y0, y1), yhi = std::max(y0, y1);
    // Rows whose centre yc = 256 r + 128 satisfies ylo <= yc < yhi.
    const std::int64_t ra =
        std::max<std::int64_t>(host::FloorDiv(ylo - kFixedHalf + kFixedOne - 1, kFixedOne), r0);
    const std::int64_t rb =
        std::min<std::int64_t>(host::FloorDiv(yhi - kFixedHalf + kFixedOne - 1, kFixedOne), r1);
    for (std::int64_t r = ra; r < rb; ++r) {
      const std::int64_t yc = r * kFixedOne + kFixedHalf;
      const std::int64_t k = host::CrossingColumn(x0, y0, x1, y1, yc, width);
      if (k < width) update[r * width + k] ^= 1;
    }
  }

  arena_.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(r0, r1, 16),
                      [&](const tbb::blocked_range<int>& rows) {
                        for (int r = rows.begin(); r != rows.end(); ++r) {
                          host::PrefixXorRow(update + std::size_t(r) * width, width);
                        }
                      });
  });

  if (job.clear_outline) host::ClearOutline(job.vertices, job.vertex_count, width, r0, r1, update);
  // Occupied wins over free: written after the fill.
  for (int i = 0; i < job.occupied_count; ++i) update[job.occupied[i]] = kUpdateOccupied;
}

}  // namespace freespace
