// `freespace bench`: the pipeline's per-stage medians and p99s per backend, and the paper's
// comparisons side by side in one run: enhanced vs conventional inverse sensor model, vehicle
// on a circle vs a rotated map (time and error against a world-fixed reference), TBB vs
// OpenCL; with --scaling, time against map size per backend, drawn as PNG plots.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

#include "bench_suite.hpp"
#include "commands.hpp"
#include "freespace/freespace.hpp"
#include "plot.hpp"

namespace freespace::cli {
namespace {

struct BenchOptions {
  std::string log;
  std::string out = "out/bench";
  std::string backends = "all";
  int scans = 0;
  int warmup = 10;
  bool json = false;
  bool scaling = false;
  EngineOptions engine;
};

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

void Line(const char* label, double a, double b, const char* unit, const char* note = "") {
  std::printf("  %-34s %12.1f %12.1f %s %s\n", label, a, b, unit, note);
}

int Run(const BenchOptions& options) {
  Config config;
  std::vector<Scan> scans;
  try {
    SensorConfig sensor;
    scans = LoadScans(options.log, options.scans, &sensor);
    config = LoadEngineConfig(options.engine, &sensor);
    MakeDirectories(options.out);
  } catch (const std::exception& e) {
    std::cerr << "freespace bench: " << e.what() << "\n";
    return kExitSetup;
  }
  if (int(scans.size()) <= options.warmup) {
    std::cerr << "freespace bench: " << options.log << " has " << scans.size()
              << " scans; need more than the warm-up of " << options.warmup << "\n";
    return kExitSetup;
  }
  nlohmann::json report = {{"log", options.log},
                           {"scans", scans.size()},
                           {"warmup", options.warmup},
                           {"map", {config.map.width_cells, config.map.height_cells}},
                           {"resolution_m", config.map.resolution_m}};
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
  for (const BackendKind kind : kinds) {
    Config c = config;
    c.backend.kind = kind;
    progress(std::string("pipeline on ") + ToString(kind));
    try {
      runs.push_back(TimePipeline(c, scans, options.warmup));
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
  auto model_us = [](const PipelineRun& r) {
    return r.times.Quantile("rasterize", 0.5) + r.times.Quantile("fuse", 0.5);
  };
  report["sensor_model"] = {
      {"enhanced",
       {{"model_us", model_us(run_e)}, {"total_us", run_e.times.Quantile("total", 0.5)}}},
      {"conventional",
       {{"model_us", model_us(run_c)}, {"total_us", run_c.times.Quantile("total", 0.5)}}},
      {"model_speedup", model_us(run_e) > 0 ? model_us(run_c) / model_us(run_e) : 0.0},
      {"coverage", coverage.ToJson()}};

  // Vehicle on a circle vs a rotated, sub-pixel shifted map, against the reference map.
  progress("circle vs rotate alignment");
  const AlignmentComparison align = CompareAlignment(config, scans, options.warmup);
  report["alignment"] = {{"circle",
                          {{"align_us", align.circle.times.Quantile("align", 0.5)},
                           {"total_us", align.circle.times.Quantile("total", 0.5)},
                           {"error", align.circle_error.ToJson()}}},
                         {"rotate",
                          {{"align_us", align.rotate.times.Quantile("align", 0.5)},
                           {"total_us", align.rotate.times.Quantile("total", 0.5)},
                           {"error", align.rotate_error.ToJson()}}}};

  // Scaling: total time against map size, per backend.
  if (options.scaling) {
    std::vector<PlotSeries> series;
    const std::vector<Scan> subset(scans.begin(),
                                   scans.begin() + std::min<std::size_t>(scans.size(), 80));
    for (const BackendKind kind : kinds) {
      PlotSeries s;
      s.name = ToString(kind);
      for (const int cells : {150, 300, 600, 1200, 1500, 2400, 3000}) {
        Config c = config;
        c.backend.kind = kind;
        c.map.width_cells = c.map.height_cells = cells;
        progress(std::string("scaling ") + ToString(kind) + " " + std::to_string(cells));
        try {
          const PipelineRun r = TimePipeline(c, subset, std::min(options.warmup, 10));
          const double us = r.times.Quantile("total", 0.5);
          s.x.push_back(double(cells) * cells);
          s.y.push_back(us);
          report["scaling"]["map"].push_back(
              {{"backend", ToString(kind)}, {"cells", cells}, {"total_us", us}});
        } catch (const BackendError&) {
          break;
        }
      }
      if (!s.x.empty()) series.push_back(s);
    }
    PlotSpec spec{"Full pipeline time against map size", "cells in the map",
                  "median microseconds per scan"};
    WriteLinePlot(options.out + "/scaling_map.png", spec, series);
    report["scaling"]["map_plot"] = options.out + "/scaling_map.png";
  }

  std::ofstream(options.out + "/bench.json") << report.dump(2) << "\n";
  if (options.json) {
    std::cout << report.dump(2) << "\n";
    return kExitOk;
  }

  std::printf("freespace bench: %s, %zu scans (%d warm-up), map %d x %d at %.2f m\n\n",
              options.log.c_str(), scans.size(), options.warmup, config.map.width_cells,
              config.map.height_cells, config.map.resolution_m);
  std::printf("Pipeline, median / p99 microseconds per scan\n");
  for (const PipelineRun& r : runs) {
    std::printf("  %s (%.0f scans/s)\n", r.backend.c_str(), 1e6 / r.times.Mean("total"));
    for (const char* stage :
         {"preprocess", "align", "rasterize", "fuse", "classify", "insight", "polygon", "total"}) {
      Line(stage, r.times.Quantile(stage, 0.5), r.times.Quantile(stage, 0.99), "us");
    }
  }
  if (runs.size() == 2) {
    std::printf("  opencl / tbb total: %.2f\n",
                runs[1].times.Quantile("total", 0.5) / runs[0].times.Quantile("total", 0.5));
  }
  std::printf("\nInverse sensor model (paper II, V.B)       enhanced conventional\n");
  Line("model (rasterize + fuse), median", model_us(run_e), model_us(run_c), "us");
  Line("full pipeline, median", run_e.times.Quantile("total", 0.5),
       run_c.times.Quantile("total", 0.5), "us");
  std::printf("  conventional / enhanced model time: %.2f\n",
              model_us(run_e) > 0 ? model_us(run_c) / model_us(run_e) : 0.0);
  Line("footprint cells without update", coverage.enhanced_holes, coverage.conventional_holes,
       "cells/scan");
  std::printf(
      "  (footprint %.0f cells a scan; conventional: %.1f updates per updated cell, "
      "up to %.0f)\n",
      coverage.footprint_cells, coverage.conventional_mean_updates,
      coverage.conventional_max_updates);
  std::printf("\nMap alignment (paper III, V.B)               circle       rotate\n");
  Line("align, median", align.circle.times.Quantile("align", 0.5),
       align.rotate.times.Quantile("align", 0.5), "us");
  Line("full pipeline, median", align.circle.times.Quantile("total", 0.5),
       align.rotate.times.Quantile("total", 0.5), "us");
  std::printf("  %-34s %12.4f %12.4f\n", "cells differing from reference",
              align.circle_error.different_fraction, align.rotate_error.different_fraction);
  std::printf("  %-34s %12.4f %12.4f\n", "free/unknown/occupied mismatch",
              align.circle_error.class_mismatch, align.rotate_error.class_mismatch);
  std::printf("  %-34s %12.4f %12.4f\n", "mean |p - p_reference|",
              align.circle_error.mean_abs_probability, align.rotate_error.mean_abs_probability);
  std::printf("\nWrote %s/bench.json%s\n", options.out.c_str(),
              options.scaling ? " and scaling_map.png" : "");
  return kExitOk;
}

}  // namespace

Command AddBenchCommand(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* command = app.add_subcommand(
      "bench",
      "Measure the pipeline and reproduce the paper's comparisons in one run: per-stage median\n"
      "and p99 per backend, enhanced vs conventional inverse sensor model (time, footprint\n"
      "cells left without update), vehicle on a circle vs a rotated map (time, error against a\n"
      "world-fixed reference map), TBB vs OpenCL; --scaling adds time against map size\n"
      "(PNG plot). Writes OUT/bench.json.");
  command->add_option("--log", options->log, "Log to replay")->required()->check(CLI::ExistingFile);
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  command->add_option("--backends", options->backends, "Backends to time")
      ->check(CLI::IsMember({"all", "tbb", "opencl"}))
      ->capture_default_str();
  command->add_option("--scans", options->scans, "Use at most this many scans (0: all)");
  command->add_option("--warmup", options->warmup, "Scans not timed at the start")
      ->capture_default_str();
  command->add_flag("--json", options->json, "Print the report as JSON");
  command->add_flag("--scaling", options->scaling, "Also time map sizes 150^2 .. 3000^2");
  AddEngineOptions(command, &options->engine);
  return {command, [options] { return Run(*options); }};
}

}  // namespace freespace::cli
