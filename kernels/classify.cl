// Kernel stage 3: normalisation to free / not free with neighbourhood hysteresis, then the
// morphological opening of the free mask by a square of side 2 OPENING_RADIUS + 1 (paper IV.A).
// Mirrors host/classify.cpp.
//
// free0 = l <= T_LOW, or l <= T_HIGH with an 8-neighbour l <= T_LOW (neighbours inside the
// map only). The opening is separable: erosion along rows, then columns, then dilation along
// rows, then columns. Cells outside the map are not free: an erosion window that leaves the map
// meets a 0, a dilation window gains nothing from it.
//
// The masks are bitsets (common.cl: BIT_WORDS ulong words per row, bit i of word w is column
// 64 w + i, no padding), as on the host: a row pass is a few shifts and ANDs or ORs per word, a
// column pass one AND or OR per word and row, and the free mask the in-sight stage reads is
// 64 times smaller than the map. Bits past the map's width are 0 in every mask.
//
// Three kernels, because a column pass needs other rows' results of the pass before it:
//   classify_hysteresis_erode_rows   map -> free0 (a) -> row erosion (b)
//   classify_erode_cols_dilate_rows  b -> column erosion (a) -> row dilation (c)
//   classify_dilate_cols             c -> column dilation (free mask)
// Inside a kernel the second pass reads other words of its own row, which the work-group wrote
// before the barrier (the host keeps each row's work-items in one work-group).
//
// Build options: T_LOW, T_HIGH, OPENING_RADIUS (and those of common.cl). Global size
// (bit row items, HEIGHT rounded up) for every kernel.

// Bits of the last word of a row that lie inside the map.
#define CLASSIFY_LAST_WORD_BITS ((WIDTH % 64) ? (~0UL >> (64 - WIDTH % 64)) : ~0UL)

ulong ClassifyValidBits(int w) { return w == BIT_WORDS - 1 ? CLASSIFY_LAST_WORD_BITS : ~0UL; }

// The 64 lanes of four compare results (-1 true, 0 false; cells c0 .. c0 + 15, c0 + 16 .. and so
// on) as the bits of one word, lane i at bit i.
ulong ClassifyPack(short16 q0, short16 q1, short16 q2, short16 q3) {
#ifdef __ENDIAN_LITTLE__
  // Bytes of 0 / 1, lane i of a ulong at byte i. The multiply gathers a ulong's eight bytes
  // into its top byte, byte i at bit 56 + i: the partial products are distinct powers of two,
  // so no carry reaches the top byte.
  ulong8 x = (ulong8)(as_ulong2(convert_char16(q0) & (char16)(1)),
                      as_ulong2(convert_char16(q1) & (char16)(1)),
                      as_ulong2(convert_char16(q2) & (char16)(1)),
                      as_ulong2(convert_char16(q3) & (char16)(1)));
  x = ((x * (ulong8)(0x0102040810204080UL)) >> (ulong8)(56)) << (ulong8)(0, 8, 16, 24, 32, 40, 48,
                                                                          56);
  const ulong4 y = x.lo | x.hi;
  const ulong2 z = y.lo | y.hi;
  return z.x | z.y;
#else
  // Any byte order: one weight per lane, OR-reduced.
  const ushort16 weight = (ushort16)(1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096,
                                     8192, 16384, 32768);
  const ushort16 q[4] = {as_ushort16(q0) & weight, as_ushort16(q1) & weight,
                         as_ushort16(q2) & weight, as_ushort16(q3) & weight};
  ulong bits = 0;
  for (int j = 0; j < 4; ++j) {
    const ushort8 a = q[j].lo | q[j].hi;
    const ushort4 b = a.lo | a.hi;
    const ushort2 c = b.lo | b.hi;
    bits |= (ulong)(c.x | c.y) << (16 * j);
  }
  return bits;
#endif
}

// 1 when cell (r, c) or the cell above or below it has l <= T_LOW (in-map cells only), else 0,
// and 0 for a column outside the map.
ulong ClassifyStrongColumn(__global const short* map, int r, int c) {
  if (c < 0 || c >= WIDTH) return 0;
  bool strong = false;
  for (int rr = max(r - 1, 0); rr <= min(r + 1, HEIGHT - 1); ++rr) {
    strong |= map[CELL(rr, c)] <= T_LOW;
  }
  return strong ? 1 : 0;
}

