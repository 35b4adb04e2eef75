// The report of `freespace bench` (docs/bench.md): RunBenchSuite() takes every measurement of
// a bench run and the paper's comparisons into one plain struct; BenchReportJson() and
// PrintBenchReport() turn it into bench.json and the printed text, apart from measuring. The
// paper's published figures the run is set against are named data (kPaperFigures), not text.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "eval/bench_suite.hpp"
#include "freespace/config.hpp"
#include "freespace/scan.hpp"
#include "sim/simulator.hpp"
#include "sim/truth.hpp"

namespace freespace {

// One figure the paper publishes, with where it says so.
struct PaperFigure {
  double value;
  const char* unit;
  const char* section;  // of the paper (Eraqi, Honer, Zuther), "V.B" = V. Experimental results, B
  const char* what;     // what the paper says the figure is
};

// The paper's figures the bench sets its run against.
struct PaperFigures {
  PaperFigure enhanced_time_saved;  // enhanced vs conventional inverse sensor model
  PaperFigure circle_time_saved;    // vehicle on a circle vs a rotated, sub-pixel shifted map
};
inline constexpr PaperFigures kPaperFigures = {
    {44.07, "%", "V.B",
     "the enhanced inverse sensor model processed full scans in less time than the "
     "conventional one by this much on average"},
    {4.30, "%", "V.B",
     "the overall time saved by the vehicle on a circle, avoiding image rotation and sub-pixel "
     "shifting, of the overall OGM execution time (enhanced inverse sensor model)"},
};

// The files `freespace bench` writes into its output folder.
inline constexpr const char* kBenchJsonFile = "bench.json";
inline constexpr const char* kMapPlotFile = "scaling_map.png";
inline constexpr const char* kPointsPlotFile = "scaling_points.png";

// Map sizes (cells a side) and scanner beams per layer of the scaling runs. The points sweep
// keeps the ScaLa's 4 layers and 145 deg and changes the horizontal resolution, so a scan has
// 4 * beams points: 500 .. 8000.
inline constexpr int kMapSizes[] = {150, 300, 600, 1200, 1500, 2400, 3000};
inline constexpr int kSweepBeams[] = {125, 250, 500, 1000, 2000};
inline constexpr int kScalingScans = 80;  // scans per scaling run at most
// Exponents of time against cells up to this count as "no faster than linearly": a fit through
// five medians taken on a shared machine moves by about this much from run to run.
inline constexpr double kLinearExponent = 1.1;

// What a bench run measures: a recorded log or a simulated drive.
struct BenchSource {
  std::string log;                    // the log's path; empty for a simulated drive
  std::string scenario;               // the drive's scenario; empty for a log
  std::uint64_t seed = 0;             // the drive's seed
  const sim::Truth* truth = nullptr;  // the drive's truth (must outlive the run); null for a log
  std::vector<Scan> scans;
  // "scenario NAME (seed N)" or the log's path.
  std::string Describe() const;
};

// The first `limit` scans (0: all) of the log at `path`; a log of one frame (KITTI) is repeated
// as a standing vehicle, 25 scans a second, at least 200 times. `*sensor` gets the log's
// sensor. Throws what OpenLog throws.
BenchSource LogBenchSource(const std::string& path, int limit, SensorConfig* sensor);
// The first `limit` scans (0: all) of `simulation`'s drive, named `scenario` and `seed`, with its
// truth; `*sensor` gets the engine's sensor. `simulation` must outlive the source.
BenchSource DriveBenchSource(sim::Simulation& simulation, const std::string& scenario,
                             std::uint64_t seed, int limit, SensorConfig* sensor);

struct BenchOptions {
  std::vector<BackendKind> backends;  // the pipeline's backends to time, in this order
  int warmup = 10;                    // scans not timed at the start of each run
  bool scaling = false;               // also time map sizes and points per scan
  sim::SimulationOptions sweep;       // the drive the points-per-scan runs simulate
  // Called, when set, before each step ("pipeline on tbb") and when a backend is unavailable.
  std::function<void(const std::string& step)> progress;
  std::function<void(const std::string& backend, const std::string& error)> unavailable;
};

// The pipeline on one backend.
struct BackendPipeline {
  BackendKind kind = BackendKind::kTbb;
  std::string error;  // why it could not run; empty when it ran
  PipelineRun run;    // when it ran
};

// One point of a scaling run: the medians of one map size or one scan size.
struct ScalePoint {
  std::string backend;        // "tbb", "opencl"
  std::string sensor_model;   // "enhanced", "conventional"
  double x = 0;               // cells in the map, or mean points per scan
  int cells = 0;              // cells a side, map-size runs
  double resolution_deg = 0;  // the scanner's horizontal resolution, points-per-scan runs
  double total_us = 0;        // median full pipeline
  double model_us = 0;        // median rasterize + fuse
};

// Scaling points grouped into series by backend (and sensor model): x against total_us.
struct ScaleSeries {
  std::string name;
  std::vector<double> x, y;
};
std::vector<ScaleSeries> GroupScalePoints(const std::vector<ScalePoint>& points, bool by_model);

// The exponent b of time ~ a * x^b of one series: over all points and over the upper ones.
struct ScaleExponent {
  double all = NAN;
  double upper = NAN;
};

struct ScalingResults {
  std::vector<ScalePoint> map;                           // per available backend, per kMapSizes
  std::map<std::string, ScaleExponent> map_exponent;     // per backend, upper from 600^2
  std::string points_scenario;                           // the scenario of the points sweep
  std::vector<ScalePoint> points;                        // per kSweepBeams, per backend, per model
  std::map<std::string, ScaleExponent> points_exponent;  // per series, upper from 2000 points
};

// The paper's comparisons of this run (docs/bench.md, "comparisons"); NaN where a time is 0.
struct BenchComparisons {
  double enhanced_model_speedup = 0;  // conventional / enhanced model_us
  double enhanced_map_speedup = 0;    // conventional / enhanced map_us
  double enhanced_total_speedup = 0;  // conventional / enhanced full pipeline
  double enhanced_time_saved_percent = 0;
  double enhanced_map_time_saved_percent = 0;
  double circle_time_saved_percent = 0;
  double circle_map_time_saved_percent = 0;
  double circle_different_fraction = 0;
  double rotate_different_fraction = 0;
  std::optional<double> opencl_over_tbb_total;  // with both backends
};

struct BenchReport {
  // What was measured.
  BenchSource source;  // without its scans and truth
  std::size_t scans = 0;
  int warmup = 0;
  double points_per_scan = 0;  // mean
  int map_width = 0, map_height = 0;
  double resolution_m = 0;
  double load_before = 0, load_after = 0;  // 1-minute load average; NaN where unknown

