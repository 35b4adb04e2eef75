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

// Per-stage times of any number of scans in fixed memory (about 40 kB a stage): each time falls
// in a logarithmic bin 1 % wide, from 0.01 us to 1e9 us (times outside go to the end bins), so
// a quantile is within 0.5 % of the exact one (nearest rank). For `freespace run`, whose logs
// have no length limit.
class StageHistogram {
 public:
  StageHistogram();
  void Add(const StageTimes& t);
  std::size_t size() const { return count_; }
  // As StageSeries::Summary().
  nlohmann::json Summary() const;
  double MedianTotal() const;

  static constexpr int kStages = 9;

 private:
  double Quantile(int stage, double q) const;

  std::vector<std::uint32_t> bins_;  // kStages x kBins
  std::size_t count_ = 0;
};

}  // namespace freespace
