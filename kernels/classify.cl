// Kernel stage 3: normalisation to free / not free with neighbourhood hysteresis, then the
// morphological opening of the free mask by the disk 2 OPENING_RADIUS + 1 cells across (paper
// IV.A; OpeningHalfWidth in src/core/include/core/backend.hpp). Mirrors host/classify.cpp.
//
// free0 = l <= T_LOW, or l <= T_HIGH with an 8-neighbour l <= T_LOW (neighbours inside the
// map only). The disk is a stack of rows of OPENING_KINDS distinct half-widths: each row is
// eroded along the row by every one of them (one plane per half-width), then the erosion of row
// r is the AND over the disk's rows dy of row r + dy of the plane of row dy's half-width; the
// dilation likewise with OR. Cells outside the map are not free: an erosion window that leaves
// the map meets a 0, a dilation window gains nothing from it.
//
// The masks are bitsets (common.cl: BIT_WORDS ulong words per row, bit i of word w is column
// 64 w + i, no padding), as on the host: a row pass is a few shifts and ANDs or ORs per word, a
// column pass one AND or OR per word and row, and the free mask the in-sight stage reads is
// 64 times smaller than the map. Bits past the map's width are 0 in every mask.
//
// In the GPU work shape, three kernels, because a column pass needs other rows' results of the
// pass before it:
//   classify_hysteresis_erode_rows   map -> free0 (a) -> row erosions (b, a plane per half-width)
//   classify_erode_cols_dilate_rows  b -> column erosion (a) -> row dilations (c, likewise)
//   classify_dilate_cols             c -> column dilation (free mask)
// Inside a kernel the second pass reads other words of its own row, which the work-group wrote
// before the barrier (the host keeps each row's work-items in one work-group). Global size
// (bit row items, HEIGHT rounded up).
//
// In the CPU work shape (src/opencl/backend.cpp), one kernel, classify_bands: one work-item per
// band of rows runs all the passes down its band, keeping only the rows a column window still
// needs (in rings of 2 OPENING_RADIUS + 1 rows of every plane), and recomputes the
// 2 OPENING_RADIUS rows beyond each end of its band that the column windows reach. Every row goes
// through the same functions as above, so the bits are the same; a scan saves two commands and
// the passes over whole-map intermediates.
//
// Build options: T_LOW, T_HIGH, OPENING_RADIUS, the disk's rows (MakeOpeningRows in
// src/core/include/core/backend.hpp): OPENING_KINDS distinct half-widths, as bits 0 .. 127 of
// OPENING_STOPS_LO and _HI, and OPENING_INDEX (per |dy| = 0 .. OPENING_RADIUS the place of its
// half-width among them, comma-separated) (and those of common.cl).
//
// Host side: src/opencl/classify.cpp; its classify_levels_arg, classify_hysteresis_erode_rows_arg,
// classify_erode_cols_dilate_rows_arg, classify_dilate_cols_arg and classify_bands_arg number the
// arguments of the kernels below: change both together.

// Per |dy|: the plane of the disk's row dy (its half-width's place among the distinct ones).
__constant int kOpeningIndex[OPENING_RADIUS + 1] = {OPENING_INDEX};

// Bits of the last word of a row that lie inside the map.
#define CLASSIFY_LAST_WORD_BITS ((WIDTH % 64) ? (~0UL >> (64 - WIDTH % 64)) : ~0UL)

ulong ClassifyValidBits(int w) { return w == BIT_WORDS - 1 ? CLASSIFY_LAST_WORD_BITS : ~0UL; }

// Word w of a level bitset row (common.cl: two uint halves; on a little-endian device they are
// the ulong itself, and rows start at an even uint).
ulong ClassifyLevelWord(__global const uint* row, int w) {
#ifdef __ENDIAN_LITTLE__
  return ((__global const ulong*)row)[w];
#else
  return (ulong)row[2 * w] | ((ulong)row[2 * w + 1] << 32);
#endif
}

