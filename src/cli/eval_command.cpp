// `freespace eval`: runs the estimator over a simulated log and scores every scan against the
// drive's truth file (docs/metrics.md); writes OUT/eval.json and prints the summary.
#include <chrono>
#include <iostream>

#include "commands.hpp"
#include "engine_options.hpp"
#include "eval/scorer.hpp"
#include "freespace/freespace.hpp"
#include "interrupt.hpp"
#include "quality_report.hpp"
#include "seed_runs.hpp"
#include "sim_options.hpp"

namespace freespace::cli {
namespace {

struct EvalOptions {
  std::string log;
  std::string truth;
  std::string out = "out/eval";
  bool quiet = false;
  EngineOptions engine;
  SimOptions sim;
  SeedOptions seeds;
  std::string single_seed;  // a --seed given: refused with the way to score one drive
};

void PrintDrive(const std::string& scenario, std::uint64_t seed, const DriveEvaluation& drive) {
  const nlohmann::json s = drive.metrics.Summary();
  std::cout << "freespace eval: " << scenario << " seed " << seed << ": " << drive.metrics.size()
            << " scans, accuracy " << s.at("accuracy").at("mean") << ", intrusion "
            << s.at("intrusion_m2").at("mean") << " m2, coverage " << s.at("coverage").at("mean")
            << std::endl;
}

// --seeds: every (scenario, seed) drive simulated and scored in memory, then the table and
// OUT/seeds.json. Ctrl-C (SIGINT) or SIGTERM stops the drives after the one at hand: the table
// and seeds.json hold the drives done (interrupted_by names the signal), then the command ends
// by the signal.
int EvalSeeds(const EvalOptions& options) {
  std::vector<std::uint64_t> seeds;
  std::vector<std::string> scenarios;
  Config config;
  bool keep_sensor = false;
  try {
    seeds = ParseSeeds(options.seeds.seeds);
    scenarios = ParseScenarios(options.seeds.scenarios, options.sim.scenario);
    config = LoadEngineConfig(options.engine, nullptr);
    keep_sensor = ConfigSetsSensor(options.engine);
    if (!keep_sensor) {
      RefuseSensorSettings(options.engine,
                           "each drive's scanner is the sensor of eval --seeds (a --config with a "
                           "sensor section replaces it, and --set then changes that)");
    }
    if (sim::MakeRig(options.sim.rig, {}).several()) {  // EvaluateDrive takes the rig's own
      RefuseSimulatedRigSettings(options.engine, options.sim.rig);
    }
    MakeDirectories(options.out);
  } catch (const std::exception& e) {
    std::cerr << "freespace eval: " << e.what() << "\n";
    return kExitSetup;
  }
  std::vector<DriveEvaluation> drives;
  const auto started = std::chrono::steady_clock::now();
  const InterruptGuard interrupt;
  int signal = 0;  // the signal that stopped the drives before the last
  try {
    for (const std::string& scenario : scenarios) {
      for (const std::uint64_t seed : seeds) {
        if ((signal = interrupt.caught()) != 0) break;
        SimOptions sim = options.sim;
        sim.scenario = scenario;
        sim.seed = seed;
        drives.push_back(EvaluateDrive(MakeSimulationOptions(sim), config, keep_sensor));
        if (!options.quiet) PrintDrive(scenario, seed, drives.back());
      }
      if (signal != 0) break;
    }
    const std::size_t planned = scenarios.size() * seeds.size();
    if (signal != 0) {
      std::cerr << "freespace eval: interrupted by " << SignalName(signal) << " after "
                << drives.size() << " of " << planned << " drives\n";
    }
    const nlohmann::json summary = SeedSummary(drives);
    // The config the drives ran (their scanner or rig in it; the same rig for every drive).
    WriteSeeds(options.out + "/seeds.json", drives.empty() ? config : drives.front().config,
               summary, signal);
    if (!options.quiet) {
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      std::cout << "freespace eval: " << drives.size() << " drives, " << seconds
                << " s; quality over seeds (docs/metrics.md):\n";
      PrintSeedTable(std::cout, summary);
      std::cout << "freespace eval: wrote " << options.out << "/seeds.json\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "freespace eval: " << e.what() << "\n";
    return kExitSetup;
  }
  // A signal during the last drive leaves every drive scored (interrupted_by null) but still ends
  // the command.
  return interrupt.Finish(signal);
}

// --log and --truth: the drive's log scored scan by scan against its truth. Ctrl-C (SIGINT) or
// SIGTERM stops after the scan at hand: eval.json holds the scans scored (interrupted_by names
// the signal), then the command ends by the signal.
class LogEval {
 public:
  explicit LogEval(const EvalOptions& options) : options_(options) {}

  int Run() {
    if (!Open()) return kExitSetup;
    const InterruptGuard interrupt;
    if (!options_.quiet) {
      std::cerr << "freespace eval: scoring " << options_.log << " against " << options_.truth
                << "\n";
    }
    const auto started = std::chrono::steady_clock::now();
    nlohmann::json report;
    try {
      Score(interrupt);
      report = QualityReport(context_, metrics_, times_);
      WriteJson(options_.out + "/eval.json", report);
    } catch (const std::exception& e) {
      std::cerr << "freespace eval: " << e.what() << "\n";
      return kExitSetup;
    }
    if (context_.interrupted_by != 0) {
      std::cerr << "freespace eval: interrupted by " << SignalName(context_.interrupted_by)
                << " after " << context_.scans_read << " scans of " << options_.log << "\n";
    }
    if (!options_.quiet) {
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      std::cout << "freespace eval: " << truth_.scenario << ", " << metrics_.size()
                << " scans scored (" << context_.rejected << " rejected), backend "
                << context_.backend << ", " << seconds << " s\n";
      PrintQuality(std::cout, report.at("summary"));
      std::cout << "freespace eval: wrote " << options_.out << "/eval.json\n";
    }
    return interrupt.Finish(context_.interrupted_by);
  }

 private:
  // The log, the config, the truth and the estimator; false (printed) when one fails.
  bool Open() {
    try {
      reader_ = OpenLog(options_.log);
      LogSensors sensors{reader_->sensors(), reader_->rig()};
      config_ = LoadEngineConfig(options_.engine, sensors);
      truth_ = sim::ReadTruth(options_.truth);
      if (config_.sensor_count() != int(truth_.rig.scanners.size())) {
        throw ConfigError("config: the drive's rig '" + truth_.rig.name + "' has " +
                          std::to_string(truth_.rig.scanners.size()) + " scanners, the config " +
                          std::to_string(config_.sensor_count()) + " sensors");
      }
      MakeDirectories(options_.out);
      estimator_ = std::make_unique<Estimator>(config_);
    } catch (const std::exception& e) {
      std::cerr << "freespace eval: " << e.what() << "\n";
      return false;
    }
    context_.scenario = truth_.scenario;
    context_.log = options_.log;
    context_.truth = options_.truth;
    context_.backend = estimator_->backend_name();
    return true;
  }

  // Every cycle of the log until its end or a signal, scored.
  void Score(const InterruptGuard& interrupt) {
    sim::TruthScorer scorer(truth_);
    CycleReader cycles(*reader_, config_.sensor_count());
    std::vector<Scan> cycle;
    for (;;) {
      if ((context_.interrupted_by = interrupt.caught()) != 0) break;
      const bool more = cycles.Next(&cycle);
      ReportIssues();  // after every read, the last (which found none) too
      if (!more) break;
      context_.scans_read += long(cycle.size());
      const Result& r = estimator_->ProcessCycle(cycle);
      if (r.status == ScanStatus::kRejected) {
        ++context_.rejected;
        std::cerr << "freespace eval: warning: scan " << r.scan_index << " rejected: " << r.message
                  << "\n";
        continue;
      }
      times_.Add(r.times);
      metrics_.Add(scorer.Score(scorer.Find(r.timestamp_s), estimator_->map(), r));
    }
  }

  void ReportIssues() {
    for (const LogIssue& issue : reader_->TakeIssues()) {
      std::cerr << "freespace eval: " << (issue.note ? "note: " : "warning: ") << issue.ToString()
                << "\n";
      if (!issue.note) ++context_.malformed_lines;
    }
  }

  const EvalOptions& options_;
  std::unique_ptr<LogReader> reader_;
  std::unique_ptr<Estimator> estimator_;
  sim::Truth truth_;
  Config config_;
  ReportContext context_;
  MetricsSeries metrics_;
  StageSeries times_;
};

int Eval(const EvalOptions& options) {
  if (!options.single_seed.empty()) {
    std::cerr << "freespace eval: --seed " << options.single_seed
              << ": eval scores the drives of --seeds (one drive: --seeds " << options.single_seed
              << ")\n";
    return kExitSetup;
  }
  if (!options.seeds.seeds.empty()) {
    if (!options.log.empty() || !options.truth.empty()) {
      std::cerr << "freespace eval: --seeds simulates its drives: give it no --log or --truth\n";
      return kExitSetup;
    }
    return EvalSeeds(options);
  }
  if (options.log.empty() || options.truth.empty()) {
    std::cerr << "freespace eval: give --log and --truth of a drive, or --seeds\n";
    return kExitSetup;
  }
  return LogEval(options).Run();
}

}  // namespace

Command AddEvalCommand(CLI::App& app) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* command = app.add_subcommand(
      "eval",
      "Run the estimator over a simulated log and score each scan against the drive's truth\n"
      "(docs/metrics.md): cell accuracy over observed cells, false-free rate, polygon\n"
      "intrusion (m^2) and coverage. Writes OUT/eval.json (summary, per-stage times, per-scan\n"
      "scores) and prints the summary. Without a `sensor` section in --config the sensor\n"
      "geometry comes from the log. With --seeds instead of --log and --truth: simulates the\n"
      "drives of those seeds (and --scenarios) in memory, scores each and prints the table of\n"
      "means over seeds, worst seed and pooled figures against the aims; writes OUT/seeds.json.");
  CLI::Option* log =
      command->add_option("--log", options->log, "Simulated log (sim.fslog or sim.clf)")
          ->check(CLI::ExistingFile);
  command->add_option("--truth", options->truth, "Truth file of the same drive (truth.json)")
      ->check(CLI::ExistingFile);
  AddSeedOptions(command, &options->seeds);
  AddSimOptions(command, &options->sim);
  LinkSeedOptions(command);
  // Each drive's seed is one of --seeds (eval simulates no single drive), and the drives'
  // options are read with --seeds only.
  command->remove_option(command->get_option("--seed"));
  SimOptionsNeed(command, command->get_option("--seeds"));
  ExcludeSimOptions(command, log);                                 // the log is the drive
  command->add_option("--seed", options->single_seed)->group("");  // hidden: says what to use
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  command->add_flag("--quiet", options->quiet, "Print nothing but errors");
  AddEngineOptions(command, &options->engine);
  return {command, [options] { return Eval(*options); }};
}

}  // namespace freespace::cli
