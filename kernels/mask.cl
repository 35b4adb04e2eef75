// Kernel stage 3b: the polygon mask of the conservative polygon (polygon.shape inside), and the
// per-scan veto of stage 3. Mirrors host/mask.cpp and host/classify.cpp's veto; host side:
// src/opencl/mask.cpp (argument namespaces mask_veto_arg, mask_unconfirmed_arg, mask_rows_arg).
//
// mask_veto: one work-item per row of the free mask: the cells holding an echo of this scan
// (a bitset the host uploads) are not free, whatever the map holds.
// mask_unconfirmed: one work-item per row: the margin's sources of the map, its cells with
// log-odds >= 0 (occupied, or never seen free more often than occupied).
// mask_rows: one work-item per row of the polygon mask: the free mask, plus the cells within
// OPENING_RADIUS of the sensor's cell with log-odds below 0 and no echo, less every cell with a
// source (unconfirmed, or an echo; not a cell the face layer's outline touches, face_seen) within
// MARGIN_CELLS in the margin's cone of one of the views (the scanners, fixed point, at most 16),
// less the cells near a face (face_near), plus the sensor's own cell. Bitsets of BIT_WORDS ulong
// words a row (common.cl).
//
// Build options: those of common.cl, OPENING_RADIUS, MARGIN_CELLS, CONE_COS, CONE_SIN (the
// cone's half-angle times 2^20) and MARGIN_ALL (1: the margin all around).

__kernel void mask_veto(__global ulong* free, __global const ulong* echo, int first_row,
                        int end_row) {
  const int r = first_row + (int)get_global_id(0);
  if (r >= end_row) return;
  for (int w = 0; w < BIT_WORDS; ++w) free[r * BIT_WORDS + w] &= ~echo[r * BIT_WORDS + w];
}

__kernel void mask_unconfirmed(__global const short* map, __global ulong* unconfirmed,
                               int first_row, int end_row) {
  const int r = first_row + (int)get_global_id(0);
  if (r >= end_row) return;
  for (int w = 0; w < BIT_WORDS; ++w) {
    ulong bits = 0;
    for (int i = 0; i < 64 && 64 * w + i < WIDTH; ++i) {
      bits |= (ulong)(map[CELL(r, 64 * w + i)] >= 0) << i;
    }
    unconfirmed[r * BIT_WORDS + w] = bits;
  }
}

// Bits start .. start + 63 of a bitset row, 0 outside it.
ulong MaskBits64(__global const ulong* row, int start) {
  const int w = start >> 6, offset = start & 63;
  const ulong lo = (w >= 0 && w < BIT_WORDS) ? row[w] : 0;
  if (offset == 0) return lo;
  const ulong hi = (w + 1 >= 0 && w + 1 < BIT_WORDS) ? row[w + 1] : 0;
  return (lo >> offset) | (hi << (64 - offset));
}

// InMarginCone() of src/core/include/core/backend.hpp.
bool MaskInCone(int sensor_x, int sensor_y, int col, int row, int dx, int dy) {
#if MARGIN_ALL
  return true;
#else
  const long vx = (long)col * (1 << FIXED_BITS) + (1 << (FIXED_BITS - 1)) - sensor_x;
  const long vy = (long)row * (1 << FIXED_BITS) + (1 << (FIXED_BITS - 1)) - sensor_y;
  const long e1x = (long)dx * CONE_COS - (long)dy * CONE_SIN;
  const long e1y = (long)dx * CONE_SIN + (long)dy * CONE_COS;
  const long e2x = (long)dx * CONE_COS + (long)dy * CONE_SIN;
  const long e2y = -(long)dx * CONE_SIN + (long)dy * CONE_COS;
  const bool after_e2 = e2x * vy - e2y * vx >= 0;
  const bool before_e1 = vx * e1y - vy * e1x >= 0;
  return CONE_COS >= 0 ? (after_e2 && before_e1) : (after_e2 || before_e1);
#endif
}

