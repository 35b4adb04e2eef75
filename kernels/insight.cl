// Kernel stage 4: the "in-sight edges" border-ray scan (paper IV.A, algorithm "In-sight Sorted
// Edges Detection"). Mirrors host/insight.cpp.
//
// insight_cast runs one work-item per border label (2 HEIGHT + 2 WIDTH rays, labels in the
// order of BorderCell() in src/backend.hpp): a Bresenham ray from the vehicle cell stops at its
// first not-free cell (the vehicle's own cell never stops it) or at the border cell. The stop
// cell goes to stop[label], and atomic_min keeps the smallest label per cell in T (`label`), so
// the result does not depend on the order the rays run in. insight_compact, one work-group,
// writes C_Edge: the distinct stop cells ordered by their smallest label, as
// edges[0] = count, edges[1 ..] = row * WIDTH + col; then it resets T for the next scan.
//
// Build options: those of common.cl. The free mask is padded (common.cl); stop cells and C_Edge
// are plain row * WIDTH + col.

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

__kernel void insight_cast(__global const uchar* free, __global int* label, __global int* stop,
                           int vehicle_col, int vehicle_row) {
  const int l = get_global_id(0);
  if (l >= INSIGHT_LABELS) return;
  const int2 target = InsightBorderCell(l);
  const int x0 = vehicle_col, y0 = vehicle_row, x1 = target.x, y1 = target.y;
  const int dx = (int)abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -(int)abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  // host::CastRay's loop, stepped by padded index: every step advances the major axis by one
  // cell, so the ray reaches the border cell after max(dx, -dy) steps; it stops earlier at the
  // first not-free cell after the vehicle's own.
  const int steps = max(dx, -dy);
  int err = dx + dy;
  int k = CELL(y0, x0);
  for (int s = 0; s < steps; ++s) {
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      k += sx;
    }
    if (e2 <= dx) {
      err += dx;
      k += sy * STRIDE;
    }
    if (!free[k]) break;
  }
  const int cell = (k / STRIDE - PAD_Y) * WIDTH + k % STRIDE - PAD_X;
  stop[l] = cell;
  atomic_min(&label[cell], l);
}

// One work-group of any size; `sums` holds one int per work-item. Work-item t owns a run of
// consecutive labels; an exclusive prefix sum over the runs' counts places each run's cells.
__kernel void insight_compact(__global const int* stop, __global int* label, __global int* edges,
                              __local int* sums) {
  const int t = get_local_id(0), group = get_local_size(0);
  const int per = (INSIGHT_LABELS + group - 1) / group;
  const int l0 = min(t * per, INSIGHT_LABELS), l1 = min(l0 + per, INSIGHT_LABELS);
  int count = 0;
  for (int l = l0; l < l1; ++l) count += label[stop[l]] == l;
  sums[t] = count;
  barrier(CLK_LOCAL_MEM_FENCE);
  // Inclusive scan (Hillis-Steele).
  for (int offset = 1; offset < group; offset <<= 1) {
    const int add = t >= offset ? sums[t - offset] : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    sums[t] += add;
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  int at = 1 + sums[t] - count;
  for (int l = l0; l < l1; ++l) {
    const int cell = stop[l];
    if (label[cell] == l) edges[at++] = cell;
  }
  if (t == group - 1) edges[0] = sums[t];
  // Every read of T above happens before any reset below.
  barrier(CLK_GLOBAL_MEM_FENCE);
  for (int l = l0; l < l1; ++l) label[stop[l]] = INT_MAX;
}
