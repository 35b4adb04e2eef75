// Kernel stage 3: normalisation to free / not free with neighbourhood hysteresis, then the
// morphological opening of the free mask by a square of side 2 OPENING_RADIUS + 1 (paper IV.A).
// Mirrors host/classify.cpp.
//
// free0 = l <= T_LOW, or l <= T_HIGH with an 8-neighbour l <= T_LOW (neighbours inside the
// map). The opening is separable: erosion along rows, then columns, then dilation along rows,
// then columns. Cells outside the map are not free. The two intermediate masks are stored with a
// border of OPENING_RADIUS zero cells on every side that no kernel ever writes: a zero border
// makes an erosion window leaving the map 0 and adds nothing to a dilation, exactly the rule
// "outside is not free", with no branch in the loops.
//
// Build options: WIDTH, HEIGHT, T_LOW, T_HIGH, OPENING_RADIUS. Global size (WIDTH rounded up,
// HEIGHT) for every kernel.

#define CLASSIFY_STRIDE (WIDTH + 2 * OPENING_RADIUS)
// Index of map cell (r, c) in a padded intermediate mask.
#define CLASSIFY_AT(r, c) (((r) + OPENING_RADIUS) * CLASSIFY_STRIDE + (c) + OPENING_RADIUS)

// map -> padded free0. Neighbour indices are clamped into the map: a clamped neighbour is
// another cell of the same 3 x 3 block, so the OR over the block is unchanged.
__kernel void classify_hysteresis(__global const short* map, __global uchar* out) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= WIDTH) return;
  const int rows[3] = {max(r - 1, 0), r, min(r + 1, HEIGHT - 1)};
  const int cols[3] = {max(c - 1, 0), c, min(c + 1, WIDTH - 1)};
  int near = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) near |= map[rows[i] * WIDTH + cols[j]] <= T_LOW;
  }
  const short m = map[r * WIDTH + c];
  const int strong = m <= T_LOW, weak = m <= T_HIGH;
  out[CLASSIFY_AT(r, c)] = (uchar)(strong | (weak & near));
}

// Padded -> padded: AND of the row window c - OPENING_RADIUS .. c + OPENING_RADIUS.
__kernel void classify_erode_rows(__global const uchar* in, __global uchar* out) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= WIDTH) return;
  const int k = CLASSIFY_AT(r, c);
  uchar v = 1;
  for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) v &= in[k + d];
  out[k] = v;
}

// Padded -> padded: AND of the column window.
__kernel void classify_erode_cols(__global const uchar* in, __global uchar* out) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= WIDTH) return;
  const int k = CLASSIFY_AT(r, c);
  uchar v = 1;
  for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) v &= in[k + d * CLASSIFY_STRIDE];
  out[k] = v;
}

// Padded -> padded: OR of the row window.
__kernel void classify_dilate_rows(__global const uchar* in, __global uchar* out) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= WIDTH) return;
  const int k = CLASSIFY_AT(r, c);
  uchar v = 0;
  for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) v |= in[k + d];
  out[k] = v;
}

// Padded -> the free mask (unpadded, row-major): OR of the column window.
__kernel void classify_dilate_cols(__global const uchar* in, __global uchar* free) {
  const int c = get_global_id(0), r = get_global_id(1);
  if (c >= WIDTH) return;
  const int k = CLASSIFY_AT(r, c);
  uchar v = 0;
  for (int d = -OPENING_RADIUS; d <= OPENING_RADIUS; ++d) v |= in[k + d * CLASSIFY_STRIDE];
  free[r * WIDTH + c] = v;
}
