// Kernel stage 4: the "in-sight edges" border-ray scan (paper IV.A, algorithm "In-sight Sorted
// Edges Detection"). Mirrors host/insight.cpp.
//
// insight_cast runs one work-item per border label (2 HEIGHT + 2 WIDTH rays, labels in the
// order of BorderCell() in core/backend.hpp): a Bresenham ray from the vehicle cell stops at its
// first not-free cell (the vehicle's own cell never stops it) or at the border cell, and the
// stop cell (row * WIDTH + col) goes to stop[label]. C_Edge, the distinct stop cells ordered by
// their smallest label, is a few thousand steps of bookkeeping that the host does on the stop
// cells it reads back (src/opencl/insight.cpp), as the host backend does.
//
// insight_claim is the same scan split over several CPU devices (BackendConfig::opencl_devices):
// one work-item per device claims chunks of consecutive labels from a counter the devices share,
// until none is left, so that a device that starts late or runs slower takes fewer rays and none
// waits for the other. Each ray still writes its own label's stop cell, so which device casts it
// changes nothing in the result.
//
// The rays visit exactly the cells of host::CastRay, as host/insight.cpp walks them: every step
// moves one cell along the ray's major axis, its offset on the other axis in closed form (no
// decision that depends on the step before), and rays within about 14 degrees of a row a run
// (one row's part of the ray) at a time, 64 cells a bitset word.
//
// Build options: those of common.cl. The free mask is a bitset (common.cl).
//
// Host side: src/opencl/insight.cpp; its insight_cast_arg and insight_claim_arg number the
// arguments of the kernels below: change both together.

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

// The first column u in [from, to] (from <= to: eastwards; from > to: westwards) whose bit in
// the bitset row `line` is 0, or -1.
int InsightFirstNotFree(__global const ulong* line, int from, int to) {
  if (from <= to) {
    for (int w = from >> 6; w <= to >> 6; ++w) {
      ulong hits = ~line[w];
      if (w == from >> 6) hits &= ~0UL << (from & 63);
      if (w == to >> 6) hits &= ~0UL >> (63 - (to & 63));
      // The lowest set bit: its index is 63 minus the leading zeros of it alone.
      if (hits != 0) return w * 64 + 63 - (int)clz(hits & (~hits + 1UL));
    }
  } else {
    for (int w = from >> 6; w >= to >> 6; --w) {
      ulong hits = ~line[w];
      if (w == from >> 6) hits &= ~0UL >> (63 - (from & 63));
      if (w == to >> 6) hits &= ~0UL << (to & 63);
      if (hits != 0) return w * 64 + 63 - (int)clz(hits);
    }
  }
  return -1;
}

// A shallow ray (dx >= 4 dy > 0) from (x0, y0) a row at a time. Step k (0 .. dx) of the ray
// lies floor((2 dy k + dx) / (2 dx)) rows off the start, so the cells of row offset m are the
// steps K(m) = ceil(dx (2m - 1) / (2 dy)) to K(m + 1) - 1, and K(m + 1) - K(m) is q or q + 1
// with 2 dx = q 2 dy + r.
int InsightRunRay(__global const ulong* free, int x0, int y0, int dx, int dy, int sx, int sy) {
  const int q = dx / dy, r = (2 * dx) % (2 * dy);
  int k_next = (dx + 2 * dy - 1) / (2 * dy);  // K(1)
  int rem = (dx + 2 * dy - 1) % (2 * dy);
  int k = 1;  // the vehicle's own cell (k = 0) never stops a ray
  int y = y0;
  while (true) {
    const int k_end = min(k_next - 1, dx);
    if (k <= k_end) {
      const int x = InsightFirstNotFree(free + y * BIT_WORDS, x0 + sx * k, x0 + sx * k_end);
      if (x >= 0) return y * WIDTH + x;
    }
    if (k_end == dx) return y * WIDTH + x0 + sx * dx;
    k = k_end + 1;
    y += sy;
    k_next += q;
    rem += r;
    if (rem >= 2 * dy) {
      rem -= 2 * dy;
      ++k_next;
    }
  }
}

