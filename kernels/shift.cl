// The integer map shift of the vehicle-on-a-circle alignment (paper III, eqs. 4, 5). Mirrors
// host/shift.cpp: new(r, c) = old(r + dy, c + dx), unknown (0) where there is no old cell.
// The host writes into the second map buffer and swaps the two, so rows never overlap; shifts
// of a whole map or more are a fill, not this kernel.
//
// Build options: those of common.cl. Global size (row items, HEIGHT rounded up).
// The source load of 16 cells may start outside the source row (|dx| < WIDTH): it stays inside
// the padded buffer, and lanes without a source cell are zeroed.

__kernel void shift_map(__global const short* src, __global short* dst, int dx, int dy) {
  const int r = get_global_id(1);
  int v0, v1;
  if (r >= HEIGHT || !RowVectors(&v0, &v1)) return;
  const int sr = r + dy;
  const int16 lane = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  for (int v = v0; v < v1; ++v) {
    const int c0 = 16 * v;
    __global short16* out = (__global short16*)(dst + CELL(r, c0));
    if (sr < 0 || sr >= HEIGHT) {
      *out = (short16)(0);
      continue;
    }
    const int16 sc = lane + (int16)(c0 + dx);
    const int16 keep = (sc >= (int16)(0)) & (sc < (int16)(WIDTH)) & InsideLanes(c0);
    const int16 old = convert_int16(vload16(0, src + CELL(sr, c0 + dx)));
    *out = convert_short16(select((int16)(0), old, keep));
  }
}