// map -> free0 on words [w0, w1) of row r. A word's 64 cells are 64-aligned in the padded map
// (common.cl), so they load as four aligned short16; the padding past the width is masked off.
void ClassifyHysteresis(__global const short* map, __global ulong* out, int r, int w0, int w1) {
  const bool below = r > 0, above = r + 1 < HEIGHT;
  for (int w = w0; w < w1; ++w) {
    __global const short* m = map + CELL(r, 64 * w);
    short16 strong[4], weak[4], near[4];
    for (int j = 0; j < 4; ++j) {
      const short16 l = *(__global const short16*)(m + 16 * j);
      strong[j] = l <= (short16)(T_LOW);
      weak[j] = l <= (short16)(T_HIGH);
      near[j] = strong[j];
      if (below) near[j] |= *(__global const short16*)(m - STRIDE + 16 * j) <= (short16)(T_LOW);
      if (above) near[j] |= *(__global const short16*)(m + STRIDE + 16 * j) <= (short16)(T_LOW);
    }
    const ulong valid = ClassifyValidBits(w);
    const ulong s = ClassifyPack(strong[0], strong[1], strong[2], strong[3]) & valid;
    const ulong k = ClassifyPack(weak[0], weak[1], weak[2], weak[3]) & valid;
    const ulong n = ClassifyPack(near[0], near[1], near[2], near[3]) & valid;
    // The 8-neighbourhood: the column itself and one column left and right, across words.
    const ulong spread = n | (n << 1) | (n >> 1) | ClassifyStrongColumn(map, r, 64 * w - 1) |
                         (ClassifyStrongColumn(map, r, 64 * w + 64) << 63);
    out[r * BIT_WORDS + w] = s | (k & spread);
  }
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

// AND (erode) or OR (dilate) of word w of `row` shifted by -OPENING_RADIUS .. OPENING_RADIUS
// within the row.
#define CLASSIFY_ROW_WINDOW(Name, op)                                    \
  ulong Name(__global const ulong* row, int w) {                         \
    const ulong x = row[w];                                              \
    const ulong prev = w > 0 ? row[w - 1] : 0;                           \
    const ulong next = w + 1 < BIT_WORDS ? row[w + 1] : 0;               \
    ulong v = x;                                                         \
    for (int d = 1; d <= OPENING_RADIUS; ++d) {                          \
      if (d < 64) {                                                      \
        v = v op((x >> d) | (next << (64 - d))) op((x << d) | (prev >> (64 - d))); \
      } else {                                                           \
        v = v op ClassifyShifted(row, w, d) op ClassifyShifted(row, w, -d); \
      }                                                                  \
    }                                                                    \
    return v;                                                            \
  }
CLASSIFY_ROW_WINDOW(ClassifyErodeRow, &)
CLASSIFY_ROW_WINDOW(ClassifyDilateRow, |)

__kernel void classify_hysteresis_erode_rows(__global const short* map, __global ulong* a,
                                             __global ulong* b) {
  const int r = get_global_id(1);
  int w0, w1;
  const bool active = r < HEIGHT && RowWords(&w0, &w1);
  if (active) ClassifyHysteresis(map, a, r, w0, w1);
  barrier(CLK_GLOBAL_MEM_FENCE);
  if (!active) return;
  for (int w = w0; w < w1; ++w) b[r * BIT_WORDS + w] = ClassifyErodeRow(a + r * BIT_WORDS, w);
}

__kernel void classify_erode_cols_dilate_rows(__global const ulong* b, __global ulong* a,
                                              __global ulong* c) {
  const int r = get_global_id(1);
  int w0, w1;
  const bool active = r < HEIGHT && RowWords(&w0, &w1);
  if (active) {
    // A column window that leaves the map meets a cell that is not free.
    const bool inside = r >= OPENING_RADIUS && r + OPENING_RADIUS < HEIGHT;
    for (int w = w0; w < w1; ++w) {
      ulong x = inside ? ~0UL : 0UL;
      if (inside) {
        for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) x &= b[(r + d) * BIT_WORDS + w];
      }
      a[r * BIT_WORDS + w] = x;
    }
  }
  barrier(CLK_GLOBAL_MEM_FENCE);
  if (!active) return;
  for (int w = w0; w < w1; ++w) {
    c[r * BIT_WORDS + w] = ClassifyDilateRow(a + r * BIT_WORDS, w) & ClassifyValidBits(w);
  }
}

// OR of the column window: the free mask.
__kernel void classify_dilate_cols(__global const ulong* c, __global ulong* free) {
  const int r = get_global_id(1);
  int w0, w1;
  if (r >= HEIGHT || !RowWords(&w0, &w1)) return;
  const int d0 = max(r - OPENING_RADIUS, 0), d1 = min(r + OPENING_RADIUS, HEIGHT - 1);
  for (int w = w0; w < w1; ++w) {
    ulong x = 0;
    for (int d = d0; d <= d1; ++d) x |= c[d * BIT_WORDS + w];
    free[r * BIT_WORDS + w] = x;
  }
}
