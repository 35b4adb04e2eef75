// `freespace bench`: the pipeline's per-stage medians and p99s per backend, and the paper's
// comparisons side by side in one run: enhanced vs conventional inverse sensor model (time,
// footprint holes, Moire cells, conflicts and, on a simulated scenario, accuracy against the
// truth), vehicle on a circle vs a rotated map (time and error against a world-fixed reference),
// TBB vs OpenCL; with --scaling, time against map size and against points per scan, per
// backend, drawn as PNG plots; with --soak N, instead, one estimator over N scans of a long
// simulated drive, its memory and scan times sampled as it goes. Field definitions:
// docs/bench.md.
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "engine_options.hpp"
#include "eval/bench_report.hpp"
#include "eval/soak.hpp"
#include "freespace/freespace.hpp"
#include "output/plot.hpp"
#include "output/text_file.hpp"
#include "quality_report.hpp"
#include "sim_options.hpp"

namespace freespace::cli {
namespace {

struct BenchCommandOptions {
  std::string log;
  SimOptions sim;
  bool scenario = false;  // --scenario given: bench a simulated drive
  std::string out = "out/bench";
  std::string backends = "all";
  int scans = 0;
  int warmup = 10;
  bool json = false;
  bool scaling = false;
  int soak = 0;  // --soak N: the soak run instead of the suite
  int soak_every = 1000;
  EngineOptions engine;
};

// The scans to measure: the log's, or a simulated drive's from `*simulation`, which gets it.
BenchSource LoadSource(const BenchCommandOptions& options,
                       std::unique_ptr<sim::Simulation>* simulation, SensorConfig* sensor) {
  if (!options.scenario) return LogBenchSource(options.log, options.scans, sensor);
  *simulation = std::make_unique<sim::Simulation>(MakeSimulationOptions(options.sim));
  return DriveBenchSource(**simulation, options.sim.scenario, options.sim.seed, options.scans,
                          sensor);
}

BenchOptions SuiteOptions(const BenchCommandOptions& options) {
  BenchOptions suite;
  if (options.backends == "all" || options.backends == "tbb") {
    suite.backends.push_back(BackendKind::kTbb);
  }
  if (options.backends == "all" || options.backends == "opencl") {
    suite.backends.push_back(BackendKind::kOpenCl);
  }
  suite.warmup = options.warmup;
  suite.scaling = options.scaling;
  if (options.scaling) {
    // The points sweep runs on the bench's scenario, or on the urban one for a log.
    suite.sweep = MakeSimulationOptions(options.sim);
    if (!options.scenario) suite.sweep.scenario = "urban";
  }
  if (!options.json) {
    suite.progress = [](const std::string& step) {
      std::cerr << "freespace bench: " << step << "...\n";
    };
    suite.unavailable = [](const std::string& backend, const std::string& error) {
      std::cerr << "freespace bench: " << backend << ": " << error << "\n";
    };
  }
  return suite;
}

std::vector<PlotSeries> Plotted(const std::vector<ScaleSeries>& series) {
  std::vector<PlotSeries> out;
  for (const ScaleSeries& s : series) out.push_back({s.name, s.x, s.y});
  return out;
}

// scaling_map.png and scaling_points.png (log-log, total time).
void WritePlots(const BenchReport& report, const std::string& out) {
  const ScalingResults& s = *report.scaling;
  WriteLinePlot(
      out + "/" + kMapPlotFile,
      {"Full pipeline time against map size", "cells in the map", "median microseconds per scan"},
      Plotted(GroupScalePoints(s.map, false)));
  WriteLinePlot(
      out + "/" + kPointsPlotFile,
      {"Full pipeline time against points per scan (" + s.points_scenario + ", map " +
           std::to_string(report.map_width) + " x " + std::to_string(report.map_height) + ")",
       "points per scan", "median microseconds per scan"},
      Plotted(GroupScalePoints(s.points, true)));
}

// --rig R with --scenario: the pipeline per cycle of rig R against the front rig's single
// scanner, the same drive, per backend, in one run: the medians, their ratio, OUT/bench.json.
std::vector<std::vector<Scan>> SimulateCycles(sim::SimulationOptions options, int limit,
                                              sim::Rig* rig) {
  sim::Simulation simulation(options);
  std::vector<std::vector<Scan>> cycles;
  std::vector<Scan> cycle;
  while ((limit <= 0 || int(cycles.size()) < limit) && simulation.NextCycle(&cycle)) {
    cycles.push_back(cycle);
  }
  *rig = simulation.rig();
  return cycles;
}

int RunRig(const BenchCommandOptions& options) {
  nlohmann::json runs = nlohmann::json::array();
  try {
    RefuseSensorSettings(options.engine, "bench --rig times the simulated rig's own scanners");
    RefuseSimulatedRigSettings(options.engine, options.sim.rig);
    const Config base = LoadEngineConfig(options.engine, nullptr);  // refused before the table
    const BenchOptions suite = SuiteOptions(options);
    MakeDirectories(options.out);
    std::printf("%-8s %-10s %8s %10s %10s %12s %12s\n", "backend", "rig", "cycles", "median_us",
                "p99_us", "preprocess", "update");
    for (const BackendKind kind : suite.backends) {
      double front_median = 0.0;
      for (const std::string& name : {std::string("front"), options.sim.rig}) {
        sim::SimulationOptions sim = MakeSimulationOptions(options.sim);
        sim.rig = name;
        sim::Rig rig;
        const std::vector<std::vector<Scan>> cycles = SimulateCycles(sim, options.scans, &rig);
        Config config = sim::WithRig(base, rig);
        config.backend.kind = kind;
        const PipelineRun run = TimeCycles(config, cycles, options.warmup);
        const double median = run.times.Quantile("total", 0.5);
        if (name == "front") front_median = median;
        std::printf("%-8s %-10s %8d %10.1f %10.1f %12.1f %12.1f\n", ToString(kind), name.c_str(),
                    run.scans, median, run.times.Quantile("total", 0.99),
                    run.times.Quantile("preprocess", 0.5),
                    run.times.Quantile("rasterize", 0.5) + run.times.Quantile("fuse", 0.5));
        nlohmann::json j = run.ToJson();
        j["rig"] = name;
        j["sensors"] = rig.scanners.size();
        if (name != "front" && front_median > 0) j["ratio_to_front"] = median / front_median;
        runs.push_back(j);
      }
    }
    const nlohmann::json json = {{"scenario", options.sim.scenario},
                                 {"seed", options.sim.seed},
                                 {"warmup", options.warmup},
                                 {"rig_runs", runs}};
    WriteJson(options.out + "/" + kBenchJsonFile, json);
  } catch (const std::exception& e) {
    std::cerr << "freespace bench: " << e.what() << "\n";
    return kExitSetup;
  }
  for (const nlohmann::json& j : runs) {
    if (j.contains("ratio_to_front")) {
      std::printf("%s: %s cycle / front scan, medians: %.2f\n",
                  j.at("backend").get<std::string>().c_str(),
                  j.at("rig").get<std::string>().c_str(), j.at("ratio_to_front").get<double>());
    }
  }
  std::printf("\nWrote %s/%s\n", options.out.c_str(), kBenchJsonFile);
  return kExitOk;
}

// Prints a soak sample's memory and times as progress.
void PrintSoakProgress(const SoakSample& s, int total) {
  std::fprintf(stderr,
               "freespace bench: soak %zu / %d scans (lap %zu): RSS %.1f MB, heap %.1f MB, "
               "median %.0f us, p99 %.0f us\n",
               s.scans, total, s.lap, s.memory.rss_kb / 1024.0, s.memory.heap_kb / 1024.0,
               s.median_us, s.p99_us);
}

// --soak N: one estimator of the config over N scans of laps of the scenario (docs/bench.md),
// memory and scan times sampled every --soak-every scans; OUT/soak.csv, OUT/soak.json and the
// summary printed.
int RunSoakCommand(const BenchCommandOptions& options) {
  SoakOptions soak;
  SoakReport report;
  try {
    soak.drive = MakeSimulationOptions(options.sim);
    soak.scans = std::size_t(options.soak);
    soak.every = std::size_t(options.soak_every);
    if (!options.json) {
      soak.on_sample = [total = options.soak](const SoakSample& s) { PrintSoakProgress(s, total); };
    }
    const SensorConfig sensor = soak.drive.scanner.EngineSensor();
    const Config config = LoadEngineConfig(options.engine, &sensor);
    MakeDirectories(options.out);
    report = RunSoak(config, soak);
  } catch (const std::exception& e) {
    std::cerr << "freespace bench: " << e.what() << "\n";
    return kExitSetup;
  }
  const nlohmann::json json = SoakJson(report);
  try {
    WriteTextFile(options.out + "/" + kSoakCsvFile, SoakCsv(report));
    WriteJson(options.out + "/" + kSoakJsonFile, json);
  } catch (const std::exception& e) {
    std::cerr << "freespace bench: " << e.what() << "\n";
    return kExitSetup;
  }
  if (options.json) {
    std::cout << json.dump(1) << "\n";
    return kExitOk;
  }
  PrintSoakReport(stdout, report);
  std::printf("\nWrote %s/%s and %s\n", options.out.c_str(), kSoakCsvFile, kSoakJsonFile);
  return kExitOk;
}

int Run(const BenchCommandOptions& options) {
  Config config;
  BenchSource source;
  BenchOptions suite;
  std::unique_ptr<sim::Simulation> simulation;
  try {
    SensorConfig sensor;
    source = LoadSource(options, &simulation, &sensor);
    config = LoadEngineConfig(options.engine, &sensor);
    suite = SuiteOptions(options);
    MakeDirectories(options.out);
  } catch (const std::exception& e) {
    std::cerr << "freespace bench: " << e.what() << "\n";
    return kExitSetup;
  }
  if (int(source.scans.size()) <= options.warmup) {
    std::cerr << "freespace bench: " << source.Describe() << " has " << source.scans.size()
              << " scans; need more than the warm-up of " << options.warmup << "\n";
    return kExitSetup;
  }
  const BenchReport report = RunBenchSuite(config, source, suite);
  const nlohmann::json json = BenchReportJson(report, options.out);
  try {
    if (report.scaling) WritePlots(report, options.out);
    WriteJson(options.out + "/" + kBenchJsonFile, json);
  } catch (const std::exception& e) {
    std::cerr << "freespace bench: " << e.what() << "\n";
    return kExitSetup;
  }
  if (options.json) {
    std::cout << json.dump(1) << "\n";
    return kExitOk;
  }
  PrintBenchReport(stdout, report);
  std::printf("\nWrote %s/%s%s\n", options.out.c_str(), kBenchJsonFile,
              options.scaling ? ", scaling_map.png and scaling_points.png" : "");
  return kExitOk;
}

}  // namespace

Command AddBenchCommand(CLI::App& app) {
  auto options = std::make_shared<BenchCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "bench",
      "Measure the pipeline and reproduce the paper's comparisons in one run, on a log or a\n"
      "simulated scenario: per-stage median and p99 per backend, enhanced vs conventional\n"
      "inverse sensor model (time, footprint holes, Moire cells, conflicts; on a scenario also\n"
      "accuracy against the truth), vehicle on a circle vs a rotated map (time, error against a\n"
      "world-fixed reference map), TBB vs OpenCL; --scaling adds time against map size and\n"
      "against points per scan (PNG plots). Writes OUT/bench.json (docs/bench.md). --soak N\n"
      "instead runs one estimator over N scans of laps of the scenario and samples memory and\n"
      "scan times every --soak-every scans (OUT/soak.csv, OUT/soak.json).");
  CLI::Option* log =
      command->add_option("--log", options->log, "Log to replay")->check(CLI::ExistingFile);
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  command->add_option("--backends", options->backends, "Backends to time")
      ->check(CLI::IsMember({"all", "tbb", "opencl"}))
      ->capture_default_str();
  command->add_option("--scans", options->scans, "Use at most this many scans (0: all)")
      ->check(CLI::Range(0, 1 << 30));
  command->add_option("--warmup", options->warmup, "Scans not timed at the start")
      ->check(CLI::Range(0, 1 << 30))
      ->capture_default_str();
  command->add_flag("--json", options->json, "Print the report as JSON");
  command->add_flag("--scaling", options->scaling,
                    "Also time map sizes 150^2 .. 3000^2 and 500 .. 8000 points a scan");
  command
      ->add_option("--soak", options->soak,
                   "Soak run: N scans of laps of --scenario through one estimator (seed, seed+1, "
                   "...; --duration: each lap's)")
      ->check(CLI::PositiveNumber);
  command->add_option("--soak-every", options->soak_every, "Scans per soak sample")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  AddSimOptions(command, &options->sim);
  CLI::Option* scenario = command->get_option("--scenario");
  scenario->default_str("");        // bench has no default drive: --log or --scenario
  ExcludeSimOptions(command, log);  // the log is the drive
  AddEngineOptions(command, &options->engine);
  return {command, [options, scenario] {
            options->scenario = scenario->count() > 0;
            if (options->log.empty() && !options->scenario) {
              std::cerr << "freespace bench: give --log FILE or --scenario NAME\n";
              return kExitSetup;
            }
            if (options->sim.rig != "front") {
              if (!options->scenario || options->scaling || options->soak > 0) {
                std::cerr << "freespace bench: --rig times a simulated drive (--scenario), "
                             "without --scaling or --soak\n";
                return kExitSetup;
              }
              return RunRig(*options);
            }
            if (options->soak > 0) {
              if (!options->scenario) {
                std::cerr << "freespace bench: --soak needs --scenario NAME (it simulates the "
                             "drive)\n";
                return kExitSetup;
              }
              return RunSoakCommand(*options);
            }
            return Run(*options);
          }};
}

}  // namespace freespace::cli