// MaskInCone() from any of the margin's views (InMarginConeOfAny() of
// src/core/include/core/backend.hpp).
bool MaskInConeOfAny(const int* view_x, const int* view_y, int view_count, int col, int row, int dx,
                     int dy) {
#if MARGIN_ALL
  return true;
#endif
  for (int i = 0; i < view_count; ++i) {
    if (MaskInCone(view_x[i], view_y[i], col, row, dx, dy)) return true;
  }
  return false;
}

// The margin's cells among the candidates `out` of row r: those with a source (unconfirmed or
// echo, and not seen) within MARGIN_CELLS in the cone of one of the views, into kill.
void MaskMargin(__global const ulong* unconfirmed, __global const ulong* echo,
                __global const ulong* seen, int r, const int* view_x, const int* view_y,
                int view_count, const ulong* out, ulong* kill) {
  for (int dy = -MARGIN_CELLS; dy <= MARGIN_CELLS; ++dy) {
    const int rr = r + dy;
    if (rr < 0 || rr >= HEIGHT) continue;
    __global const ulong* occ = unconfirmed + rr * BIT_WORDS;
    __global const ulong* ech = echo + rr * BIT_WORDS;
    __global const ulong* see = seen + rr * BIT_WORDS;
    for (int dx = -MARGIN_CELLS; dx <= MARGIN_CELLS; ++dx) {
      if (dx == 0 && dy == 0) continue;
      for (int w = 0; w < BIT_WORDS; ++w) {
        const int at = w * 64 + dx;
        ulong candidates =
            out[w] & ~kill[w] & (MaskBits64(occ, at) | MaskBits64(ech, at)) & ~MaskBits64(see, at);
        while (candidates != 0) {
          const int bit = 63 - (int)clz(candidates & (~candidates + 1UL));
          candidates &= candidates - 1;
          if (MaskInConeOfAny(view_x, view_y, view_count, w * 64 + bit, r, dx, dy)) {
            kill[w] |= 1UL << bit;
          }
        }
      }
    }
  }
}

__kernel void mask_rows(__global const ulong* free, __global const ulong* echo,
                        __global const ulong* face_near, __global const ulong* face_seen,
                        __global const ulong* unconfirmed, __global const short* map,
                        __global ulong* mask, int first_row, int end_row, int span_begin,
                        int span_end, int sensor_col, int sensor_row, int16 view_x16,
                        int16 view_y16, int view_count) {
  const int r = first_row + (int)get_global_id(0);
  if (r >= end_row) return;
  __global ulong* row = mask + r * BIT_WORDS;
  if (r < span_begin || r >= span_end) {
    for (int w = 0; w < BIT_WORDS; ++w) row[w] = 0;
    return;
  }
  ulong out[BIT_WORDS];
  for (int w = 0; w < BIT_WORDS; ++w) out[w] = free[r * BIT_WORDS + w];
  __global const ulong* ech = echo + r * BIT_WORDS;
  if (abs(r - sensor_row) <= OPENING_RADIUS) {
    for (int c = max(0, sensor_col - OPENING_RADIUS);
         c <= min(WIDTH - 1, sensor_col + OPENING_RADIUS); ++c) {
      if (map[CELL(r, c)] < 0 && !((ech[c >> 6] >> (c & 63)) & 1)) out[c >> 6] |= 1UL << (c & 63);
    }
  }
#if MARGIN_CELLS > 0
  ulong kill[BIT_WORDS];
  for (int w = 0; w < BIT_WORDS; ++w) kill[w] = 0;
  int view_x[16], view_y[16];
  vstore16(view_x16, 0, view_x);
  vstore16(view_y16, 0, view_y);
  MaskMargin(unconfirmed, echo, face_seen, r, view_x, view_y, view_count, out, kill);
  for (int w = 0; w < BIT_WORDS; ++w) out[w] &= ~kill[w];
#endif
  for (int w = 0; w < BIT_WORDS; ++w) out[w] &= ~face_near[r * BIT_WORDS + w];
  if (r == sensor_row) out[sensor_col >> 6] |= 1UL << (sensor_col & 63);
  for (int w = 0; w < BIT_WORDS; ++w) row[w] = out[w];
}
