// Kernel stage 3 on the host: normalisation to free / not free with neighbourhood hysteresis,
// then morphological opening of the free mask (paper IV.A). Mirrors kernels/classify.cl.
//
// Thresholds are fixed-point log-odds (p <= t  <=>  l <= T), so "normalising" is a compare.
// The opening's element is the disk 2h + 1 cells across (OpeningHalfWidth()): a stack of rows
// of half-widths w(dy). Its erosion is the AND over dy of row dy's erosion of row r + dy by
// w(dy), its dilation likewise with OR, so each row is eroded (dilated) once for each of the
// distinct half-widths, widening one window into the next, and the column passes pick each
// row's by its offset. Cells outside the map count as not free, so the result is the union of
// all disks of free cells that fit inside the map.
//
// The masks are handled as bitsets, 64 cells a word: a row erosion is a few shifts and ANDs
// per word, a column erosion one AND per word and row. The free mask stays a bitset: the
// in-sight stage reads it as such, and ReadFree() unpacks it for views and tests.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "host/host_backend.hpp"

namespace freespace {
namespace {

// A row of bitset words with one zero word on each side, so that shifted reads need no
// bounds checks. Rows are at most 8192 cells = 128 words.
struct PaddedRow {
  std::uint64_t word[130];
  std::uint64_t* data() { return word + 1; }
  void Clear(int words) {
    word[0] = 0;
    word[words + 1] = 0;
  }
};

// Bit c of the result is bit c + d (0 < d < 64) of the padded row x; same for c - d.
inline std::uint64_t Right(const std::uint64_t* x, int w, int d) {
  return (x[w] >> d) | (x[w + 1] << (64 - d));
}
inline std::uint64_t Left(const std::uint64_t* x, int w, int d) {
  return (x[w] << d) | (x[w - 1] >> (64 - d));
}
// The same for any d >= 0 (elements wider than 64 cells), reading 0 outside the row.
inline std::uint64_t Far(const std::uint64_t* x, int words, int w, int d) {
  const int bit = w * 64 + d, word = bit >> 6, offset = bit & 63;
  auto at = [&](int i) { return (i >= 0 && i < words) ? x[i] : 0; };
  return offset == 0 ? at(word) : (at(word) >> offset) | (at(word + 1) << (64 - offset));
}

// out = AND (erode) or OR (dilate) of x shifted by -h .. h within the row. x is a padded row
// (a zero word before and after). For h < 32 the window of 2h + 1 cells is built by doubling:
// the AND (OR) of `len` cells starting at each cell, len = 1, 2, 4, ..., following the binary
// digits of 2h + 1, then shifted left by h: about log2(2h + 1) passes instead of 2h. The runs
// are kept for the padding word before the row too, whose runs reach into the row.
void RowMorphology(const std::uint64_t* x, int words, int h, bool erode, std::uint64_t* out) {
  if (h == 0) {
    std::copy(x, x + words, out);
    return;
  }
  if (h < 32) {
    PaddedRow run, next;
    run.Clear(words);
    next.Clear(words);
    std::uint64_t* e = run.data();
    std::uint64_t* n = next.data();
    std::copy(x - 1, x + words, e - 1);
    const int length = 2 * h + 1;
    int top = 31 - __builtin_clz(unsigned(length));
    int len = 1;
    for (int bit = top - 1; bit >= 0; --bit) {
      // len -> 2 len: the run at c and the run at c + len.
      for (int w = -1; w < words; ++w) {
        n[w] = erode ? (e[w] & Right(e, w, len)) : (e[w] | Right(e, w, len));
      }
      std::swap(e, n);
      len *= 2;
      if ((length >> bit) & 1) {  // len -> len + 1: and the cell at c + len
        for (int w = -1; w < words; ++w) {
          n[w] = erode ? (e[w] & Right(x, w, len)) : (e[w] | Right(x, w, len));
        }
        std::swap(e, n);
        len += 1;
      }
    }
    for (int w = 0; w < words; ++w) out[w] = Left(e, w, h);  // window [c - h, c + h]
    return;
  }
  for (int w = 0; w < words; ++w) {
    std::uint64_t v = x[w];
    for (int d = 1; d <= h; ++d) {
      const std::uint64_t right = d < 64 ? Right(x, w, d) : Far(x, words, w, d);
      const std::uint64_t left = d < 64 ? Left(x, w, d) : Far(x, words, w, -d);
      v = erode ? (v & right & left) : (v | right | left);
    }
    out[w] = v;
  }
}

// Pass 1: strong (l <= t_low), weak (l <= t_high) and unconfirmed (l >= 0: occupied, or never
// seen free more often than occupied) bits of a row.
void LevelRow(const LogOdds* m, std::uint64_t* strong, std::uint64_t* weak,
              std::uint64_t* unconfirmed, int width, LogOdds t_low, LogOdds t_high) {
  const int words = (width + 63) / 64;
  for (int w = 0; w < words; ++w) {
    const int c0 = w * 64;
    std::uint64_t s = 0, k = 0, o = 0;
    int c = c0;
#if defined(__SSE2__)
    // 16 cells at a time: l <= t  <=>  t + 1 > l (thresholds are below 32767).
    const __m128i low = _mm_set1_epi16(std::int16_t(t_low + 1));
    const __m128i high = _mm_set1_epi16(std::int16_t(t_high + 1));
    const __m128i minus_one = _mm_set1_epi16(-1);
    for (; c + 16 <= std::min(c0 + 64, width); c += 16) {
      const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(m + c));
      const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(m + c + 8));
      const int ms =
          _mm_movemask_epi8(_mm_packs_epi16(_mm_cmpgt_epi16(low, a), _mm_cmpgt_epi16(low, b)));
      const int mk =
          _mm_movemask_epi8(_mm_packs_epi16(_mm_cmpgt_epi16(high, a), _mm_cmpgt_epi16(high, b)));
      const int mo = _mm_movemask_epi8(
          _mm_packs_epi16(_mm_cmpgt_epi16(a, minus_one), _mm_cmpgt_epi16(b, minus_one)));
      s |= std::uint64_t(std::uint16_t(ms)) << (c - c0);
      k |= std::uint64_t(std::uint16_t(mk)) << (c - c0);
      o |= std::uint64_t(std::uint16_t(mo)) << (c - c0);
    }
#endif
    for (; c < std::min(c0 + 64, width); ++c) {
      s |= std::uint64_t(m[c] <= t_low) << (c - c0);
      k |= std::uint64_t(m[c] <= t_high) << (c - c0);
      o |= std::uint64_t(m[c] >= 0) << (c - c0);
    }
    strong[w] = s;
    weak[w] = k;
    unconfirmed[w] = o;
  }
}

