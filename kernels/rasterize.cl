// Kernel stage 1: the enhanced inverse sensor model (paper II). The full-scan polygon is
// rasterized into the per-scan update mask by the even-odd rule and the kept echoes are marked
// occupied. Mirrors host/rasterize.cpp bit for bit: each polygon edge toggles a parity bit at
// the first column whose centre lies right of its crossing with a row's centre line (integer
// geometry in 1/256 cell, 64-bit), and a prefix XOR along each row turns parity into inside /
// outside. A centre exactly on an edge counts as left of it.
//
// Edges toggle parity bits and kept echoes set bits in two bit planes (parity toggles,
// occupied): one bit per cell, 32 cells a word, each row padded to whole words. With job[5]
// set (sensor_model.free_on_outline off) the edges between beams also set the bits of the cells
// they touch in a third plane, the outline, which the occupied buffer holds after its own plane
// (HEIGHT rows on): those cells get no free update (host/rasterize.cpp, ClearOutline). The row
// pass scans each row's toggles, writes the row of the (padded) update mask and clears the
// planes for the next scan; bits make the prefix XOR a few word operations and let edges meet
// in any order (XOR commutes). The row pass can also fuse the mask into the map (kernel stage 2,
// fuse.cl's arithmetic) and apply a pending map shift (shift.cl) on the way, so that a scan
// reads and writes each row once; every map cell it writes also goes into the level bitsets
// that stage 3 starts from (common.cl, StoreLevels), while the values are in registers.
//
// Two shapes, both exact:
//   elsewhere than on a CPU: rasterize_edges, one work-item per edge and per echo with atomics,
//     then rasterize_rows, one work-group of RASTER_GROUP work-items per row;
//   on a CPU (RASTER_SERIAL 1, RASTER_GROUP 1): rasterize_bands alone, one work-item per band
//     of rows walking every edge and echo for its rows without atomics, then its rows.
//
// Build options: FIXED_BITS, UPDATE_NONE, UPDATE_FREE, UPDATE_OCCUPIED, L_FREE, L_OCCUPIED,
// L_MIN, L_MAX, RASTER_GROUP (a power of two up to 256), RASTER_SERIAL (0 or 1), and those of
// common.cl. Arguments after those of the row pass: the level bitsets (strong, weak), the
// source's level bitsets and whether to shift them (RasterMap).
//
// The job buffer, written by the host each scan: a header of 8 ints, job[0] vertex count n,
// job[1] count m of occupied cells on the rasterized rows, job[2] first row r0, job[3] end row
// r1 (both clipped to the map, r0 < r1), job[4] count of occupied cells on other rows, job[5]
// 1 when the outline's cells get no free update (RasterJob::clear_outline); then
// the n vertices (x, y in fixed point, map cell coordinates), the m occupied cells on the
// rasterized rows sorted by row (row * WIDTH + col), r1 - r0 + 1 offsets into them (row r's
// cells are [offset[r - r0], offset[r - r0 + 1])), and the occupied cells on other rows.
//
// Host side: src/opencl/rasterize.cpp; its rasterize_edges_arg, rasterize_rows_arg and
// rasterize_bands_arg number the arguments of the kernels below: change both together.

#define RASTER_WORDS ((WIDTH + 31) / 32)
#define RASTER_FIXED_ONE (1L << FIXED_BITS)
#define RASTER_FIXED_HALF (RASTER_FIXED_ONE / 2)
#define RASTER_WORDS_PER_ITEM ((RASTER_WORDS + RASTER_GROUP - 1) / RASTER_GROUP)
#define RASTER_CARRY ((RASTER_GROUP + 31) / 32)

// The parts of the job buffer.
#define JOB_VERTICES(job) ((job) + 8)
#define JOB_CELLS(job) (JOB_VERTICES(job) + 2 * (job)[0])
#define JOB_OFFSETS(job) (JOB_CELLS(job) + (job)[1])
#define JOB_OTHER_CELLS(job) (JOB_OFFSETS(job) + (job)[3] - (job)[2] + 1)
// The outline plane, after the occupied plane in the same buffer.
#define OUTLINE_PLANE(occupied) ((occupied) + HEIGHT * RASTER_WORDS)

