// The estimator: one call per full scan turns raw scan points and odometry into the local
// occupancy grid and one free-space polygon of at most N vertices (the whole paper).
#pragma once

#include <memory>
#include <string>

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