// The row windows of x (a padded row) for each of the element's half-widths `widths` (ascending):
// the AND (erode) or OR (dilate) of x shifted by -widths[j] .. widths[j] into outs[j], each
// widened from the one before.
void RowWindows(const std::uint64_t* x, int words, const std::vector<int>& widths, bool erode,
                std::uint64_t* const* outs) {
  RowMorphology(x, words, widths[0], erode, outs[0]);
  for (std::size_t j = 1; j < widths.size(); ++j) {
    const std::uint64_t* in = outs[j - 1];
    std::uint64_t* out = outs[j];
    for (int w = 0; w < words; ++w) {
      std::uint64_t v = in[w];
      for (int d = widths[j - 1] + 1; d <= widths[j]; ++d) {
        const std::uint64_t right = d < 64 ? Right(x, w, d) : Far(x, words, w, d);
        const std::uint64_t left = d < 64 ? Left(x, w, d) : Far(x, words, w, -d);
        v = erode ? (v & right & left) : (v | right | left);
      }
      out[w] = v;
    }
  }
}

// Pass 2: free0 = strong, or weak with a strong cell among its 8 neighbours; then its row
// erosions. `lo` / `hi` are the strong rows below / above (null at the map's edge).
void HysteresisErodeRow(const std::uint64_t* lo, const std::uint64_t* strong,
                        const std::uint64_t* hi, const std::uint64_t* weak, int words,
                        const std::vector<int>& widths, std::uint64_t* const* outs) {
  PaddedRow near, free0;
  near.Clear(words);
  free0.Clear(words);
  std::uint64_t* n = near.data();
  std::uint64_t* f = free0.data();
  for (int w = 0; w < words; ++w) n[w] = strong[w] | (lo ? lo[w] : 0) | (hi ? hi[w] : 0);
  for (int w = 0; w < words; ++w) {
    f[w] = strong[w] | (weak[w] & (n[w] | Right(n, w, 1) | Left(n, w, 1)));
  }
  RowWindows(f, words, widths, true, outs);
}

// Bitset rows in planes, one per distinct half-width of the opening's element's rows.
struct Planes {
  std::uint64_t* base;
  std::size_t plane, words;  // words a plane, a row
  const int* index;          // per |dy|: the plane of the element's row dy
  int count;

  // Row `row` of the plane of the element's row dy.
  const std::uint64_t* At(int dy, int row) const {
    return base + std::size_t(index[dy < 0 ? -dy : dy]) * plane + std::size_t(row) * words;
  }
  // Row r of every plane, in half-width order.
  void Rows(int r, std::uint64_t** outs) const {
    for (int j = 0; j < count; ++j)
      outs[j] = base + std::size_t(j) * plane + std::size_t(r) * words;
  }
};