  std::vector<BackendPipeline> pipelines;  // per backend asked for
  // The pipelines that ran, in the order asked for.
  std::vector<const BackendPipeline*> Ran() const;

  // Enhanced vs conventional inverse sensor model, same scans, TBB.
  PipelineRun enhanced, conventional;
  CoverageStats coverage;
  std::optional<TruthQuality> enhanced_quality, conventional_quality;  // on a simulated drive

  AlignmentComparison alignment;  // circle vs rotate, TBB
  // The paper's polygon against the conservative one (the config's margin, or the road setup's
  // one-cell margin in a 45 deg cone when the config has none), same scans, TBB.
  PipelineRun paper_shape, inside_shape;
  std::optional<ScalingResults> scaling;  // with --scaling
  BenchComparisons comparisons;
};

// Median time of the inverse sensor model: kernel stages 1 and 2.
double ModelUs(const PipelineRun& run);
// Median time of building the map (the paper's "OGM execution time"): every stage up to the
// fused map, before classification, in-sight edges and the polygon.
double MapUs(const PipelineRun& run);
double TotalUs(const PipelineRun& run);  // median full pipeline

// Runs every measurement of `freespace bench` on `source` with `config`. Throws what the
// Estimator throws, but for an unavailable backend of the pipeline runs (`pipelines[].error`).
BenchReport RunBenchSuite(const Config& config, const BenchSource& source,
                          const BenchOptions& options);

// bench.json (docs/bench.md); `out_dir` is the folder the plots are written to.
nlohmann::json BenchReportJson(const BenchReport& report, const std::string& out_dir);

// The printed report: stage times, the comparisons side by side, the paper's figures.
void PrintBenchReport(std::FILE* out, const BenchReport& report);

}  // namespace freespace
