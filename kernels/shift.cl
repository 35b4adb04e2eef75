// The integer map shift of the vehicle-on-a-circle alignment (paper III, eqs. 4, 5). Mirrors
// host/shift.cpp: new(r, c) = old(r + dy, c + dx), unknown (0) where there is no old cell.
// The host side writes into the second map buffer and swaps the two, so rows never overlap;
// shifts of a whole map or more are a fill, not this kernel.
//
// Build options: WIDTH, HEIGHT. Global size (WIDTH rounded up, HEIGHT).

__kernel void shift_map(__global const short* src, __global short* dst, int dx, int dy) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= WIDTH) return;
  const int sr = r + dy, sc = c + dx;
  const bool inside = sr >= 0 && sr < HEIGHT && sc >= 0 && sc < WIDTH;
  dst[r * WIDTH + c] = inside ? src[sr * WIDTH + sc] : (short)0;
}
