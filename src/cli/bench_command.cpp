// `freespace bench`: the pipeline's per-stage medians and p99s per backend, and the paper's
// comparisons side by side in one run: enhanced vs conventional inverse sensor model (time,
// footprint holes, Moire cells, conflicts and, on a simulated scenario, accuracy against the
// truth), vehicle on a circle vs a rotated map (time and error against a world-fixed reference),
// TBB vs OpenCL; with --scaling, time against map size and against points per scan, per
// backend, drawn as PNG plots. Field definitions: docs/bench.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "eval/bench_suite.hpp"
#include "freespace/freespace.hpp"
#include "output/plot.hpp"
#include "quality_report.hpp"
#include "sim_options.hpp"

namespace freespace::cli {
namespace {

struct BenchOptions {
  std::string log;
  SimOptions sim;
  bool scenario = false;  // --scenario given: bench a simulated drive
  std::string out = "out/bench";
  std::string backends = "all";
  int scans = 0;
  int warmup = 10;
  bool json = false;
  bool scaling = false;
  EngineOptions engine;
};

// Map sizes (cells a side) and scanner beams per layer of the scaling runs. The points sweep
// keeps the ScaLa's 4 layers and 145 deg and changes the horizontal resolution, so a scan has
// 4 * beams points: 500 .. 8000.
constexpr int kMapSizes[] = {150, 300, 600, 1200, 1500, 2400, 3000};
constexpr int kSweepBeams[] = {125, 250, 500, 1000, 2000};
constexpr int kScalingScans = 80;  // scans per scaling run at most

std::vector<Scan> LoadScans(const std::string& path, int limit, SensorConfig* sensor) {
  auto reader = OpenLog(path);
  *sensor = reader->sensor();
  std::vector<Scan> scans;
  Scan scan;
  while ((limit <= 0 || int(scans.size()) < limit) && reader->Next(&scan)) scans.push_back(scan);
  // A single frame (KITTI) is repeated as a standing vehicle, 25 scans a second.
  if (scans.size() == 1) {
    const Scan frame = scans[0];
    for (int k = 1; k < std::max(limit, 200); ++k) {
      scans.push_back(frame);
      scans.back().timestamp_s = frame.timestamp_s + 0.04 * k;
    }
  }
  return scans;
}

double MeanPoints(const std::vector<Scan>& scans) {
  double sum = 0;
  for (const Scan& s : scans) sum += double(s.points.size());
  return scans.empty() ? 0.0 : sum / double(scans.size());
}

// Median time of the inverse sensor model: kernel stages 1 and 2.
double ModelUs(const PipelineRun& r) {
  return r.times.Quantile("rasterize", 0.5) + r.times.Quantile("fuse", 0.5);
}
double TotalUs(const PipelineRun& r) { return r.times.Quantile("total", 0.5); }
// Median time of building the map (the paper's "OGM execution time"): every stage up to the
// fused map, before classification, in-sight edges and the polygon.
double MapUs(const PipelineRun& r) {
  return r.times.Quantile("preprocess", 0.5) + r.times.Quantile("align", 0.5) + ModelUs(r);
}
// Exponents of time against cells up to this count as "no faster than linearly": a fit through
// five medians taken on a shared machine moves by about this much from run to run.
constexpr double kLinearExponent = 1.1;

// The 1-minute load average of the machine (NaN where /proc/loadavg is missing).
double LoadAverage() {
  double load = NAN;
  if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = NAN;
    std::fclose(f);
  }
  return load;
}
double Ratio(double a, double b) { return b > 0 ? a / b : NAN; }
nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; }

void Line(const char* label, double a, double b, const char* unit, const char* note = "") {
  std::printf("  %-36s %12.1f %12.1f %s %s\n", label, a, b, unit, note);
}
void Line4(const char* label, double a, double b) {
  std::printf("  %-36s %12.4f %12.4f\n", label, a, b);
}

