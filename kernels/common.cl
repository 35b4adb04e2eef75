// Definitions shared by every kernel file. The program is this file followed by the stage files
// (rasterize.cl, fuse.cl, classify.cl, insight.cl, shift.cl, rays.cl), built once per map size
// and parameter set; see src/opencl/backend.cpp for the build options.
//
// Every per-cell buffer (map, update mask, ray deltas) uses one padded layout: PAD_Y zero rows
// above and below the map, PAD_X zero columns left of it and at least max(OPENING_RADIUS, 1)
// plus the rounding to 16 right of it, rows STRIDE cells apart. PAD_X and STRIDE are multiples
// of 64, so a row's cells start 64-aligned and the kernels work on 16 (or 32, or 64) cells at a
// time with aligned vector loads and stores (lanes past the map's width are written 0), and
// shifted loads never leave the buffer. The
// padding is zero on every buffer at all times: no kernel writes it and the host copies only the
// map's cells in and out (rectangular copies).
//
// Kernels over cells take global size (row items, rows): work-item (x, r) handles the 16-cell
// vectors [x * VECTORS_PER_ITEM, (x + 1) * VECTORS_PER_ITEM) of row r (a whole row on a CPU,
// one or a few vectors on a GPU). All row items of a row are in one work-group, so a kernel
// may pass a row between its work-items through global memory and a barrier. Extra rows from
// rounding up to whole work-groups do nothing.
//
// The masks of stage 3 (and the free mask stage 4 reads) are bitsets instead: BIT_WORDS ulong
// words per row, bit i of word w is column 64 w + i, rows BIT_WORDS words apart, no padding.
// Kernels over them take global size (bit row items, rows): work-item (x, r) handles the words
// [x * BIT_WORDS_PER_ITEM, (x + 1) * BIT_WORDS_PER_ITEM) of row r, 64 cells a word, so four
// 16-cell vectors of the cell layout (a whole row on a CPU, one word on a GPU).
//
// Build options: WIDTH, HEIGHT, PAD_X, PAD_Y, STRIDE, VECTORS_PER_ITEM, T_LOW, T_HIGH.

// Index of map cell (row r, column c) in a padded buffer.
#define CELL(r, c) (((r) + PAD_Y) * STRIDE + PAD_X + (c))
// 16-cell vectors per row.
#define ROW_VECTORS ((WIDTH + 15) / 16)

// The vectors of row `r` this work-item handles: [*v0, *v1). False when it has none.
bool RowVectors(int* v0, int* v1) {
  *v0 = (int)get_global_id(0) * VECTORS_PER_ITEM;
  *v1 = min(*v0 + VECTORS_PER_ITEM, ROW_VECTORS);
  return *v0 < *v1;
}

// Lane i of the vector starting at column c0 is inside the map: -1 (all bits) inside, else 0.
int16 InsideLanes(int c0) {
  const int16 lane = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  return lane < (int16)(WIDTH - c0);
}

