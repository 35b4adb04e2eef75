// The integer map shift of the vehicle-on-a-circle alignment (paper III, eqs. 4, 5). Mirrors
// host/shift.cpp: new(r, c) = old(r + dy, c + dx), unknown (0) where there is no old cell.
// The host writes into the second map buffer and swaps the two, so rows never overlap; shifts
// of a whole map or more are a fill, not this kernel.
//
// Build options: those of common.cl. Global size (row items, HEIGHT rounded up). When a
// Fuse() follows, the shift runs inside the row pass instead (rasterize.cl).
//
// Host side: src/opencl/shift.cpp; its shift_map_arg numbers the arguments of the kernel below:
// change both together.

__kernel void shift_map(__global const short* src, __global short* dst, int dx, int dy) {
  const int r = get_global_id(1);
  int v0, v1;
  if (r >= HEIGHT || !RowVectors(&v0, &v1)) return;
  for (int v = v0; v < v1; ++v) {
    *(__global short16*)(dst + CELL(r, 16 * v)) = ShiftedCells(src, r, 16 * v, dx, dy);
  }
}