// One point of a scaling run.
struct ScalePoint {
  std::string backend, model;
  double x = 0;         // cells in the map, or points per scan
  double total_us = 0;  // median full pipeline
  double model_us = 0;  // median rasterize + fuse
};

// Groups scaling points into plot series by backend (and model) and fits their exponents.
std::vector<PlotSeries> Series(const std::vector<ScalePoint>& points, bool by_model) {
  std::vector<PlotSeries> out;
  for (const ScalePoint& p : points) {
    const std::string name = by_model ? p.backend + " " + p.model : p.backend;
    auto it = std::find_if(out.begin(), out.end(), [&](auto& s) { return s.name == name; });
    if (it == out.end()) it = out.insert(out.end(), PlotSeries{name, {}, {}});
    it->x.push_back(p.x);
    it->y.push_back(p.total_us);
  }
  return out;
}

// The exponent of time against x per series, over all points and over x >= from.
nlohmann::json Exponents(const std::vector<PlotSeries>& series, double from) {
  nlohmann::json out = nlohmann::json::object();
  for (const PlotSeries& s : series) {
    std::vector<double> x, y;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (s.x[i] >= from) x.push_back(s.x[i]), y.push_back(s.y[i]);
    }
    out[s.name] = {{"all", Number(LogLogSlope(s.x, s.y))}, {"upper", Number(LogLogSlope(x, y))}};
  }
  return out;
}