// Pass 3: the column erosion of rows r - h .. r + h (row r + dy eroded by the element's row dy),
// then its row dilations.
void ErodeColumnsDilateRow(const Planes& eroded, int words, int r, int height, int h,
                           const std::vector<int>& widths, std::uint64_t valid_last,
                           std::uint64_t* const* outs) {
  PaddedRow column;
  column.Clear(words);
  std::uint64_t* e = column.data();
  if (r < h || r + h >= height) {
    std::fill(e, e + words, 0);
  } else {
    std::copy(eroded.At(-h, r - h), eroded.At(-h, r - h) + words, e);
    for (int dy = -h + 1; dy <= h; ++dy) {
      const std::uint64_t* row = eroded.At(dy, r + dy);
      for (int w = 0; w < words; ++w) e[w] &= row[w];
    }
  }
  RowWindows(e, words, widths, false, outs);
  for (std::size_t j = 0; j < widths.size(); ++j) outs[j][words - 1] &= valid_last;
}

// Pass 4: the column dilation of rows r - h .. r + h inside the map (row r + dy dilated by the
// element's row dy), less the vetoed cells (null: none).
void DilateColumnsRow(const Planes& dilated, int words, int r, int height, int h,
                      const std::uint64_t* veto, std::uint64_t* out) {
  const int d0 = std::max(0, r - h), d1 = std::min(height - 1, r + h);
  std::copy(dilated.At(d0 - r, d0), dilated.At(d0 - r, d0) + words, out);
  for (int d = d0 + 1; d <= d1; ++d) {
    const std::uint64_t* row = dilated.At(d - r, d);
    for (int w = 0; w < words; ++w) out[w] |= row[w];
  }
  if (veto != nullptr) {
    for (int w = 0; w < words; ++w) out[w] &= ~veto[w];
  }
}

}  // namespace

void HostBackend::Classify() {
  const int width = params_.width, height = params_.height, h = params_.opening_radius;
  const LogOdds t_low = params_.t_low, t_high = params_.t_high;
  const int words = (width + 63) / 64;
  const std::size_t w = std::size_t(width), nw = std::size_t(words);
  const std::uint64_t valid_last = (width % 64) ? (~0ull >> (64 - width % 64)) : ~0ull;
  const LogOdds* map = map_.data();
  std::uint64_t* strong = bits_strong_.data();
  std::uint64_t* weak = bits_weak_.data();
  std::uint64_t* unconfirmed = bits_unconfirmed_.data();
  // Per half-width of the element (opening_widths_), the rows' erosions and dilations.
  const std::vector<int>& widths = opening_widths_;
  const std::size_t plane = std::size_t(height) * nw;
  const Planes eroded{bits_eroded_.data(), plane, nw, opening_index_.data(), int(widths.size())};
  const Planes dilated{bits_dilated_.data(), plane, nw, opening_index_.data(), int(widths.size())};
  std::uint64_t* f = free_.data();

  // Where an unknown cell is on no level (t_high < 0, as every valid config has it), the rows
  // outside known_ have no level bit, so free0 and both erosions are empty there, and the free
  // mask is empty outside known_ widened by h. Each pass then writes the rows it can set plus
  // those it set last time (bits_rows_, free_rows_; now cleared), instead of the whole map.
  const bool sparse = t_high < 0;
  const RowSpan all{0, height};
  const RowSpan set = sparse ? known_ : all;
  const RowSpan set_free = sparse ? set.Widened(h, height) : all;
  auto rows = [this](RowSpan span, auto&& body) {
    if (span.empty()) return;
    arena_.execute([&] {
      tbb::parallel_for(tbb::blocked_range<int>(span.begin, span.end, 16),
                        [&](const tbb::blocked_range<int>& range) {
                          for (int r = range.begin(); r != range.end(); ++r) body(r);
                        });
    });
  };
  const RowSpan bits = set.Hull(bits_rows_);
  rows(bits, [=](int r) {
    LevelRow(map + r * w, strong + r * nw, weak + r * nw, unconfirmed + r * nw, width, t_low,
             t_high);
  });
  rows(bits, [=, &widths](int r) {
    std::uint64_t* outs[kMaxOpeningWidths];
    eroded.Rows(r, outs);
    HysteresisErodeRow(r > 0 ? strong + (r - 1) * nw : nullptr, strong + r * nw,
                       r + 1 < height ? strong + (r + 1) * nw : nullptr, weak + r * nw, words,
                       widths, outs);
  });
  rows(bits, [=, &widths](int r) {
    std::uint64_t* outs[kMaxOpeningWidths];
    dilated.Rows(r, outs);
    ErodeColumnsDilateRow(eroded, words, r, height, h, widths, valid_last, outs);
  });
  const std::uint64_t* veto = params_.veto_echoes ? echo_.data() : nullptr;
  rows(set_free.Hull(free_rows_), [=](int r) {
    DilateColumnsRow(dilated, words, r, height, h, veto ? veto + r * nw : nullptr, f + r * nw);
  });
  bits_rows_ = set;
  free_rows_ = set_free;
}

void HostBackend::SetEchoes(const std::int32_t* cells, int count) {
  host::SetCellBits(cells, count, params_.width, words(), &echo_words_, &echo_);
}

}  // namespace freespace
