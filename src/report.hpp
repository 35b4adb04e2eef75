// Run reports shared by the command-line tools: per-stage timing statistics (median, p99)
// and the polygons.jsonl line of a scan (docs/formats.md).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "freespace/estimator.hpp"

namespace freespace {

// The q-quantile (0..1) of `values` by nearest rank; 0 when empty. Reorders `values`.
double Quantile(std::vector<double>& values, double q);

// Per-stage times of many scans.
class StageSeries {
 private:
  const std::vector<double>* Stage(const std::string& name) const;

 public:
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
  std::vector<double> preprocess_, align_, rasterize_, fuse_, classify_, insight_, polygon_, total_;
};

// One line of polygons.jsonl (without the newline): scan index, time, pose, origin, vehicle,
// status and the polygon in world metres.
std::string PolygonJsonLine(std::uint64_t scan, const Result& result);

}  // namespace freespace
