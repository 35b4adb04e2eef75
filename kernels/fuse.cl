// Kernel stage 2: Bayes fusion of the update mask into the map in fixed-point log-odds,
// clamped to [L_MIN, L_MAX]. Mirrors host/fuse.cpp. Each cell gets at most one update per scan
// because stage 1 wrote one value per cell.
//
// Build options: L_FREE, L_OCCUPIED, L_MIN, L_MAX, UPDATE_FREE, UPDATE_OCCUPIED.
// One work-item per cell of the contiguous range [first, first + count) (whole rows).

__kernel void fuse(__global short* map, __global const uchar* update, int first, int count) {
  const int i = get_global_id(0);
  if (i >= count) return;
  const int k = first + i;
  const uchar u = update[k];
  const int delta = u == UPDATE_FREE ? L_FREE : (u == UPDATE_OCCUPIED ? L_OCCUPIED : 0);
  map[k] = (short)clamp((int)map[k] + delta, L_MIN, L_MAX);
}
