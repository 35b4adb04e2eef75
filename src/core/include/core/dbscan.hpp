// DBSCAN clutter filter (paper II, after Ester et al.): clusters echoes by density and drops
// clusters smaller than min_cluster_size, and noise. Neighbours are searched in scan order:
// only echoes whose horizontal angle can put them within eps are compared, never all pairs.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/thread_arena.hpp"
#include "freespace/config.hpp"

namespace freespace {

class Crew;

// An echo in the sensor frame (metres) with its angular bin.
struct EchoPoint {
  float x = 0.0f;
  float y = 0.0f;
  float range = 0.0f;
  float angle = 0.0f;
  std::int32_t bin = 0;
};

class ClutterFilter {
 public:
  // bins: number of angular bins; bin_width_rad: their width; threads: 0 = all cores.
  ClutterFilter(const ClutterConfig& config, int bins, double bin_width_rad, int threads = 0);

  // Sets keep[i] = 1 for echoes in clusters of at least min_cluster_size points, 0 for the
  // rest (clutter). Returns the number of clutter echoes. Deterministic for a given input.
  int Run(const std::vector<EchoPoint>& points, std::vector<std::uint8_t>* keep);

  // Runs the parallel passes on `crew` (calling thread included; not owned) instead of in a
  // TBB arena; nullptr: TBB again. The result is the same either way.
  void UseCrew(Crew* crew) { crew_ = crew; }

 private:
  int Find(int a) const;
  void Unite(int a, int b);
  void Reserve(int n);
  // Sorts the echoes by bin (stable) into x_, y_, r_ and order_, and sizes the per-echo arrays.
  void SortByBin(const std::vector<EchoPoint>& points);
  // body(a) for every sorted echo a of n, on the crew or in the arena.
  template <class Body>
  void ForEachEcho(int n, const Body& body);
  // keep[i] for every echo from its cluster (a large one, or one of min_cluster_size or more);
  // returns the clutter count.
  int KeepClustered(int n, std::vector<std::uint8_t>* keep);

  ClutterConfig config_;
  int bins_;
  double bin_width_;
  ThreadArena arena_;
  Crew* crew_ = nullptr;
  // Points in bin order, structure of arrays.
  std::vector<std::int32_t> bin_start_;
  std::vector<std::int32_t> cursor_;
  std::vector<std::int32_t> order_;  // sorted position -> input index
  std::vector<float> x_, y_, r_;
  // Per point, in sorted order: its search window, core flag, union-find parent, cluster.
  std::vector<std::int32_t> first_, last_;
  std::vector<std::uint8_t> core_;
  std::vector<std::uint8_t> sure_;   // core, with enough core neighbours for a large cluster
  std::vector<std::int32_t> found_;  // the first neighbours found, kMaxRecorded per echo
  std::vector<std::uint8_t> found_count_;
  std::unique_ptr<std::atomic<std::int32_t>[]> parent_;
  int capacity_ = 0;
  std::vector<std::int32_t> cluster_;  // root of the cluster a point belongs to, -1 for noise
  std::vector<std::int32_t> size_;
};

}  // namespace freespace