// Level bitsets -> free0 on words [w0, w1) of row r, into the bitset row `out`. Walks the words
// left to right carrying the strong columns (rows r - 1 .. r + 1 OR'd) of the words left and
// right of the current one; the 8-neighbourhood is the current column OR'd with its neighbours
// one bit left and right. A row beyond the map's edge is replaced by row r itself, which adds
// nothing to the OR.
void ClassifyHysteresis(__global const uint* strong, __global const uint* weak, __global ulong* out,
                        int r, int w0, int w1) {
  __global const uint* s = strong + r * LEVEL_WORDS;
  __global const uint* below = r > 0 ? s - LEVEL_WORDS : s;
  __global const uint* above = r + 1 < HEIGHT ? s + LEVEL_WORDS : s;
  __global const uint* k = weak + r * LEVEL_WORDS;
#define CLASSIFY_NEAR(w) \
  (ClassifyLevelWord(below, (w)) | ClassifyLevelWord(s, (w)) | ClassifyLevelWord(above, (w)))
  ulong left = w0 > 0 ? CLASSIFY_NEAR(w0 - 1) : 0, here = CLASSIFY_NEAR(w0);
  for (int w = w0; w < w1; ++w) {
    const ulong right = w + 1 < BIT_WORDS ? CLASSIFY_NEAR(w + 1) : 0;
    const ulong spread = here | (here << 1) | (left >> 63) | (here >> 1) | (right << 63);
    out[w] = ClassifyLevelWord(s, w) | (ClassifyLevelWord(k, w) & spread);
    left = here;
    here = right;
  }
#undef CLASSIFY_NEAR
}

// Bits c + d of `row` for the 64 columns c of word w, any d; 0 outside the row.
ulong ClassifyShifted(__global const ulong* row, int w, int d) {
  const int bit = 64 * w + d;
  const int word = bit >= 0 ? bit / 64 : -((63 - bit) / 64);  // floor(bit / 64)
  const int offset = bit - 64 * word;
  const ulong lo = (word >= 0 && word < BIT_WORDS) ? row[word] : 0;
  if (offset == 0) return lo;
  const ulong hi = (word + 1 >= 0 && word + 1 < BIT_WORDS) ? row[word + 1] : 0;
  return (lo >> offset) | (hi << (64 - offset));
}

// Whether d is one of the half-widths (OPENING_STOPS_LO, _HI: bit d, d - 64).
#define CLASSIFY_STOP(d) \
  ((d) < 64 ? (OPENING_STOPS_LO >> (d)) & 1 : (OPENING_STOPS_HI >> ((d)-64)) & 1)

// The AND (erode) or OR (dilate) of words [w0, w1) of `row` shifted by -w .. w within the row
// for each of the disk's half-widths w, the j-th smallest into plane j of `out` (planes `plane`
// words apart): one window, widened a cell at a time, stored at each half-width. A dilation keeps
// the bits inside the map.
#define CLASSIFY_ROW_WINDOWS(Name, op, keep)                                                \
  void Name(__global const ulong* row, int w0, int w1, __global ulong* out, size_t plane) { \
    for (int w = w0; w < w1; ++w) {                                                         \
      const ulong x = row[w];                                                               \
      const ulong prev = w > 0 ? row[w - 1] : 0;                                            \
      const ulong next = w + 1 < BIT_WORDS ? row[w + 1] : 0;                                \
      ulong v = x;                                                                          \
      size_t at = w;                                                                        \
      if (CLASSIFY_STOP(0)) {                                                               \
        out[at] = v & (keep);                                                               \
        at += plane;                                                                        \
      }                                                                                     \
      for (int d = 1; d <= OPENING_RADIUS; ++d) {                                           \
        if (d < 64) {                                                                       \
          v = v op((x >> d) | (next << (64 - d))) op((x << d) | (prev >> (64 - d)));        \
        } else {                                                                            \
          v = v op ClassifyShifted(row, w, d) op ClassifyShifted(row, w, -d);               \
        }                                                                                   \
        if (CLASSIFY_STOP(d)) {                                                             \
          out[at] = v & (keep);                                                             \
          at += plane;                                                                      \
        }                                                                                   \
      }                                                                                     \
    }                                                                                       \
  }
