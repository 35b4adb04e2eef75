// Timing statistics of many scans: the q-quantile by nearest rank and per-stage series of the
// estimator's stage times (median, p99), for reports and the bench suite.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "freespace/result.hpp"

namespace freespace {

// The q-quantile (0..1) of `values` by nearest rank; 0 when empty. Reorders `values`.
double Quantile(std::vector<double>& values, double q);

// Per-stage times of many scans.
class StageSeries {
 public:
  void Add(const StageTimes& t);
  std::size_t size() const { return total_.size(); }
  // {"preprocess": {"median": .., "p99": ..}, ..., "total": {...}} in microseconds.
  nlohmann::json Summary() const;
  double MedianTotal() const;
  // The q-quantile of one stage by name ("preprocess", ..., "total"), microseconds.
  double Quantile(const std::string& stage, double q) const;
  double Mean(const std::string& stage) const;

 private:
  const std::vector<double>* Stage(const std::string& name) const;

  std::vector<double> preprocess_, align_, rasterize_, fuse_, classify_, mask_, insight_, polygon_,
      total_;
};

}  // namespace freespace
