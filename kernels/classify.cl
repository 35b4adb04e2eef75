// Kernel stage 3: normalisation to free / not free with neighbourhood hysteresis, then the
// morphological opening of the free mask by a square of side 2 OPENING_RADIUS + 1 (paper IV.A).
// Mirrors host/classify.cpp.
//
// free0 = l <= T_LOW, or l <= T_HIGH with an 8-neighbour l <= T_LOW (neighbours inside the
// map only). The opening is separable: erosion along rows, then columns, then dilation along
// rows, then columns, over padded masks (common.cl). Cells outside the map are not free, and
// the zero padding says exactly that: an erosion window that leaves the map meets a 0, a
// dilation window gains nothing from it. PAD_X and PAD_Y are at least OPENING_RADIUS.
//
// Three kernels, because a column pass needs other rows' results of the pass before it:
//   classify_hysteresis_erode_rows   map -> free0 (a) -> row erosion (b)
//   classify_erode_cols_dilate_rows  b -> column erosion (a) -> row dilation (c)
//   classify_dilate_cols             c -> column dilation (free mask)
// Inside a kernel the second pass reads only its own row, which the work-group wrote before
// the barrier (the host keeps each row's work-items in one work-group).
//
// Every pass writes 0 to the lanes past the map's width, so the padding stays zero; the
// erosions and the column dilation get that for free (their window includes the lane's own,
// zero, cell or column), the row dilation masks it.
//
// Build options: T_LOW, T_HIGH, OPENING_RADIUS (and those of common.cl). Global size
// (row items, HEIGHT rounded up) for every kernel.

// Vector v (16 cells) of row r: -1 where an in-map cell of rows r - 1 .. r + 1 has l <= T_LOW,
// 0 elsewhere, including lanes past the width and vectors outside the row.
short16 ClassifyStrongColumn(__global const short* map, int r, int v) {
  if (v < 0 || v >= ROW_VECTORS) return (short16)(0);
  short16 strong = (short16)(0);
  for (int rr = max(r - 1, 0); rr <= min(r + 1, HEIGHT - 1); ++rr) {
    strong |= *(__global const short16*)(map + CELL(rr, 16 * v)) <= (short16)(T_LOW);
  }
  return strong & convert_short16(InsideLanes(16 * v));
}

// map -> padded free0 on vectors [v0, v1) of row r. Walks the vectors left to right carrying
// the strong columns of the vectors left and right of the current one; the 8-neighbourhood is
// the current column OR'd with its neighbours one lane left and right.
void ClassifyHysteresis(__global const short* map, __global uchar* out, int r, int v0, int v1) {
  short16 left = ClassifyStrongColumn(map, r, v0 - 1);
  short16 here = ClassifyStrongColumn(map, r, v0);
  for (int v = v0; v < v1; ++v) {
    const short16 right = ClassifyStrongColumn(map, r, v + 1);
    // Constant swizzles, not shuffle2(): they compile to one permute on every device.
    const short16 near = here | (short16)(left.sf, here.s0123, here.s4567, here.s89ab, here.scde) |
                         (short16)(here.s123, here.s4567, here.s89ab, here.scdef, right.s0);
    const int k = CELL(r, 16 * v);
    const short16 m = *(__global const short16*)(map + k);
    const short16 strong = m <= (short16)(T_LOW), weak = m <= (short16)(T_HIGH);
    const short16 free0 = (strong | (weak & near)) & convert_short16(InsideLanes(16 * v));
    *(__global uchar16*)(out + k) = convert_uchar16(free0 & (short16)(1));
    left = here;
    here = right;
  }
}

// The four window passes work on the masks' bytes only with AND and OR, so where 64 cells of
// a row lie inside the map and start 64-aligned (PAD_X and STRIDE are multiples of 64) they
// take them as one ulong8 instead of four uchar16: the same bytes, a quarter of the work. The
// rest of a row (its last cells, or a work-item's vectors on a GPU) goes 16 cells at a time.
#define CLASSIFY_WIDE(v, v1) ((v) % 4 == 0 && (v) + 4 <= (v1) && 16 * (v) + 64 <= WIDTH)