CLASSIFY_ROW_WINDOWS(ClassifyErodeRows, &, ~0UL)
CLASSIFY_ROW_WINDOWS(ClassifyDilateRows, |, ClassifyValidBits(w))

// The plane of the row windows for the disk's row dy.
#define CLASSIFY_PLANE(dy) kOpeningIndex[(dy) < 0 ? -(dy) : (dy)]

// The level bitsets of the whole map, when the row pass of stage 1 did not write them (the map
// was shifted, fused or written some other way since).
__kernel void classify_levels(__global const short* map, __global uint* strong,
                              __global uint* weak) {
  const int r = get_global_id(1);
  int w0, w1;
  if (r >= HEIGHT || !RowWords(&w0, &w1)) return;
  for (int c0 = 64 * w0; c0 < 64 * w1; c0 += 32) {
    __global const short* m = map + CELL(r, c0);
    StoreLevels(*(__global const short16*)m, *(__global const short16*)(m + 16), r, c0, strong,
                weak);
  }
}

__kernel void classify_hysteresis_erode_rows(__global const uint* strong, __global const uint* weak,
                                             __global ulong* a, __global ulong* b) {
  const int r = get_global_id(1);
  int w0, w1;
  const bool active = r < HEIGHT && RowWords(&w0, &w1);
  if (active) ClassifyHysteresis(strong, weak, a + r * BIT_WORDS, r, w0, w1);
  barrier(CLK_GLOBAL_MEM_FENCE);
  if (!active) return;
  ClassifyErodeRows(a + r * BIT_WORDS, w0, w1, b + r * BIT_WORDS, (size_t)HEIGHT * BIT_WORDS);
}

__kernel void classify_erode_cols_dilate_rows(__global const ulong* b, __global ulong* a,
                                              __global ulong* c) {
  const int r = get_global_id(1);
  int w0, w1;
  const bool active = r < HEIGHT && RowWords(&w0, &w1);
  if (active) {
    // A column window that leaves the map meets a cell that is not free. Rows outer, words
    // inner: a row's words are contiguous.
    __global ulong* out = a + r * BIT_WORDS;
    if (r >= OPENING_RADIUS && r + OPENING_RADIUS < HEIGHT) {
      for (int w = w0; w < w1; ++w) out[w] = ~0UL;
      for (int dy = -OPENING_RADIUS; dy <= OPENING_RADIUS; ++dy) {
        __global const ulong* in =
            b + (size_t)CLASSIFY_PLANE(dy) * HEIGHT * BIT_WORDS + (r + dy) * BIT_WORDS;
        for (int w = w0; w < w1; ++w) out[w] &= in[w];
      }
    } else {
      for (int w = w0; w < w1; ++w) out[w] = 0;
    }
  }
  barrier(CLK_GLOBAL_MEM_FENCE);
  if (!active) return;
  ClassifyDilateRows(a + r * BIT_WORDS, w0, w1, c + r * BIT_WORDS, (size_t)HEIGHT * BIT_WORDS);
}

// OR of the column window: the free mask.
__kernel void classify_dilate_cols(__global const ulong* c, __global ulong* free) {
  const int r = get_global_id(1);
  int w0, w1;
  if (r >= HEIGHT || !RowWords(&w0, &w1)) return;
  const int d0 = max(r - OPENING_RADIUS, 0), d1 = min(r + OPENING_RADIUS, HEIGHT - 1);
  __global ulong* out = free + r * BIT_WORDS;
  for (int w = w0; w < w1; ++w) out[w] = 0;
  for (int d = d0; d <= d1; ++d) {
    __global const ulong* in =
        c + (size_t)CLASSIFY_PLANE(d - r) * HEIGHT * BIT_WORDS + d * BIT_WORDS;
    for (int w = w0; w < w1; ++w) out[w] |= in[w];
  }
}

