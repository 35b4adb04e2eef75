// The measurements behind `freespace bench` (docs/bench.md): the pipeline's stage times per
// backend, and the paper's comparisons (enhanced vs conventional inverse sensor model, vehicle
// on a circle vs a rotated map), each taken in one run over the same scans; on simulated
// drives, quality against the truth.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eval/stage_stats.hpp"
#include "freespace/config.hpp"
#include "freespace/scan.hpp"
#include "sim/simulator.hpp"
#include "sim/truth.hpp"

namespace freespace {

// Stage times of one estimator over a scan sequence.
struct PipelineRun {
  std::string backend;      // as the estimator names it
  std::string opencl_wait;  // backend.opencl_wait of an OpenCL run; empty for TBB
  int opencl_spin_us = 0;   // backend.opencl_spin_us of an OpenCL run
  StageSeries times;        // scans after the warm-up
  int scans = 0;            // processed (not rejected), warm-up included
  nlohmann::json ToJson() const;
};

// Runs an estimator of `config` over `scans`; the first `warmup` processed scans are not
// timed. Throws what the Estimator throws (ConfigError, BackendError).
PipelineRun TimePipeline(const Config& config, const std::vector<Scan>& scans, int warmup);
// Estimators of `configs` over the same `scans`, each scan processed by each of them in turn,
// so that a change of the machine's speed during the run falls on all of them alike and their
// ratios hold: one PipelineRun per config, as TimePipeline() would give it.
std::vector<PipelineRun> TimePipelinesInTurn(const std::vector<Config>& configs,
                                             const std::vector<Scan>& scans, int warmup);
// The same for a rig: one Estimator::ProcessCycle() per cycle; `scans` counts cycles.
PipelineRun TimeCycles(const Config& config, const std::vector<std::vector<Scan>>& cycles,
                       int warmup);

// How one scan's update of one inverse sensor model covers the sensor's footprint: the cells
// inside the fan triangles between consecutive real (non-virtual) returns (docs/bench.md).
// Means per scan.
struct FootprintStats {
  double holes = 0;  // footprint cells the scan leaves without update
  // Moire cells: holes with an updated cell on both sides along the arc through the hole's
  // centre (the circle about the sensor), each within one beam spacing of arc (at least one
  // cell): the interleaved stripes of paper Fig. 1 where rays thin out.
  double moire = 0;
  // Conflicts (paper Fig. 1 B): cells one scan marks both free and occupied; conflicts_free:
  // of those, cells whose summed update is free, an echo erased by other rays. The enhanced
  // model has none by construction (occupied wins, one update per cell).
  double conflicts = 0;
  double conflicts_free = 0;
  double mean_updates = 0;  // updates per updated footprint cell
  double max_updates = 0;   // largest count in one cell
  nlohmann::json ToJson() const;
};

// The footprint statistics of the enhanced and the conventional model on the same scans; the
// enhanced model updates each footprint cell exactly once, the conventional model's rays leave
// holes between them far out and cross cells near the sensor many times.
struct CoverageStats {
  int scans = 0;               // scans measured
  double footprint_cells = 0;  // mean per scan
  FootprintStats enhanced, conventional;
  nlohmann::json ToJson() const;
};
// Measures every `every`-th scan, the sensor placed off-centre in a map of the config's size.
CoverageStats SensorModelCoverage(const Config& config, const std::vector<Scan>& scans, int every);

// Quality of one estimator's maps and polygons against a simulated drive's truth (the
// metrics of docs/metrics.md, every scan scored in order).
struct TruthQuality {
  long scans = 0;              // scans scored
  double accuracy = 0;         // pooled: sum of correct / sum of observed cells
  double accuracy_mean = 0;    // mean of the per-scan accuracies
  double observed_cells = 0;   // mean observed cells per scan
  double false_free_rate = 0;  // pooled
  double false_occupied = 0;   // mean per scan
  double coverage = 0;         // pooled polygon coverage
  nlohmann::json summary;      // MetricsSeries::Summary()
  nlohmann::json ToJson() const;
};
// Runs an estimator of `config` over `scans`, scan k being the truth's scan k, scoring each.
TruthQuality ScoreAgainstTruth(const Config& config, const std::vector<Scan>& scans,
                               const sim::Truth& truth);

// The first `limit` scans (0: all) of a simulated drive; `*sensor` gets the engine's sensor.
std::vector<Scan> SimulateScans(const sim::SimulationOptions& options, int limit,
                                SensorConfig* sensor);

// Least-squares slope of log(y) against log(x): the exponent b of y ~ a * x^b. NaN with fewer
// than two usable (positive) points.
double LogLogSlope(const std::vector<double>& x, const std::vector<double>& y);

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