// A ray of n steps along its major axis, each one cell (major_x, major_y), with d <= n steps
// (minor_x, minor_y) on the other axis in all: host::CastRay's cells, whose step k is
// floor((2 d k + n) / (2 n)) minor steps off the start. That is the integer part of
// 2^31 + k slope over 2^32 with slope = ceil(2^32 d / n), exact for n <= 46340 (host::RaySlope
// in host/host_backend.hpp says why; maps have at most 8192 cells a side). No step depends on
// the one before but through the sum, so the steps overlap on the core instead of waiting for
// a decision each.
int InsightStepRay(__global const ulong* free, int x0, int y0, int n, int d, int major_x,
                   int major_y, int minor_x, int minor_y) {
  if (n == 0) return y0 * WIDTH + x0;
  const ulong slope = (((ulong)d << 32) + (ulong)(n - 1)) / (ulong)n;
  ulong sum = 0x80000000UL;  // 2^31: step 0
  for (int k = 1; k <= n; ++k) {
    sum += slope;
    const int m = (int)(sum >> 32);
    const int x = x0 + major_x * k + minor_x * m, y = y0 + major_y * k + minor_y * m;
    if (!((free[y * BIT_WORDS + (x >> 6)] >> (x & 63)) & 1)) return y * WIDTH + x;
  }
  return (y0 + major_y * n + minor_y * d) * WIDTH + x0 + major_x * n + minor_x * d;
}

// The stop cell of the ray from (x0, y0) over dx = |x1 - x0|, dy = |y1 - y0| cells in
// directions (sx, sy): shallow rays (dx >= dy) step along x, steep ones along y.
int InsightRay(__global const ulong* free, int x0, int y0, int dx, int dy, int sx, int sy) {
  if (dy > 0 && dx >= 4 * dy) return InsightRunRay(free, x0, y0, dx, dy, sx, sy);
  if (dx >= dy) return InsightStepRay(free, x0, y0, dx, dy, sx, 0, 0, sy);
  return InsightStepRay(free, x0, y0, dy, dx, 0, sy, sx, 0);
}

// The stop cell of label l's ray from the vehicle cell.
int InsightLabel(__global const ulong* free, int vehicle_col, int vehicle_row, int l) {
  const int2 target = InsightBorderCell(l);
  const int dx = target.x - vehicle_col, dy = target.y - vehicle_row;
  return InsightRay(free, vehicle_col, vehicle_row, abs(dx), abs(dy), dx < 0 ? -1 : 1,
                    dy < 0 ? -1 : 1);
}

__kernel void insight_cast(__global const ulong* free, __global int* stop, int vehicle_col,
                           int vehicle_row) {
  const int l = (int)get_global_id(0);
  if (l < INSIGHT_LABELS) stop[l] = InsightLabel(free, vehicle_col, vehicle_row, l);
}

// One work-item per device. `next` counts the chunks claimed; it is 0 when the scan's first
// device starts, and every work-item stops at its first claim past the last chunk.
__kernel void insight_claim(__global const ulong* free, __global int* stop, int vehicle_col,
                            int vehicle_row, volatile __global int* next, int chunk) {
  const int chunks = (INSIGHT_LABELS + chunk - 1) / chunk;
  for (int c = atomic_inc(next); c < chunks; c = atomic_inc(next)) {
    const int last = min((c + 1) * chunk, INSIGHT_LABELS);
    for (int l = c * chunk; l < last; ++l) {
      stop[l] = InsightLabel(free, vehicle_col, vehicle_row, l);
    }
  }
}

// The exact rays of the conservative polygon (polygon.shape inside): TraceExactRayRows() of
// src/core/include/core/exact_ray.hpp line for line, on the polygon mask (mask.cl) from the
// sensor's fixed-point position. Stop kinds: 0 reached the border cell's centre, 1 entered a
// blocked cell across x = line, 2 across y = line, 3 through a corner (x = line).
#define EXACT_ONE (1 << FIXED_BITS)
#define EXACT_HALF (1 << (FIXED_BITS - 1))

bool ExactAllowed(__global const ulong* mask, int x, int y) {
  return (mask[y * BIT_WORDS + (x >> 6)] >> (x & 63)) & 1;
}

int3 ExactCorner(__global const ulong* mask, int* cx, int* cy, int step_x, int step_y) {
  const int edge_x = step_x > 0 ? *cx + 1 : *cx;
  if (!ExactAllowed(mask, *cx + step_x, *cy + step_y)) {
    return (int3)((*cy + step_y) * WIDTH + *cx + step_x, 3, edge_x);
  }
  if (!ExactAllowed(mask, *cx + step_x, *cy)) return (int3)(*cy * WIDTH + *cx + step_x, 3, edge_x);
  if (!ExactAllowed(mask, *cx, *cy + step_y)) return (int3)((*cy + step_y) * WIDTH + *cx, 3, edge_x);
  *cx += step_x;
  *cy += step_y;
  return (int3)(-1, 0, 0);
}