// floor(a / b) for b > 0.
long RasterFloorDiv(long a, long b) {
  const long q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

// The edge (x0, y0) -> (x1, y1) crosses the centre line yc = 256 r + 128 of row r at
// x = x0 + (yc - y0) * (x1 - x0) / (y1 - y0); the first column whose centre 256 c + 128 lies
// right of it is c = floor((x - 128) / 256) + 1 = floor(num / den) + 1 with
//   num = (x0 - 128) * (y1 - y0) + (yc - y0) * (x1 - x0),  den = (y1 - y0) * 256,
// signs flipped so that den > 0 (host/rasterize.cpp, CrossingColumn). From one row to the next
// num grows by 256 (x1 - x0), so the kernel steps the quotient and remainder of that division
// instead of dividing per row: the same integers, two divisions per edge.
// On a CPU (RASTER_SERIAL 1) each work-item of rasterize_bands owns a band of rows and sets
// their bits without atomics. Elsewhere every edge and echo is a work-item of rasterize_edges,
// and the bits are set with atomics.
#if RASTER_SERIAL
#define RASTER_XOR(p, bits) (*(p) ^= (bits))
#define RASTER_OR(p, bits) (*(p) |= (bits))
#else
#define RASTER_XOR(p, bits) atomic_xor((p), (bits))
#define RASTER_OR(p, bits) atomic_or((p), (bits))
#endif

// Toggles the parity bits of edge i of the ring `v` (n vertices) on its rows within [lo, hi).
void RasterEdge(__global const int* v, int n, int i, long lo, long hi, __global uint* toggles) {
  const int j = i + 1 == n ? 0 : i + 1;
  const long x0 = v[2 * i], y0 = v[2 * i + 1];
  const long x1 = v[2 * j], y1 = v[2 * j + 1];
  if (y0 == y1) return;
  const long ylo = min(y0, y1), yhi = max(y0, y1);
  // Rows whose centre yc = 256 r + 128 satisfies ylo <= yc < yhi.
  const long ra =
      max(RasterFloorDiv(ylo - RASTER_FIXED_HALF + RASTER_FIXED_ONE - 1, RASTER_FIXED_ONE), lo);
  const long rb =
      min(RasterFloorDiv(yhi - RASTER_FIXED_HALF + RASTER_FIXED_ONE - 1, RASTER_FIXED_ONE), hi);
  if (ra >= rb) return;
  const long sign = y1 > y0 ? 1 : -1;
  const long den = sign * (y1 - y0) * RASTER_FIXED_ONE;
  const long num = sign * ((x0 - RASTER_FIXED_HALF) * (y1 - y0) +
                           (ra * RASTER_FIXED_ONE + RASTER_FIXED_HALF - y0) * (x1 - x0));
  const long step = sign * RASTER_FIXED_ONE * (x1 - x0);
  long q = RasterFloorDiv(num, den), rem = num - q * den;
  const long step_q = RasterFloorDiv(step, den), step_rem = step - step_q * den;
  for (long r = ra; r < rb; ++r) {
    const long k = clamp(q + 1, 0L, (long)WIDTH);
    if (k < WIDTH) RASTER_XOR(&toggles[r * RASTER_WORDS + (k >> 5)], 1u << (uint)(k & 31));
    q += step_q;
    rem += step_rem;
    if (rem >= den) {
      rem -= den;
      ++q;
    }
  }
}

// OutlineColumns() of src/core/kernel_params.cpp: the columns [*c_lo, *c_hi] of row r that the
// edge (x0, y0) -> (x1, y1) touches (its part with 256 r <= y <= 256 (r + 1)), false when it
// misses the row or the map's columns.
long RasterOutlineX(long x0, long y0, long x1, long y1, long y) {
  if (y == y0) return x0;
  if (y == y1) return x1;
  const long sign = y1 > y0 ? 1 : -1;
  return x0 + RasterFloorDiv(sign * (y - y0) * (x1 - x0), sign * (y1 - y0));
}

bool RasterOutlineColumns(long x0, long y0, long x1, long y1, long r, int* c_lo, int* c_hi) {
  const long top = r * RASTER_FIXED_ONE, bottom = top + RASTER_FIXED_ONE;
  if (max(y0, y1) < top || min(y0, y1) > bottom) return false;
  long xa = x0, xb = x1;
  if (y0 != y1) {
    xa = RasterOutlineX(x0, y0, x1, y1, max(min(y0, y1), top));
    xb = RasterOutlineX(x0, y0, x1, y1, min(max(y0, y1), bottom));
  }
  const long lo = RasterFloorDiv(min(xa, xb), RASTER_FIXED_ONE);
  const long hi = RasterFloorDiv(max(xa, xb), RASTER_FIXED_ONE);
  if (hi < 0 || lo >= WIDTH) return false;
  *c_lo = (int)max(lo, 0L);
  *c_hi = (int)min(hi, (long)WIDTH - 1);
  return true;
}

// Sets the outline bits of edge i (1 <= i <= n - 2: between two beams) on its rows within
// [lo, hi): rows ra .. rb with 256 r <= max y and 256 (r + 1) >= min y (host/rasterize.cpp,
// ClearOutline). An edge inside one row costs no division (RasterOutlineX takes a vertex's x).
void RasterOutline(__global const int* v, int i, long lo, long hi, __global uint* outline) {
  const long x0 = v[2 * i], y0 = v[2 * i + 1], x1 = v[2 * i + 2], y1 = v[2 * i + 3];
  const long ra = RasterFloorDiv(min(y0, y1) + RASTER_FIXED_ONE - 1, RASTER_FIXED_ONE) - 1;
  const long rb = RasterFloorDiv(max(y0, y1), RASTER_FIXED_ONE);
  for (long r = max(ra, lo); r <= min(rb, hi - 1); ++r) {
    int c0, c1;
    if (!RasterOutlineColumns(x0, y0, x1, y1, r, &c0, &c1)) continue;
    for (int w = c0 >> 5; w <= (c1 >> 5); ++w) {
      const int a = max(c0 - 32 * w, 0), b = min(c1 - 32 * w, 31);
      const uint bits = (0xffffffffu >> (31 - (b - a))) << a;
      RASTER_OR(&outline[r * RASTER_WORDS + w], bits);
    }
  }
}

// Marks kept echo `cell` (row * WIDTH + col) in the occupied plane.
void RasterEcho(int cell, __global uint* occupied) {
  const int r = cell / WIDTH, c = cell % WIDTH;
  RASTER_OR(&occupied[r * RASTER_WORDS + (c >> 5)], 1u << (uint)(c & 31));
}

// A kept echo on a row no row pass rewrites goes straight into the mask, as the host does; no
// other work-item writes that row, so this cannot race.
void RasterOtherEcho(int cell, __global uchar* update) {
  update[CELL(cell / WIDTH, cell % WIDTH)] = UPDATE_OCCUPIED;
}

// Global size n + job[1] + job[4] rounded up (not used with RASTER_SERIAL): work-item i is edge
// i, or an occupied cell.
__kernel void rasterize_edges(__global const int* job, __global uint* toggles,
                              __global uint* occupied, __global uchar* update) {
  const int i = get_global_id(0);
  const int n = job[0], m = job[1], r0 = job[2], r1 = job[3], other = job[4];
  if (i < n) {
    RasterEdge(JOB_VERTICES(job), n, i, r0, r1, toggles);
    if (job[5] && i >= 1 && i + 1 < n) {
      RasterOutline(JOB_VERTICES(job), i, r0, r1, OUTLINE_PLANE(occupied));
    }
  } else if (i < n + m) {
    RasterEcho(JOB_CELLS(job)[i - n], occupied);
  } else if (i < n + m + other) {
    RasterOtherEcho(JOB_OTHER_CELLS(job)[i - n - m], update);
  }
}

// Sixteen mask values from sixteen parity and occupied bits (occupied wins; the outline's
// parity bits cleared before), zero on lanes past the map's width (c0 is the column of lane 0).
uchar16 RasterExpand16(uint parity, uint occupied, int c0) {
  const ushort16 lane = (ushort16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const ushort16 p = ((ushort16)((ushort)parity) >> lane) & (ushort16)(1);
  const ushort16 o = ((ushort16)((ushort)occupied) >> lane) & (ushort16)(1);
  const ushort16 inside =
      select((ushort16)(UPDATE_NONE), (ushort16)(UPDATE_FREE), p != (ushort16)(0));
  const ushort16 value = select(inside, (ushort16)(UPDATE_OCCUPIED), o != (ushort16)(0));
  return convert_uchar16(value & as_ushort16(InsideLanes16(c0)));
}

// Kernel stage 2 folded into the row pass (fuse.cl's arithmetic): the map cells `m` of columns
// c0 .. c0 + 15 with the mask vector `u` fused in, 0 past the width.
// In 16 bits: L_MIN .. L_MAX lie inside the range of short, so clamping the saturated sum gives
// the same value as clamping the exact one.
short16 RasterFuse16(short16 m, uchar16 u, int c0) {
  const short16 value = convert_short16(u);
  const short16 delta =
      select(select((short16)(0), (short16)(L_OCCUPIED), value == (short16)(UPDATE_OCCUPIED)),
             (short16)(L_FREE), value == (short16)(UPDATE_FREE));
  const short16 fused = clamp(add_sat(m, delta), (short16)(L_MIN), (short16)(L_MAX));
  return fused & InsideLanes16(c0);
}

// What the row pass does to the map besides writing the mask: nothing (src null), fuse in
// place (src == dst), or shift src into dst by (dx, dy) and fuse there. Whenever it writes map
// cells it also writes their level bits (strong, weak; common.cl) for stage 3: from the values
// (StoreLevels), or, on rows it only shifts and with shift_levels set, by shifting src's level
// bits (src_strong, src_weak) the same way, which the host allows when those are up to date and
// an unknown cell is on no level.
typedef struct {
  __global const short* src;
  __global short* dst;
  int dx, dy;
  __global uint* strong;
  __global uint* weak;
  __global const uint* src_strong;
  __global const uint* src_weak;
  int shift_levels;
} RasterMap;

// Level uints [w0, w1) of row r (columns 32 w ..) of `dst` after the map shift by (dx, dy):
// those of columns 32 w + dx .. of row r + dy of `src`, 0 where that cell is outside the map
// and past the width. Source bits past the width are 0.
void RasterShiftLevels(__global const uint* src, __global uint* dst, int r, int w0, int w1, int dx,
                       int dy) {
  __global uint* out = dst + r * LEVEL_WORDS;
  const int sr = r + dy;
  if (sr < 0 || sr >= HEIGHT) {
    for (int w = w0; w < w1; ++w) out[w] = 0u;
    return;
  }
  __global const uint* row = src + sr * LEVEL_WORDS;
  // Column 32 w + dx is bit s of uint w + q.
  const int q = dx >= 0 ? dx / 32 : -((31 - dx) / 32), s = dx - 32 * q;
  for (int w = w0; w < w1; ++w) {
    const int j = w + q;
    const ulong lo = (j >= 0 && j < LEVEL_WORDS) ? row[j] : 0u;
    const ulong hi = (j + 1 >= 0 && j + 1 < LEVEL_WORDS) ? row[j + 1] : 0u;
    const uint v = (uint)(((hi << 32) | lo) >> s);
    const int inside = WIDTH - 32 * w;  // at least 1: w is a word of the row
    out[w] = inside >= 32 ? v : v & ((1u << inside) - 1u);
  }
}

// Turns words [w0, w1) of row r into mask values; `fill` is all ones when the parity left of
// word w0 is odd. Clears the words of the three planes for the next scan, and fuses into the
// map.
void RasterWords(__global uint* toggles, __global uint* occupied, __global uchar* update,
                 RasterMap map, int r, int w0, int w1, uint fill) {
  __global uint* row_toggles = toggles + r * RASTER_WORDS;
  __global uint* row_occupied = occupied + r * RASTER_WORDS;
  __global uint* row_outline = OUTLINE_PLANE(occupied) + r * RASTER_WORDS;
  for (int w = w0; w < w1; ++w) {
    uint x = row_toggles[w];
    const uint o = row_occupied[w];
    const uint edge = row_outline[w];
    row_toggles[w] = 0;
    row_occupied[w] = 0;
    row_outline[w] = 0;
    // Inclusive prefix XOR of the word's bits, then the parity carried in from the left.
    x ^= x << 1;
    x ^= x << 2;
    x ^= x << 4;
    x ^= x << 8;
    x ^= x << 16;
    x ^= fill;
    fill = (x >> 31) ? 0xffffffffu : 0u;
    x &= ~edge;  // after the carry: the outline changes no parity
    // Whole aligned vectors: the padded row has room up to the next multiple of 32 columns.
    const int c0 = 32 * w, k = CELL(r, c0);
    const uchar16 lo = RasterExpand16(x, o, c0), hi = RasterExpand16(x >> 16, o >> 16, c0 + 16);
    *(__global uchar16*)(update + k) = lo;
    *(__global uchar16*)(update + k + 16) = hi;
    if (map.src == 0) continue;
    const short16 m_lo = RasterFuse16(ShiftedCells(map.src, r, c0, map.dx, map.dy), lo, c0);
    const short16 m_hi =
        RasterFuse16(ShiftedCells(map.src, r, c0 + 16, map.dx, map.dy), hi, c0 + 16);
    *(__global short16*)(map.dst + k) = m_lo;
    *(__global short16*)(map.dst + k + 16) = m_hi;
    StoreLevels(m_lo, m_hi, r, c0, map.strong, map.weak);
  }
}

// Words [w0, w1) of a row outside the rasterized rows while the map shifts: the shift only.
void RasterShiftWords(RasterMap map, int r, int w0, int w1) {
  if (map.shift_levels) {
    for (int c0 = 32 * w0; c0 < 32 * w1; c0 += 16) {
      *(__global short16*)(map.dst + CELL(r, c0)) = ShiftedCells(map.src, r, c0, map.dx, map.dy);
    }
    RasterShiftLevels(map.src_strong, map.strong, r, w0, w1, map.dx, map.dy);
    RasterShiftLevels(map.src_weak, map.weak, r, w0, w1, map.dx, map.dy);
    return;
  }
  for (int c0 = 32 * w0; c0 < 32 * w1; c0 += 32) {
    const short16 m_lo = ShiftedCells(map.src, r, c0, map.dx, map.dy);
    const short16 m_hi = ShiftedCells(map.src, r, c0 + 16, map.dx, map.dy);
    *(__global short16*)(map.dst + CELL(r, c0)) = m_lo;
    *(__global short16*)(map.dst + CELL(r, c0 + 16)) = m_hi;
    StoreLevels(m_lo, m_hi, r, c0, map.strong, map.weak);
  }
}

// Rewrites row r's mask and does `map`'s work on it; rows outside [job[2], job[3]) only shift.
// On a CPU (RASTER_GROUP 1) one work-item does the row left to right. Elsewhere a work-group of
// RASTER_GROUP work-items does it: work-item t owns a run of whole words, and `carry` (local
// memory of RASTER_CARRY words, declared by the kernel) holds one bit per work-item, the parity
// of its run, so that each knows the parity left of its run.
void RasterRow(__global const int* job, __global uint* toggles, __global uint* occupied,
               __global uchar* update, RasterMap map, int r, __local uint* carry) {
  const bool rasterized = r >= job[2] && r < job[3];
#if RASTER_GROUP == 1
  if (rasterized) {
    RasterWords(toggles, occupied, update, map, r, 0, RASTER_WORDS, 0u);
  } else {
    RasterShiftWords(map, r, 0, RASTER_WORDS);
  }
#else
  const int t = get_local_id(0);
  const int w0 = min(t * RASTER_WORDS_PER_ITEM, RASTER_WORDS);
  const int w1 = min(w0 + RASTER_WORDS_PER_ITEM, RASTER_WORDS);
  if (!rasterized) {  // the same for the whole work-group
    RasterShiftWords(map, r, w0, w1);
    return;
  }
  __global uint* row_toggles = toggles + r * RASTER_WORDS;
  if (t < RASTER_CARRY) carry[t] = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  uint run = 0;
  for (int w = w0; w < w1; ++w) run ^= row_toggles[w];
  if (popcount(run) & 1) atomic_or(&carry[t >> 5], 1u << (t & 31));
  barrier(CLK_LOCAL_MEM_FENCE);

  // Parity left of this run: the XOR of the runs of work-items 0 .. t - 1.
  uint left = popcount(carry[t >> 5] & ((1u << (t & 31)) - 1u));
  for (int k = 0; k < (t >> 5); ++k) left += popcount(carry[k]);
  RasterWords(toggles, occupied, update, map, r, w0, w1, (left & 1) ? 0xffffffffu : 0u);
#endif
}

// The row of work-group (or, on a CPU, work-item) g in dimension 1: row_first + g, or none.
bool RasterRowOf(int row_first, int row_end, int* r) {
#if RASTER_GROUP == 1
  *r = row_first + (int)get_global_id(1);
#else
  *r = row_first + (int)get_group_id(1);
#endif
  return *r < row_end;
}

// The row pass elsewhere than on a CPU: global size (RASTER_GROUP, rows), local size
// (RASTER_GROUP, 1), work-group g rewrites row row_first + g of [row_first, row_end). With src
// null it writes the mask of the rasterized rows only. With src == dst it also fuses the mask
// into the map in place (kernel stage 2 in the same pass; dx = dy = 0). With a pending map
// shift it runs over every row that can hold a known cell or a level bit, before or after
// (the host's RowSpan bookkeeping; the others are unknown and on no level either way), writing
// dst(r, c) = src(r + dy, c + dx) and fusing the rasterized rows on the way.
// src/opencl/rasterize.cpp defers the row pass of Rasterize() to learn which.
__kernel void rasterize_rows(__global const int* job, __global uint* toggles,
                             __global uint* occupied, __global uchar* update,
                             __global const short* src, __global short* dst, int dx, int dy,
                             int row_first, int row_end, __global uint* strong, __global uint* weak,
                             __global const uint* src_strong, __global const uint* src_weak,
                             int shift_levels) {
  __local uint carry[RASTER_CARRY];
  int r;
  if (!RasterRowOf(row_first, row_end, &r)) return;
  const RasterMap map = {src, dst, dx, dy, strong, weak, src_strong, src_weak, shift_levels};
  RasterRow(job, toggles, occupied, update, map, r, carry);
}

#if RASTER_SERIAL
// The whole of stage 1 (and 2) on a CPU: band b = first_band + work-item owns rows
// [row_first + b * band, row_first + (b + 1) * band) within [row_first, row_end). It toggles the
// bits of every edge and echo on its rasterized rows, then runs the row pass on its rows with
// src / dst as rasterize_rows does; the host sorted the occupied cells by row, so each band
// reads only its own. Band 0 also writes the echoes outside the rasterized rows. Global size:
// the number of bands, one work-item per group (first_band 0), or one band per command when
// the host splits the bands over devices.
__kernel void rasterize_bands(__global const int* job, __global uint* toggles,
                              __global uint* occupied, __global uchar* update,
                              __global const short* src, __global short* dst, int dx, int dy,
                              int row_first, int row_end, int band, __global uint* strong,
                              __global uint* weak, __global const uint* src_strong,
                              __global const uint* src_weak, int shift_levels, int first_band) {
  const int b = first_band + (int)get_global_id(0);
  const int ba = row_first + b * band, bb = min(ba + band, row_end);
  if (ba >= bb) return;
  const int n = job[0], r0 = job[2], r1 = job[3];
  const int lo = max(ba, r0), hi = min(bb, r1);
  if (lo < hi) {
    for (int i = 0; i < n; ++i) RasterEdge(JOB_VERTICES(job), n, i, lo, hi, toggles);
    if (job[5]) {
      for (int i = 1; i + 1 < n; ++i) {
        RasterOutline(JOB_VERTICES(job), i, lo, hi, OUTLINE_PLANE(occupied));
      }
    }
    __global const int* cells = JOB_CELLS(job);
    __global const int* offsets = JOB_OFFSETS(job);
    for (int i = offsets[lo - r0]; i < offsets[hi - r0]; ++i) RasterEcho(cells[i], occupied);
  }
  if (b == 0) {
    for (int i = 0; i < job[4]; ++i) RasterOtherEcho(JOB_OTHER_CELLS(job)[i], update);
  }
  const RasterMap map = {src, dst, dx, dy, strong, weak, src_strong, src_weak, shift_levels};
  for (int r = ba; r < bb; ++r) RasterRow(job, toggles, occupied, update, map, r, 0);
}
#endif
