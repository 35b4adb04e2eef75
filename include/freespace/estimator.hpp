// The estimator: one call per full scan turns raw scan points and odometry into the local
// occupancy grid and one free-space polygon of at most N vertices (the whole paper).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "freespace/config.hpp"
#include "freespace/result.hpp"
#include "freespace/scan.hpp"

namespace freespace {

class Estimator {
 public:
  // Validates `config` (throws ConfigError) and creates the configured backend (throws
  // BackendError). All per-scan memory is allocated here.
  explicit Estimator(const Config& config);
  ~Estimator();
  Estimator(const Estimator&) = delete;
  Estimator& operator=(const Estimator&) = delete;

  // Processes one full scan. Never throws for bad scan content: a bad scan is rejected or
  // partly used, and the Result says so. The reference stays valid until the next call.
  const Result& Process(const Scan& scan);

  // Processes one cycle of a rig (Config::sensors): at most one scan per sensor, each taken at
  // its own time and pose. Each scan is filtered and fused from its own sensor's pose, one after
  // the other in the rig's order, each updating a cell at most once; then the map is
  // classified and the polygon extracted once, around the rig's reference point at the newest
  // scan's pose (docs/design.md, "A rig of sensors"). With a single sensor a cycle is one scan.
  // Never throws for bad content: an empty cycle, a sensor index outside the rig or a sensor
  // twice rejects the cycle (kBadCycle), as does any scan that Process() would reject for its
  // timestamp or pose.
  const Result& ProcessCycle(const Scan* scans, int count);
  const Result& ProcessCycle(const std::vector<Scan>& scans) {
    return ProcessCycle(scans.data(), int(scans.size()));
  }

  // Clears the map and the alignment state; the next scan starts a new map.
  void Reset();

  // The map after the last Process(). On the OpenCL backend this copies it from the device.
  MapView map() const;

  const Config& config() const;
  // "tbb" or "opencl: <device>"; with backend auto, which one was taken.
  std::string backend_name() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace freespace
