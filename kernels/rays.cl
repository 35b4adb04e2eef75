// The conventional inverse sensor model (the paper's baseline, section V.B): one Bresenham ray
// per kept echo, every map cell on it updated as often as rays cross it. Mirrors host/rays.cpp.
// rays_cast adds each ray's log-odds into a per-cell int delta with atomic_add, so the sums do
// not depend on the order the rays run in; rays_fuse adds the deltas into the map once, clamps,
// and clears the deltas for the next scan.
//
// Build options: WIDTH, HEIGHT, L_FREE, L_OCCUPIED, L_MIN, L_MAX.
//
// The job buffer, written by the host each scan: job[0] ray count, job[1] origin column,
// job[2] origin row, job[3] unused, then the end cells (col, row) of the rays. Origins and
// ends may lie outside the map; cells outside are skipped.

__kernel void rays_cast(__global const int* job, __global int* delta) {
  const int i = get_global_id(0);
  if (i >= job[0]) return;
  const int x0 = job[1], y0 = job[2];
  const int x1 = job[4 + 2 * i], y1 = job[4 + 2 * i + 1];
  const int dx = (int)abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -(int)abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  int x = x0, y = y0;
  while (true) {
    const bool end = x == x1 && y == y1;
    if (x >= 0 && x < WIDTH && y >= 0 && y < HEIGHT) {
      atomic_add(&delta[y * WIDTH + x], end ? L_OCCUPIED : L_FREE);
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

// One work-item per cell of the contiguous range [first, first + count) (whole rows).
__kernel void rays_fuse(__global short* map, __global int* delta, int first, int count) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const int k = first + i;
  map[k] = (short)clamp((int)map[k] + delta[k], L_MIN, L_MAX);
  delta[k] = 0;
}