int Run(const BenchOptions& options) {
  Config config;
  std::vector<Scan> scans;
  std::unique_ptr<sim::Simulation> simulation;
  std::string source = options.log;
  try {
    SensorConfig sensor;
    if (options.scenario) {
      simulation = std::make_unique<sim::Simulation>(MakeSimulationOptions(options.sim));
      sensor = simulation->truth().scanner.EngineSensor();
      Scan scan;
      while ((options.scans <= 0 || int(scans.size()) < options.scans) && simulation->Next(&scan)) {
        scans.push_back(scan);
      }
      source =
          "scenario " + options.sim.scenario + " (seed " + std::to_string(options.sim.seed) + ")";
    } else {
      scans = LoadScans(options.log, options.scans, &sensor);
    }
    config = LoadEngineConfig(options.engine, &sensor);
    MakeDirectories(options.out);
  } catch (const std::exception& e) {
    std::cerr << "freespace bench: " << e.what() << "\n";
    return kExitSetup;
  }
  if (int(scans.size()) <= options.warmup) {
    std::cerr << "freespace bench: " << source << " has " << scans.size()
              << " scans; need more than the warm-up of " << options.warmup << "\n";
    return kExitSetup;
  }
  const double points_per_scan = MeanPoints(scans);
  const double load_before = LoadAverage();
  nlohmann::json report = {{"source", source},
                           {"scans", scans.size()},
                           {"warmup", options.warmup},
                           {"points_per_scan", points_per_scan},
                           {"map", {config.map.width_cells, config.map.height_cells}},
                           {"resolution_m", config.map.resolution_m}};
  if (options.scenario) {
    report["scenario"] = {{"name", options.sim.scenario}, {"seed", options.sim.seed}};
  } else {
    report["log"] = options.log;
  }
  auto progress = [&](const std::string& what) {
    if (!options.json) std::cerr << "freespace bench: " << what << "...\n";
  };

  // The pipeline per backend.
  std::vector<BackendKind> kinds;
  if (options.backends == "all" || options.backends == "tbb") kinds.push_back(BackendKind::kTbb);
  if (options.backends == "all" || options.backends == "opencl") {
    kinds.push_back(BackendKind::kOpenCl);
  }
  std::vector<PipelineRun> runs;
  std::vector<BackendKind> available;
  for (const BackendKind kind : kinds) {
    Config c = config;
    c.backend.kind = kind;
    progress(std::string("pipeline on ") + ToString(kind));
    try {
      runs.push_back(TimePipeline(c, scans, options.warmup));
      available.push_back(kind);
      report["pipeline"][ToString(kind)] = runs.back().ToJson();
    } catch (const BackendError& e) {
      report["pipeline"][ToString(kind)] = {{"unavailable", e.what()}};
      if (!options.json)
        std::cerr << "freespace bench: " << ToString(kind) << ": " << e.what() << "\n";
    }
  }

  // Enhanced vs conventional inverse sensor model, same scans, same backend (TBB).
  progress("enhanced vs conventional inverse sensor model");
  Config enhanced = config, conventional = config;
  enhanced.backend.kind = conventional.backend.kind = BackendKind::kTbb;
  enhanced.sensor_model.kind = SensorModelKind::kEnhanced;
  conventional.sensor_model.kind = SensorModelKind::kConventional;
  const PipelineRun run_e = TimePipeline(enhanced, scans, options.warmup);
  const PipelineRun run_c = TimePipeline(conventional, scans, options.warmup);
  const CoverageStats coverage = SensorModelCoverage(config, scans, 5);
  nlohmann::json& models = report["sensor_model"];
  auto times = [](const PipelineRun& r) {
    return nlohmann::json{{"model_us", ModelUs(r)}, {"map_us", MapUs(r)}, {"total_us", TotalUs(r)}};
  };
  models = {{"enhanced", times(run_e)},
            {"conventional", times(run_c)},
            {"model_speedup", Number(Ratio(ModelUs(run_c), ModelUs(run_e)))},
            {"map_speedup", Number(Ratio(MapUs(run_c), MapUs(run_e)))},
            {"total_speedup", Number(Ratio(TotalUs(run_c), TotalUs(run_e)))},
            {"coverage", coverage.ToJson()}};
  TruthQuality quality_e, quality_c;
  if (simulation) {
    progress("enhanced vs conventional against the truth");
    quality_e = ScoreAgainstTruth(enhanced, scans, simulation->truth());
    quality_c = ScoreAgainstTruth(conventional, scans, simulation->truth());
    models["enhanced"]["quality"] = quality_e.ToJson();
    models["conventional"]["quality"] = quality_c.ToJson();
  }

  // Vehicle on a circle vs a rotated, sub-pixel shifted map, against the reference map.
  progress("circle vs rotate alignment");
  const AlignmentComparison align = CompareAlignment(config, scans, options.warmup);
  report["alignment"] = {{"circle",
                          {{"align_us", align.circle.times.Quantile("align", 0.5)},
                           {"map_us", MapUs(align.circle)},
                           {"total_us", TotalUs(align.circle)},
                           {"error", align.circle_error.ToJson()}}},
                         {"rotate",
                          {{"align_us", align.rotate.times.Quantile("align", 0.5)},
                           {"map_us", MapUs(align.rotate)},
                           {"total_us", TotalUs(align.rotate)},
                           {"error", align.rotate_error.ToJson()}}}};

  // Scaling: total time against map size, per backend; against points per scan, per backend
  // and sensor model, on a simulated drive (the bench's scenario, or urban for a log).
  std::vector<ScalePoint> map_points, sweep_points;
  std::string sweep_scenario;
  if (options.scaling) {
    const std::vector<Scan> subset(
        scans.begin(), scans.begin() + std::min<std::size_t>(scans.size(), kScalingScans));
    const int warmup = std::min(options.warmup, 10);
    for (const BackendKind kind : available) {
      for (const int cells : kMapSizes) {
        Config c = config;
        c.backend.kind = kind;
        c.map.width_cells = c.map.height_cells = cells;
        progress(std::string("map scaling ") + ToString(kind) + " " + std::to_string(cells));
        const PipelineRun r = TimePipeline(c, subset, warmup);
        map_points.push_back(
            {ToString(kind), "enhanced", double(cells) * cells, TotalUs(r), ModelUs(r)});
        report["scaling"]["map"].push_back(
            {{"backend", ToString(kind)},
             {"cells", cells},
             {"total_us", TotalUs(r)},
             {"ns_per_cell", 1000.0 * TotalUs(r) / (double(cells) * cells)}});
      }
    }
    const std::vector<PlotSeries> map_series = Series(map_points, false);
    WriteLinePlot(
        options.out + "/scaling_map.png",
        {"Full pipeline time against map size", "cells in the map", "median microseconds per scan"},
        map_series);
    report["scaling"]["map_plot"] = options.out + "/scaling_map.png";
    report["scaling"]["map_exponent"] = Exponents(map_series, 600.0 * 600.0);

    sim::SimulationOptions sweep = MakeSimulationOptions(options.sim);
    if (!options.scenario) sweep.scenario = "urban";
    sweep_scenario = sweep.scenario;
    const int sweep_scans = int(subset.size());
    for (const int beams : kSweepBeams) {
      sweep.scanner.resolution_deg =
          (sweep.scanner.max_angle_deg - sweep.scanner.min_angle_deg) / (beams - 1);
      progress("points scaling: simulating " + std::to_string(beams * sweep.scanner.layers) +
               " points a scan");
      SensorConfig sensor;
      const std::vector<Scan> sweep_run = SimulateScans(sweep, sweep_scans, &sensor);
      const double points = MeanPoints(sweep_run);
      for (const BackendKind kind : available) {
        for (const SensorModelKind model :
             {SensorModelKind::kEnhanced, SensorModelKind::kConventional}) {
          Config c = config;
          c.sensor = sensor;
          c.backend.kind = kind;
          c.sensor_model.kind = model;
          const PipelineRun r = TimePipeline(c, sweep_run, warmup);
          sweep_points.push_back({ToString(kind), ToString(model), points, TotalUs(r), ModelUs(r)});
          report["scaling"]["points"].push_back({{"backend", ToString(kind)},
                                                 {"sensor_model", ToString(model)},
                                                 {"points_per_scan", points},
                                                 {"resolution_deg", sensor.angular_resolution_deg},
                                                 {"total_us", TotalUs(r)},
                                                 {"model_us", ModelUs(r)}});
        }
      }
    }
    const std::vector<PlotSeries> sweep_series = Series(sweep_points, true);
    WriteLinePlot(options.out + "/scaling_points.png",
                  {"Full pipeline time against points per scan (" + sweep_scenario + ", map " +
                       std::to_string(config.map.width_cells) + " x " +
                       std::to_string(config.map.height_cells) + ")",
                   "points per scan", "median microseconds per scan"},
                  sweep_series);
    report["scaling"]["points_scenario"] = sweep_scenario;
    report["scaling"]["points_plot"] = options.out + "/scaling_points.png";
    report["scaling"]["points_exponent"] = Exponents(sweep_series, 2000.0);
  }

  // The paper's comparisons in one place (docs/bench.md, "comparisons").
  nlohmann::json& paper = report["comparisons"];
  paper["enhanced_model_speedup"] = models["model_speedup"];
  paper["enhanced_total_speedup"] = models["total_speedup"];
  paper["enhanced_time_saved_percent"] =
      Number(100.0 * (1.0 - Ratio(TotalUs(run_e), TotalUs(run_c))));
  paper["enhanced_map_time_saved_percent"] =
      Number(100.0 * (1.0 - Ratio(MapUs(run_e), MapUs(run_c))));
  if (simulation) {
    paper["accuracy_enhanced"] = Number(quality_e.accuracy);
    paper["accuracy_conventional"] = Number(quality_c.accuracy);
  }
  paper["circle_different_fraction"] = align.circle_error.different_fraction;
  paper["rotate_different_fraction"] = align.rotate_error.different_fraction;
  paper["circle_time_saved_percent"] =
      Number(100.0 * (1.0 - Ratio(TotalUs(align.circle), TotalUs(align.rotate))));
  paper["circle_map_time_saved_percent"] =
      Number(100.0 * (1.0 - Ratio(MapUs(align.circle), MapUs(align.rotate))));
  if (runs.size() == 2) {
    paper["opencl_over_tbb_total"] = Number(Ratio(TotalUs(runs[1]), TotalUs(runs[0])));
  }
  if (!runs.empty()) {
    paper["pipeline_median_us"] = {{"backend", runs[0].backend},
                                   {"map", {config.map.width_cells, config.map.height_cells}},
                                   {"points_per_scan", points_per_scan},
                                   {"total_us", TotalUs(runs[0])}};
  }
  if (options.scaling) {
    for (const auto& [name, e] : report["scaling"]["map_exponent"].items()) {
      paper["map_exponent"][name] = e;
      paper["map_at_most_linear"][name] =
          e["upper"].is_number() && double(e["upper"]) <= kLinearExponent;
    }
  }

  const double load_after = LoadAverage();
  report["load_average"] = {Number(load_before), Number(load_after)};
  try {
    WriteJson(options.out + "/bench.json", report);
  } catch (const std::exception& e) {
    std::cerr << "freespace bench: " << e.what() << "\n";
    return kExitSetup;
  }
  if (options.json) {
    std::cout << report.dump(1) << "\n";
    return kExitOk;
  }

  std::printf(
      "freespace bench: %s, %zu scans (%d warm-up), %.0f points a scan, map %d x %d at "
      "%.2f m\n\n",
      source.c_str(), scans.size(), options.warmup, points_per_scan, config.map.width_cells,
      config.map.height_cells, config.map.resolution_m);
  std::printf("Pipeline, median / p99 microseconds per scan\n");
  for (const PipelineRun& r : runs) {
    std::string wait;
    if (r.opencl_wait == "auto") {
      wait = ", wait auto (spins at most " + std::to_string(r.opencl_spin_us) + " us)";
    } else if (!r.opencl_wait.empty()) {
      wait = ", wait " + r.opencl_wait;
    }
    std::printf("  %s%s (%.0f scans/s)\n", r.backend.c_str(), wait.c_str(),
                1e6 / r.times.Mean("total"));
    for (const char* stage :
         {"preprocess", "align", "rasterize", "fuse", "classify", "insight", "polygon", "total"}) {
      Line(stage, r.times.Quantile(stage, 0.5), r.times.Quantile(stage, 0.99), "us");
    }
  }
  if (runs.size() == 2) {
    std::printf("  opencl / tbb median, per stage:");
    for (const char* stage :
         {"preprocess", "align", "rasterize", "fuse", "classify", "insight", "polygon", "total"}) {
      std::printf(" %s %.2f", stage,
                  Ratio(runs[1].times.Quantile(stage, 0.5), runs[0].times.Quantile(stage, 0.5)));
    }
    std::printf("\n");
  }
  std::printf("\nInverse sensor model (paper II, V.B)         enhanced conventional\n");
  Line("model (rasterize + fuse), median", ModelUs(run_e), ModelUs(run_c), "us");
  Line("map building (preprocess .. fuse)", MapUs(run_e), MapUs(run_c), "us");
  Line("full pipeline, median", TotalUs(run_e), TotalUs(run_c), "us");
  std::printf("  conventional / enhanced: model %.2f, map building %.2f, full pipeline %.2f\n",
              Ratio(ModelUs(run_c), ModelUs(run_e)), Ratio(MapUs(run_c), MapUs(run_e)),
              Ratio(TotalUs(run_c), TotalUs(run_e)));
  const FootprintStats &fe = coverage.enhanced, &fc = coverage.conventional;
  std::printf("  footprint: %.0f cells a scan, %d scans measured\n", coverage.footprint_cells,
              coverage.scans);
  Line("footprint cells without update", fe.holes, fc.holes, "cells/scan");
  Line("  of which Moire (between updates)", fe.moire, fc.moire, "cells/scan");
  Line("conflicts (free and occupied)", fe.conflicts, fc.conflicts, "cells/scan");
  Line("  of which echo erased (net free)", fe.conflicts_free, fc.conflicts_free, "cells/scan");
  Line("updates per updated footprint cell", fe.mean_updates, fc.mean_updates, "");
  Line("most updates in one cell", fe.max_updates, fc.max_updates, "");
  if (simulation) {
    std::printf("  against the truth (docs/metrics.md), %ld scans scored:\n", quality_e.scans);
    Line4("accuracy on observed cells (pooled)", quality_e.accuracy, quality_c.accuracy);
    Line4("accuracy, mean of scans", quality_e.accuracy_mean, quality_c.accuracy_mean);
    Line("observed cells", quality_e.observed_cells, quality_c.observed_cells, "cells/scan");
    Line4("false-free rate (pooled)", quality_e.false_free_rate, quality_c.false_free_rate);
    Line("false-occupied cells", quality_e.false_occupied, quality_c.false_occupied, "cells/scan");
    Line4("polygon coverage (pooled)", quality_e.coverage, quality_c.coverage);
  }
  std::printf("\nMap alignment (paper III, V.B)                 circle       rotate\n");
  Line("align, median", align.circle.times.Quantile("align", 0.5),
       align.rotate.times.Quantile("align", 0.5), "us");
  Line("map building (preprocess .. fuse)", MapUs(align.circle), MapUs(align.rotate), "us");
  Line("full pipeline, median", TotalUs(align.circle), TotalUs(align.rotate), "us");
  Line4("cells differing from reference", align.circle_error.different_fraction,
        align.rotate_error.different_fraction);
  Line4("free/unknown/occupied mismatch", align.circle_error.class_mismatch,
        align.rotate_error.class_mismatch);
  Line4("mean |p - p_reference|", align.circle_error.mean_abs_probability,
        align.rotate_error.mean_abs_probability);

  if (options.scaling) {
    std::printf("\nMap size, median full pipeline microseconds per scan\n  %-10s", "cells");
    for (const BackendKind kind : available) std::printf(" %12s", ToString(kind));
    std::printf("\n");
    for (const int cells : kMapSizes) {
      std::printf("  %4d^2    ", cells);
      for (const ScalePoint& p : map_points) {
        if (p.x == double(cells) * cells) std::printf(" %12.1f", p.total_us);
      }
      std::printf("\n");
    }
    std::printf("  exponent of time against cells (all sizes / from 600^2):");
    for (const auto& [name, e] : report["scaling"]["map_exponent"].items()) {
      std::printf(" %s %.2f / %.2f", name.c_str(), e["all"].is_number() ? double(e["all"]) : NAN,
                  e["upper"].is_number() ? double(e["upper"]) : NAN);
    }
    std::printf(
        "\n\nPoints per scan (%s, 4 layers, resolution varied), median microseconds:"
        "\n  full pipeline (in brackets: rasterize + fuse)\n  %-8s",
        sweep_scenario.c_str(), "points");
    const std::vector<PlotSeries> sweep_series = Series(sweep_points, true);
    for (const PlotSeries& s : sweep_series) std::printf(" %24s", s.name.c_str());
    std::printf("\n");
    for (std::size_t i = 0; i < sweep_points.size(); i += sweep_series.size()) {
      std::printf("  %-8.0f", sweep_points[i].x);
      for (std::size_t k = i; k < i + sweep_series.size() && k < sweep_points.size(); ++k) {
        char cell[40];
        std::snprintf(cell, sizeof cell, "%.1f (%.1f)", sweep_points[k].total_us,
                      sweep_points[k].model_us);
        std::printf(" %24s", cell);
      }
      std::printf("\n");
    }
  }

  std::printf("\nThe paper's comparisons, this run\n");
  std::printf(
      "  enhanced vs conventional: model %.2fx faster; %.1f %% less time building the map, "
      "%.1f %% less for the full pipeline (paper: 44.07 %% less)\n",
      Ratio(ModelUs(run_c), ModelUs(run_e)), 100.0 * (1.0 - Ratio(MapUs(run_e), MapUs(run_c))),
      100.0 * (1.0 - Ratio(TotalUs(run_e), TotalUs(run_c))));
  if (simulation) {
    std::printf("  accuracy on observed cells: enhanced %.4f, conventional %.4f\n",
                quality_e.accuracy, quality_c.accuracy);
  }
  std::printf(
      "  circle vs rotate: %.1f %% less time building the map, %.1f %% less for the full "
      "pipeline (paper: 4.30 %%); cells differing from the reference: circle %.4f, rotate "
      "%.4f\n",
      100.0 * (1.0 - Ratio(MapUs(align.circle), MapUs(align.rotate))),
      100.0 * (1.0 - Ratio(TotalUs(align.circle), TotalUs(align.rotate))),
      align.circle_error.different_fraction, align.rotate_error.different_fraction);
  if (!runs.empty()) {
    std::printf("  full pipeline median on %s: %.1f us (map %d x %d, %.0f points a scan)\n",
                runs[0].backend.c_str(), TotalUs(runs[0]), config.map.width_cells,
                config.map.height_cells, points_per_scan);
  }
  if (runs.size() == 2) {
    std::printf("  opencl / tbb full pipeline: %.2f\n", Ratio(TotalUs(runs[1]), TotalUs(runs[0])));
  }
  if (options.scaling) {
    for (const auto& [name, e] : report["scaling"]["map_exponent"].items()) {
      const double upper = e["upper"].is_number() ? double(e["upper"]) : NAN;
      std::printf("  %s: time grows as cells^%.2f from 600^2 to 3000^2: %s\n", name.c_str(), upper,
                  upper <= 1.0               ? "no faster than linearly"
                  : upper <= kLinearExponent ? "about linearly (within the run-to-run noise)"
                                             : "FASTER than linearly");
    }
  }
  std::printf("  load average %.2f at the start, %.2f at the end (a shared machine)\n", load_before,
              load_after);
  std::printf("\nWrote %s/bench.json%s\n", options.out.c_str(),
              options.scaling ? ", scaling_map.png and scaling_points.png" : "");
  return kExitOk;
}

}  // namespace

