// The conventional inverse sensor model (the paper's baseline, section V.B): one Bresenham ray
// per kept echo, every map cell on it updated as often as rays cross it. Mirrors host/rays.cpp.
// rays_cast adds each ray's log-odds into a per-cell int delta with atomic_add, so the sums do
// not depend on the order the rays run in; rays_fuse adds the deltas into the map once, clamps,
// and clears the deltas for the next scan.
//
// Build options: L_FREE, L_OCCUPIED, L_MIN, L_MAX (and those of common.cl).
//
// The job buffer, written by the host each scan: a header of 8 ints, job[0] ray count, job[1]
// origin column, job[2] origin row, then the end cells (col, row) of the rays. Origins and
// ends may lie outside the map; cells outside are skipped.
//
// Host side: src/opencl/rays.cpp; its rays_cast_arg and rays_fuse_arg number the arguments of the
// kernels below: change both together.

__kernel void rays_cast(__global const int* job, __global int* delta) {
  const int i = get_global_id(0);
  if (i >= job[0]) return;
  const int x0 = job[1], y0 = job[2];
  const int x1 = job[8 + 2 * i], y1 = job[8 + 2 * i + 1];
  const int dx = (int)abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -(int)abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  int x = x0, y = y0;
  while (true) {
    const bool end = x == x1 && y == y1;
    if (x >= 0 && x < WIDTH && y >= 0 && y < HEIGHT) {
      atomic_add(&delta[CELL(y, x)], end ? L_OCCUPIED : L_FREE);
    }
    if (end) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y += sy;
    }
  }
}

// Global size (row items, row_end - row_begin rounded up), as fuse.
__kernel void rays_fuse(__global short* map, __global int* delta, int row_begin, int row_end) {
  const int r = row_begin + (int)get_global_id(1);
  int v0, v1;
  if (r >= row_end || !RowVectors(&v0, &v1)) return;
  for (int v = v0; v < v1; ++v) {
    const int k = CELL(r, 16 * v);
    __global short16* m = (__global short16*)(map + k);
    __global int16* d = (__global int16*)(delta + k);
    const int16 fused = clamp(convert_int16(*m) + *d, L_MIN, L_MAX);
    *m = convert_short16(select((int16)(0), fused, InsideLanes(16 * v)));
    *d = (int16)(0);
  }
}