// The same as 16-bit lanes (c0 > WIDTH - 32768, true for every vector of a row).
short16 InsideLanes16(int c0) {
  const short16 lane = (short16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  return lane < (short16)(min(WIDTH - c0, 16));
}

// Bitset words per row, and per work-item.
#define BIT_WORDS ((WIDTH + 63) / 64)
#define BIT_WORDS_PER_ITEM ((VECTORS_PER_ITEM + 3) / 4)

// The level bitsets (strong: l <= T_LOW, weak: l <= T_HIGH) that the row pass of stage 1 writes
// for stage 3 are kept as uint halves, LEVEL_WORDS per row: uint 2 w holds columns 64 w ..
// 64 w + 31, uint 2 w + 1 the next 32 (whichever the byte order, since readers combine them
// arithmetically). A half past the map's width is 0.
#define LEVEL_WORDS (2 * BIT_WORDS)

// The bitset words of row `r` this work-item handles: [*w0, *w1). False when it has none.
bool RowWords(int* w0, int* w1) {
  *w0 = (int)get_global_id(0) * BIT_WORDS_PER_ITEM;
  *w1 = min(*w0 + BIT_WORDS_PER_ITEM, BIT_WORDS);
  return *w0 < *w1;
}

// The 32 lanes of two compare results (-1 true, 0 false; cells c0 .. c0 + 15 and c0 + 16 ..
// c0 + 31) as the bits of a uint, lane i at bit i.
uint PackBits32(short16 lo, short16 hi) {
#ifdef __ENDIAN_LITTLE__
  // Bytes of 0 / 1, lane i of a ulong at byte i. The multiply gathers a ulong's eight bytes
  // into its top byte, byte i at bit 56 + i: the partial products are distinct powers of two,
  // so no carry reaches the top byte.
  ulong4 x = (ulong4)(as_ulong2(convert_char16(lo) & (char16)(1)),
                      as_ulong2(convert_char16(hi) & (char16)(1)));
  x = ((x * (ulong4)(0x0102040810204080UL)) >> (ulong4)(56)) << (ulong4)(0, 8, 16, 24);
  const ulong2 y = x.lo | x.hi;
  return (uint)(y.x | y.y);
#else
  // Any byte order: one weight per lane, OR-reduced.
  const ushort16 weight =
      (ushort16)(1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384, 32768);
  const ushort16 q[2] = {as_ushort16(lo) & weight, as_ushort16(hi) & weight};
  uint bits = 0;
  for (int j = 0; j < 2; ++j) {
    const ushort8 a = q[j].lo | q[j].hi;
    const ushort4 b = a.lo | a.hi;
    const ushort2 c = b.lo | b.hi;
    bits |= (uint)(c.x | c.y) << (16 * j);
  }
  return bits;
#endif
}

// Strong and weak bits of the 32 map cells `lo`, `hi` (columns c0 .. c0 + 31 of row r) into
// the level bitsets, as uint c0 / 32 of the row; 0 past the width.
void StoreLevels(short16 lo, short16 hi, int r, int c0, __global uint* strong,
                 __global uint* weak) {
  const short16 in_lo = InsideLanes16(c0), in_hi = InsideLanes16(c0 + 16);
  const int k = r * LEVEL_WORDS + c0 / 32;
  strong[k] = PackBits32((lo <= (short16)(T_LOW)) & in_lo, (hi <= (short16)(T_LOW)) & in_hi);
  weak[k] = PackBits32((lo <= (short16)(T_HIGH)) & in_lo, (hi <= (short16)(T_HIGH)) & in_hi);
}

// Map cells (row r, columns c0 .. c0 + 15) after a shift of the map by whole cells:
// src(r + dy, c + dx), 0 where that cell is outside the map, and 0 past the width. The load
// may start outside the source row (|dx| < WIDTH, |dy| < HEIGHT): it stays inside the padded
// buffer. Two 16-byte loads: an unaligned vload16 of shorts may be split into many small
// loads, one of bytes is not.
short16 ShiftedCells(__global const short* src, int r, int c0, int dx, int dy) {
  // Unshifted: an aligned load, and the padding past the width is 0 already.
  if (dx == 0 && dy == 0) return *(__global const short16*)(src + CELL(r, c0));
  const int sr = r + dy;
  if (sr < 0 || sr >= HEIGHT) return (short16)(0);
  __global const uchar* bytes = (__global const uchar*)(src + CELL(sr, c0 + dx));
  const short16 old = (short16)(as_short8(vload16(0, bytes)), as_short8(vload16(1, bytes)));
  // Every lane inside the map and its source inside the source row: nothing to clear.
  if (c0 + dx >= 0 && c0 + dx + 16 <= WIDTH && c0 + 16 <= WIDTH) return old;
  const int16 lane = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const int16 sc = lane + (int16)(c0 + dx);
  const int16 keep = (sc >= (int16)(0)) & (sc < (int16)(WIDTH)) & InsideLanes(c0);
  return select((short16)(0), old, convert_short16(keep));
}