int3 ExactRay(__global const ulong* mask, int sx, int sy, int cx, int cy, int tc, int tr) {
  const long dx = (long)tc * EXACT_ONE + EXACT_HALF - sx;
  const long dy = (long)tr * EXACT_ONE + EXACT_HALF - sy;
  const int step_x = dx > 0 ? 1 : (dx < 0 ? -1 : 0), step_y = dy > 0 ? 1 : (dy < 0 ? -1 : 0);
  const long adx = dx < 0 ? -dx : dx, ady = dy < 0 ? -dy : dy;
  if (step_y == 0 || step_x == 0) {
    while (cx != tc || cy != tr) {
      cx += step_x;
      cy += step_y;
      if (!ExactAllowed(mask, cx, cy)) {
        if (step_y == 0) return (int3)(cy * WIDTH + cx, 1, step_x > 0 ? cx : cx + 1);
        return (int3)(cy * WIDTH + cx, 2, step_y > 0 ? cy : cy + 1);
      }
    }
    return (int3)(cy * WIDTH + cx, 0, 0);
  }
  const long nx = step_x > 0 ? (long)(cx + 1) * EXACT_ONE - sx : (long)sx - (long)cx * EXACT_ONE;
  const long ny = step_y > 0 ? (long)(cy + 1) * EXACT_ONE - sy : (long)sy - (long)cy * EXACT_ONE;
  const long a = (long)EXACT_ONE * adx, b = (long)EXACT_ONE * ady;
  const long q = a / b, r = a % b;
  long e = ny * adx - nx * ady;
  if (q < 4) {
    while (cx != tc || cy != tr) {
      if (e > 0) {
        cx += step_x;
        e -= b;
        if (!ExactAllowed(mask, cx, cy)) return (int3)(cy * WIDTH + cx, 1, step_x > 0 ? cx : cx + 1);
      } else if (e < 0) {
        cy += step_y;
        e += a;
        if (!ExactAllowed(mask, cx, cy)) return (int3)(cy * WIDTH + cx, 2, step_y > 0 ? cy : cy + 1);
      } else {
        const int3 stop = ExactCorner(mask, &cx, &cy, step_x, step_y);
        if (stop.x >= 0) return stop;
        e += a - b;
      }
    }
    return (int3)(cy * WIDTH + cx, 0, 0);
  }
  long crossings = e > 0 ? (e + b - 1) / b : 0;
  while (true) {
    if (cy == tr) crossings = step_x > 0 ? tc - cx : cx - tc;
    if (crossings > 0) {
      const int to = cx + step_x * (int)crossings;
      const int x = InsightFirstNotFree(mask + cy * BIT_WORDS, cx + step_x, to);
      if (x >= 0) return (int3)(cy * WIDTH + x, 1, step_x > 0 ? x : x + 1);
      cx = to;
    }
    if (cy == tr) return (int3)(cy * WIDTH + cx, 0, 0);
    e -= crossings * b;
    long carry;
    if (e == 0) {
      const int3 stop = ExactCorner(mask, &cx, &cy, step_x, step_y);
      if (stop.x >= 0) return stop;
      carry = b;
    } else {
      cy += step_y;
      if (!ExactAllowed(mask, cx, cy)) return (int3)(cy * WIDTH + cx, 2, step_y > 0 ? cy : cy + 1);
      carry = -e;
    }
    e = a - carry;
    crossings = q + (r > carry ? 1 : (r - carry == -b ? -1 : 0));
  }
}

// One work-item per label; stops[3 l .. 3 l + 2]: cell, kind, line.
__kernel void insight_exact(__global const ulong* mask, __global int* stops, int sensor_x,
                            int sensor_y, int sensor_col, int sensor_row) {
  const int l = (int)get_global_id(0);
  if (l >= INSIGHT_LABELS) return;
  const int2 target = InsightBorderCell(l);
  const int3 stop = ExactRay(mask, sensor_x, sensor_y, sensor_col, sensor_row, target.x, target.y);
  vstore3(stop, l, stops);
}