// The rows a band keeps: a ring of row erosions (b) and one of row dilations (c), each as many
// rows as a column window, every row in each plane (the planes of a row side by side), then one
// row for free0 and for the column erosion in turn. Every ring row is written before it is read,
// so the scratch needs no initial contents.
#define CLASSIFY_RING (2 * OPENING_RADIUS + 1)
#define CLASSIFY_BAND_ROWS (2 * CLASSIFY_RING * OPENING_KINDS + 1)

// Stage 3 for the rows [row_first + g band, row_first + (g + 1) band) within [row_first,
// row_end) of band g = first_band + work-item (the host leaves out rows it knows to be empty;
// first_band > 0 when it splits the bands over devices); `scratch` holds CLASSIFY_BAND_ROWS
// bitset rows per band. Step t computes b of row t, the column erosion
// and c of row t - OPENING_RADIUS (whose window of b ends at row t) and the free mask of row
// t - 2 OPENING_RADIUS (whose window of c ends there), each where the band needs it.
__kernel void classify_bands(__global const uint* strong, __global const uint* weak,
                             __global ulong* scratch, __global ulong* free, int band, int row_first,
                             int row_end, int first_band) {
  const int g = first_band + (int)get_global_id(0);
  const int r0 = row_first + g * band, r1 = min(r0 + band, row_end);
  if (r0 >= r1) return;
  const int h = OPENING_RADIUS;
  __global ulong* b_ring = scratch + (size_t)g * CLASSIFY_BAND_ROWS * BIT_WORDS;
  __global ulong* c_ring = b_ring + CLASSIFY_RING * OPENING_KINDS * BIT_WORDS;
  __global ulong* row = c_ring + CLASSIFY_RING * OPENING_KINDS * BIT_WORDS;
  // Row t's window of plane j in a ring.
#define CLASSIFY_RING_ROW(ring, t, j) \
  ((ring) + (((t) % CLASSIFY_RING) * OPENING_KINDS + (j)) * BIT_WORDS)
  // b of the rows the column erosions reach, c of the rows the column dilations reach.
  const int b_begin = max(r0 - 2 * h, 0), b_end = min(r1 + 2 * h, HEIGHT);
  const int c_begin = max(r0 - h, 0), c_end = min(r1 + h, HEIGHT);
  for (int t = b_begin; t < r1 + 2 * h; ++t) {
    if (t < b_end) {
      ClassifyHysteresis(strong, weak, row, t, 0, BIT_WORDS);
      __global ulong* b = CLASSIFY_RING_ROW(b_ring, t, 0);
      ClassifyErodeRows(row, 0, BIT_WORDS, b, BIT_WORDS);
    }
    const int j = t - h;
    if (j >= c_begin && j < c_end) {
      // b rows j - h .. j + h are the ring's rows t - 2h .. t: all of it.
      if (j >= h && j + h < HEIGHT) {
        for (int w = 0; w < BIT_WORDS; ++w) row[w] = ~0UL;
        for (int dy = -h; dy <= h; ++dy) {
          __global const ulong* in = CLASSIFY_RING_ROW(b_ring, j + dy, CLASSIFY_PLANE(dy));
          for (int w = 0; w < BIT_WORDS; ++w) row[w] &= in[w];
        }
      } else {
        for (int w = 0; w < BIT_WORDS; ++w) row[w] = 0;
      }
      __global ulong* c = CLASSIFY_RING_ROW(c_ring, j, 0);
      ClassifyDilateRows(row, 0, BIT_WORDS, c, BIT_WORDS);
    }
    const int k = t - 2 * h;
    if (k >= r0 && k < r1) {
      // c rows k - h .. k + h (inside the map) are the ring's rows t - 3h .. t - h.
      const int d0 = max(k - h, 0), d1 = min(k + h, HEIGHT - 1);
      __global ulong* out = free + k * BIT_WORDS;
      for (int w = 0; w < BIT_WORDS; ++w) out[w] = 0;
      for (int d = d0; d <= d1; ++d) {
        __global const ulong* in = CLASSIFY_RING_ROW(c_ring, d, CLASSIFY_PLANE(d - k));
        for (int w = 0; w < BIT_WORDS; ++w) out[w] |= in[w];
      }
    }
  }
#undef CLASSIFY_RING_ROW
}
