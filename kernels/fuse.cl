// Kernel stage 2: Bayes fusion of the update mask into the map in fixed-point log-odds,
// clamped to [L_MIN, L_MAX]. Mirrors host/fuse.cpp. Each cell gets at most one update per scan
// because stage 1 wrote one value per cell.
//
// Build options: L_FREE, L_OCCUPIED, L_MIN, L_MAX, UPDATE_FREE, UPDATE_OCCUPIED (and those of
// common.cl). Global size (row items, row_end - row_begin rounded up).
//
// Host side: src/opencl/fuse.cpp; its fuse_arg numbers the arguments of the kernel below: change
// both together.

__kernel void fuse(__global short* map, __global const uchar* update, int row_begin, int row_end) {
  const int r = row_begin + (int)get_global_id(1);
  int v0, v1;
  if (r >= row_end || !RowVectors(&v0, &v1)) return;
  for (int v = v0; v < v1; ++v) {
    const int k = CELL(r, 16 * v);
    __global short16* m = (__global short16*)(map + k);
    const int16 u = convert_int16(*(__global const uchar16*)(update + k));
    const int16 delta = select(select((int16)(0), (int16)(L_OCCUPIED), u == UPDATE_OCCUPIED),
                               (int16)(L_FREE), u == UPDATE_FREE);
    const int16 fused = clamp(convert_int16(*m) + delta, L_MIN, L_MAX);
    *m = convert_short16(select((int16)(0), fused, InsideLanes(16 * v)));
  }
}