Command AddBenchCommand(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* command = app.add_subcommand(
      "bench",
      "Measure the pipeline and reproduce the paper's comparisons in one run, on a log or a\n"
      "simulated scenario: per-stage median and p99 per backend, enhanced vs conventional\n"
      "inverse sensor model (time, footprint holes, Moire cells, conflicts; on a scenario also\n"
      "accuracy against the truth), vehicle on a circle vs a rotated map (time, error against a\n"
      "world-fixed reference map), TBB vs OpenCL; --scaling adds time against map size and\n"
      "against points per scan (PNG plots). Writes OUT/bench.json (docs/bench.md).");
  CLI::Option* log =
      command->add_option("--log", options->log, "Log to replay")->check(CLI::ExistingFile);
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  command->add_option("--backends", options->backends, "Backends to time")
      ->check(CLI::IsMember({"all", "tbb", "opencl"}))
      ->capture_default_str();
  command->add_option("--scans", options->scans, "Use at most this many scans (0: all)");
  command->add_option("--warmup", options->warmup, "Scans not timed at the start")
      ->capture_default_str();
  command->add_flag("--json", options->json, "Print the report as JSON");
  command->add_flag("--scaling", options->scaling,
                    "Also time map sizes 150^2 .. 3000^2 and 500 .. 8000 points a scan");
  AddSimOptions(command, &options->sim);
  CLI::Option* scenario = command->get_option("--scenario");
  log->excludes(scenario);
  AddEngineOptions(command, &options->engine);
  return {command, [options, scenario] {
            options->scenario = scenario->count() > 0;
            if (options->log.empty() && !options->scenario) {
              std::cerr << "freespace bench: give --log FILE or --scenario NAME\n";
              return kExitSetup;
            }
            return Run(*options);
          }};
}

}  // namespace freespace::cli
