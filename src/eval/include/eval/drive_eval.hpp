// Quality over many simulated drives: a drive simulated, estimated and scored in memory, and the
// summary of many drives per scenario (mean over seeds, the worst seed, pooled over every scan),
// beside the project's aims. `freespace eval --seeds` and `freespace demo --seeds` print and
// write it (docs/metrics.md, "Over many drives").
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eval/metrics.hpp"
#include "eval/stage_stats.hpp"
#include "freespace/config.hpp"
#include "sim/simulator.hpp"

namespace freespace {

// One drive's scores and stage times.
struct DriveEvaluation {
  std::string scenario;
  std::uint64_t seed = 0;
  MetricsSeries metrics;
  StageSeries times;
  long rejected = 0;
  Config config;  // the config the estimator ran: the drive's scanner or rig in it
};

// Simulates the drive of `options` and runs an estimator of `config` on every scan, scoring
// each against the truth. The sensor comes from the drive's scanner unless `keep_sensor`.
// Throws what the simulator and the estimator throw for bad options or config.
DriveEvaluation EvaluateDrive(const sim::SimulationOptions& options, const Config& config,
                              bool keep_sensor = false);

// The project's quality aims over seeds (issue "A safe free-space polygon"): means over the
// seeds and the bound on the worst seed.
struct QualityAim {
  const char* metric;  // a MetricsSeries summary field
  bool at_most;        // the value must stay below (intrusion) or above (accuracy, coverage)
  double mean;
  double worst;
};
inline constexpr QualityAim kQualityAims[] = {
    {"accuracy", false, 0.985, 0.98},
    {"intrusion_m2", true, 0.03, 0.06},
    {"coverage", false, 0.87, 0.83},
};

// Per scenario, in order of first appearance: {"scenario", "seeds": [...], "per_seed": [{"seed",
// metric: mean, ...}], "mean": {metric: mean over seeds}, "worst": {metric: {"value", "seed"}},
// "pooled": {metric: pooled over all scans}, "aims": {metric: {"mean", "worst", "met"}},
// "stage_us": {stage: median of the drives' medians}}.
nlohmann::json SeedSummary(const std::vector<DriveEvaluation>& drives);

}  // namespace freespace
