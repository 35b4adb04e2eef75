// The measurements behind `freespace bench`: the pipeline's stage times per backend, and the
// paper's comparisons (enhanced vs conventional inverse sensor model, vehicle on a circle vs a
// rotated map), each taken in one run over the same scans.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "freespace/config.hpp"
#include "freespace/scan.hpp"
#include "report.hpp"

namespace freespace {

// Stage times of one estimator over a scan sequence.
struct PipelineRun {
  std::string backend;  // as the estimator names it
  StageSeries times;    // scans after the warm-up
  int scans = 0;        // processed (not rejected), warm-up included
  nlohmann::json ToJson() const;
};

// Runs an estimator of `config` over `scans`; the first `warmup` processed scans are not
// timed. Throws what the Estimator throws (ConfigError, BackendError).
PipelineRun TimePipeline(const Config& config, const std::vector<Scan>& scans, int warmup);

// How completely one scan's update covers the sensor's footprint: the cells inside the fan
// triangles between consecutive real (non-virtual) returns. The enhanced model updates each such
// cell once; the conventional model's rays leave holes between them far out and cross cells near
// the sensor many times (the Moire effect of paper Fig. 1).
struct CoverageStats {
  double footprint_cells = 0;  // mean per scan
  double enhanced_holes = 0;   // footprint cells without update, mean per scan
  double conventional_holes = 0;
  double conventional_mean_updates = 0;  // updates per updated footprint cell
  double conventional_max_updates = 0;   // largest count in a cell, mean per scan
  nlohmann::json ToJson() const;
};
CoverageStats SensorModelCoverage(const Config& config, const std::vector<Scan>& scans, int every);

// Map error of an alignment against the world-fixed reference map, averaged over scans.
struct AlignmentError {
  double cells_compared = 0;      // mean per scan
  double different_fraction = 0;  // cells whose log-odds differ
  double class_mismatch = 0;      // free / unknown / occupied differ
  double mean_abs_probability = 0;
  nlohmann::json ToJson() const;
};

struct AlignmentComparison {
  PipelineRun circle, rotate;
  AlignmentError circle_error, rotate_error;
};
// Circle and rotate estimators and the reference map in lockstep over `scans` (TBB backend).
AlignmentComparison CompareAlignment(const Config& config, const std::vector<Scan>& scans,
                                     int warmup);

}  // namespace freespace
