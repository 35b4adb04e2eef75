// Kernel stage 4: the "in-sight edges" border-ray scan (paper IV.A, algorithm "In-sight Sorted
// Edges Detection"). Mirrors host/insight.cpp.
//
// insight_cast runs one work-item per border label (2 HEIGHT + 2 WIDTH rays, labels in the
// order of BorderCell() in src/backend.hpp): a Bresenham ray from the vehicle cell stops at its
// first not-free cell (the vehicle's own cell never stops it) or at the border cell, and the
// stop cell (row * WIDTH + col) goes to stop[label]. C_Edge, the distinct stop cells ordered by
// their smallest label, is a few thousand steps of bookkeeping that the host does on the stop
// cells it reads back (src/opencl_backend.cpp), as the host backend does.
//
// Build options: those of common.cl. The free mask is a bitset (common.cl).

#define INSIGHT_LABELS (2 * HEIGHT + 2 * WIDTH)

// The border cell of 0-based label l as (x = col, y = row): left column top to bottom, bottom
// row west to east, right column bottom to top, top row east to west.
int2 InsightBorderCell(int label0) {
  const int l = label0 + 1;
  if (l <= HEIGHT) return (int2)(0, HEIGHT - l);
  if (l <= HEIGHT + WIDTH) return (int2)(l - HEIGHT - 1, 0);
  if (l <= 2 * HEIGHT + WIDTH) return (int2)(WIDTH - 1, l - HEIGHT - WIDTH - 1);
  return (int2)(2 * HEIGHT + 2 * WIDTH - l, HEIGHT - 1);
}

__kernel void insight_cast(__global const ulong* free, __global int* stop, int vehicle_col,
                           int vehicle_row) {
  const int l = get_global_id(0);
  if (l >= INSIGHT_LABELS) return;
  const int2 target = InsightBorderCell(l);
  const int x0 = vehicle_col, y0 = vehicle_row, x1 = target.x, y1 = target.y;
  const int dx = (int)abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -(int)abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  // host::CastRay's loop: every step advances the major axis by one cell, so the ray reaches
  // the border cell after max(dx, -dy) steps; it stops earlier at the first not-free cell after
  // the vehicle's own.
  const int steps = max(dx, -dy);
  int err = dx + dy;
  int x = x0, y = y0;
  for (int s = 0; s < steps; ++s) {
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y += sy;
    }
    if (!((free[y * BIT_WORDS + (x >> 6)] >> (x & 63)) & 1)) break;
  }
  stop[l] = y * WIDTH + x;
}