// 64 bytes from any address (as whole 16-byte loads).
ulong8 ClassifyLoad64(__global const uchar* p) {
  return (ulong8)(as_ulong2(vload16(0, p)), as_ulong2(vload16(1, p)), as_ulong2(vload16(2, p)),
                  as_ulong2(vload16(3, p)));
}

// AND of the row window c - OPENING_RADIUS .. c + OPENING_RADIUS.
void ClassifyErodeRows(__global const uchar* in, __global uchar* out, int r, int v0, int v1) {
  for (int v = v0; v < v1;) {
    const int k = CELL(r, 16 * v);
    if (CLASSIFY_WIDE(v, v1)) {
      ulong8 x = (ulong8)(~0ul);
      for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) x &= ClassifyLoad64(in + k + d);
      *(__global ulong8*)(out + k) = x;
      v += 4;
    } else {
      uchar16 x = (uchar16)(1);
      for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) x &= vload16(0, in + k + d);
      *(__global uchar16*)(out + k) = x;
      ++v;
    }
  }
}

// AND of the column window.
void ClassifyErodeCols(__global const uchar* in, __global uchar* out, int r, int v0, int v1) {
  for (int v = v0; v < v1;) {
    const int k = CELL(r, 16 * v);
    if (CLASSIFY_WIDE(v, v1)) {
      ulong8 x = (ulong8)(~0ul);
      for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) {
        x &= *(__global const ulong8*)(in + k + d * STRIDE);
      }
      *(__global ulong8*)(out + k) = x;
      v += 4;
    } else {
      uchar16 x = (uchar16)(1);
      for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) {
        x &= *(__global const uchar16*)(in + k + d * STRIDE);
      }
      *(__global uchar16*)(out + k) = x;
      ++v;
    }
  }
}

// OR of the row window, lanes past the width zeroed (wide chunks lie inside the map).
void ClassifyDilateRows(__global const uchar* in, __global uchar* out, int r, int v0, int v1) {
  for (int v = v0; v < v1;) {
    const int k = CELL(r, 16 * v);
    if (CLASSIFY_WIDE(v, v1)) {
      ulong8 x = (ulong8)(0);
      for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) x |= ClassifyLoad64(in + k + d);
      *(__global ulong8*)(out + k) = x;
      v += 4;
    } else {
      uchar16 x = (uchar16)(0);
      for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) x |= vload16(0, in + k + d);
      *(__global uchar16*)(out + k) = x & convert_uchar16(InsideLanes(16 * v) & 1);
      ++v;
    }
  }
}

// OR of the column window: the free mask.
__kernel void classify_dilate_cols(__global const uchar* in, __global uchar* free) {
  const int r = get_global_id(1);
  int v0, v1;
  if (r >= HEIGHT || !RowVectors(&v0, &v1)) return;
  for (int v = v0; v < v1;) {
    const int k = CELL(r, 16 * v);
    if (CLASSIFY_WIDE(v, v1)) {
      ulong8 x = (ulong8)(0);
      for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) {
        x |= *(__global const ulong8*)(in + k + d * STRIDE);
      }
      *(__global ulong8*)(free + k) = x;
      v += 4;
    } else {
      uchar16 x = (uchar16)(0);
      for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) {
        x |= *(__global const uchar16*)(in + k + d * STRIDE);
      }
      *(__global uchar16*)(free + k) = x;
      ++v;
    }
  }
}

__kernel void classify_hysteresis_erode_rows(__global const short* map, __global uchar* a,
                                             __global uchar* b) {
  const int r = get_global_id(1);
  int v0, v1;
  const bool active = r < HEIGHT && RowVectors(&v0, &v1);
  if (active) ClassifyHysteresis(map, a, r, v0, v1);
  barrier(CLK_GLOBAL_MEM_FENCE);
  if (active) ClassifyErodeRows(a, b, r, v0, v1);
}

__kernel void classify_erode_cols_dilate_rows(__global const uchar* b, __global uchar* a,
                                              __global uchar* c) {
  const int r = get_global_id(1);
  int v0, v1;
  const bool active = r < HEIGHT && RowVectors(&v0, &v1);
  if (active) ClassifyErodeCols(b, a, r, v0, v1);
  barrier(CLK_GLOBAL_MEM_FENCE);
  if (active) ClassifyDilateRows(a, c, r, v0, v1);
}
