// `freespace run`: processes a recorded log scan by scan and writes polygons.jsonl,
// summary.json and PNG snapshots (docs/formats.md). Bad input is reported with file and line,
// skipped and counted; with --strict the first bad input stops the run with exit code 1.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include "bag_options.hpp"
#include "commands.hpp"
#include "engine_options.hpp"
#include "freespace/freespace.hpp"
#include "interrupt.hpp"
#include "output/render.hpp"
#include "output/report.hpp"
#include "output/text_file.hpp"
#include "output_options.hpp"
#include "run_tally.hpp"

namespace freespace::cli {
namespace {

struct RunOptions {
  std::string log;
  std::string out = "out/run";
  std::string format = "auto";
  int snapshot_every = 500;
  long max_scans = 0;
  bool strict = false;
  bool quiet = false;
  std::string save_map;  // --save-map PREFIX
  std::string polygon_format = "jsonl";
  BagCliOptions bag;  // ROS bag topics in, --out-bag
  EngineOptions engine;
};

// Prints the first few warnings of each kind, then only counts them.
class Warnings {
 public:
  void Print(const std::string& kind, const std::string& text) {
    const int n = ++printed_[kind];
    if (n <= kLimit) {
      std::cerr << "\nwarning: " << text << "\n";
    } else if (n == kLimit + 1) {
      std::cerr << "\nwarning: further '" << kind << "' warnings are only counted (summary.json)\n";
    }
  }

 private:
  static constexpr int kLimit = 10;
  std::map<std::string, int> printed_;
};

LogFormat ParseFormat(const std::string& name) {
  if (name == "carmen") return LogFormat::kCarmen;
  if (name == "kitti") return LogFormat::kKitti;
  if (name == "freespace") return LogFormat::kNative;
  return LogFormat::kAuto;
}

using Clock = std::chrono::steady_clock;

// One `freespace run`: the log, the estimator, and what they write.
class LogRun {
 public:
  explicit LogRun(const RunOptions& options) : options_(options) {}

  // Ctrl-C or SIGTERM ends the run after the scan at hand, with every output closed and
  // summary.json saying so (interrupted_by), then by the signal (InterruptGuard::Finish).
  int Run() {
    if (!Open()) return kExitSetup;
    const InterruptGuard interrupt;
    interrupt_ = &interrupt;
    PrintSetup();
    tty_ = isatty(STDERR_FILENO);
    started_ = last_progress_ = Clock::now();
    try {
      const int code = ProcessLog();
      if (code != kExitOk) return code;
      polygons_->Close();
      bag_out_.Close();
      SaveMapIfAsked(options_.save_map, estimator_->map(), "run");
      WriteSummary();
    } catch (const std::exception& e) {
      // A failed write (OutputError) or a backend failure: nothing more is claimed written.
      std::cerr << "\nfreespace run: " << e.what() << "\n";
      return kExitSetup;
    }
    PrintClosing();
    // A signal after the last scan leaves the outputs as they are (whole, interrupted_by null)
    // but still ends the command.
    return interrupt.Finish(signal_);
  }

 private:
  enum class Verdict { kKeep, kSkip, kStop };

  // Opens the log, the config, the estimator and polygons.jsonl; false (printed) when one fails.
  bool Open() {
    try {
      LogOptions log_options;
      log_options.format = ParseFormat(options_.format);
      reader_ = OpenInput(options_.log, log_options, options_.bag);
      LogSensors sensors{reader_->sensors(), reader_->rig()};
      config_ = LoadEngineConfig(options_.engine, sensors);
      const std::string replaced = SensorReplacedNote(reader_->sensors(), config_);
      if (!replaced.empty()) std::cerr << "note: " << replaced << "\n";
      if (reader_->sensors().size() > std::size_t(config_.sensor_count())) {
        throw ConfigError("config: the log holds scans of " +
                          std::to_string(reader_->sensors().size()) + " sensors, the config has " +
                          std::to_string(config_.sensor_count()));
      }
      cycles_ = std::make_unique<CycleReader>(*reader_, config_.sensor_count());
      tally_ = RunTally(config_.sensor_count());
      RefuseOverwritingInputs({{"--log", options_.log}, {"--config", options_.engine.config_path}},
                              Outputs());
      MakeDirectories(options_.out);
      estimator_ = std::make_unique<Estimator>(config_);
      bag_out_.Open(options_.bag);
      RemoveEarlierRun();  // once nothing before the first scan can fail
      polygons_ =
          std::make_unique<TextFile>(options_.out + "/" + PolygonFileName(options_.polygon_format));
    } catch (const std::exception& e) {
      std::cerr << "freespace run: " << e.what() << "\n";
      return false;
    }
    return true;
  }

  // The files the run writes or removes.
  std::vector<NamedPath> Outputs() const {
    std::vector<NamedPath> outputs = {{"--out-bag", options_.bag.out_bag}};
    for (const char* name : {"summary.json", "polygons.jsonl", "polygons.geojsonl"})
      outputs.push_back({"--out", options_.out + "/" + name});
    AddMapOutputs(options_.save_map, &outputs);
    for (const std::filesystem::path& p : EarlierRunFiles())
      outputs.push_back({"--out", p.string()});
    return outputs;
  }

  // The files an earlier run left in --out (summary.json, both polygon files, snapshots), which
  // the run removes; none while --out does not exist.
  std::vector<std::filesystem::path> EarlierRunFiles() const {
    namespace fs = std::filesystem;
    std::error_code error;
    std::vector<fs::path> old;
    if (!fs::exists(options_.out, error) && !error) return old;
    for (fs::directory_iterator it(options_.out, error), end; !error && it != end;
         it.increment(error)) {
      const fs::path& p = it->path();
      const std::string name = p.filename().string();
      const bool snapshot = name.rfind("snapshot_", 0) == 0 && p.extension() == ".png";
      if (!snapshot && name != "summary.json" && name != "polygons.jsonl" &&
          name != "polygons.geojsonl") {
        continue;
      }
      std::error_code kind;
      if (fs::is_regular_file(fs::symlink_status(p, kind)) && !kind) old.push_back(p);
    }
    if (error) throw OutputError(options_.out + ": cannot list: " + error.message());
    return old;
  }

  // A run that stops early must not leave an earlier run's files beside its own, looking
  // complete. Says what it removed.
  void RemoveEarlierRun() const {
    const std::vector<std::filesystem::path> old = EarlierRunFiles();
    for (const std::filesystem::path& p : old) {
      std::error_code error;
      if (!std::filesystem::remove(p, error) && error) {
        throw OutputError(p.string() + ": cannot remove an earlier run's file: " + error.message());
      }
    }
    if (!old.empty()) {
      std::cerr << "freespace run: removed " << old.size() << " file(s) of an earlier run from "
                << options_.out << "\n";
    }
  }

  void PrintSetup() const {
    const SensorConfig& s = config_.sensor_at(0);
    if (config_.is_rig()) {
      std::cerr << "freespace run: " << options_.log << ": a rig of " << config_.sensor_count()
                << " sensors; the first, " << s.name << ":\n";
    }
    std::cerr << "freespace run: " << options_.log << ": " << s.layers << " layer(s), "
              << s.min_angle_deg << " .. " << s.max_angle_deg << " deg at "
              << s.angular_resolution_deg
              << " deg, no echo at >= " << s.max_range_m - s.no_echo_margin_m << " m; backend "
              << estimator_->backend_name() << "; map " << config_.map.width_cells << " x "
              << config_.map.height_cells << " at " << config_.map.resolution_m << " m\n";
  }

  // Every scan of the log (up to --max-scans); kExitBadInput when --strict stops it.
  // A rig's log goes by cycles (CycleReader); --max-scans counts scans: the last cycle is cut
  // to the limit.
  int ProcessLog() {
    std::vector<Scan> cycle;
    // A copy: the estimator's result is the next scan's once that is processed, rejected too.
    Result last;
    bool any = false;
    while (options_.max_scans <= 0 || tally_.scans_read < options_.max_scans) {
      if ((signal_ = interrupt_->caught()) != 0) break;
      const bool more = cycles_->Next(&cycle);
      if (ReportIssues()) return kExitBadInput;
      if (!more) break;
      const bool cut =
          options_.max_scans > 0 && tally_.scans_read + long(cycle.size()) > options_.max_scans;
      if (cut) cycle.resize(std::size_t(options_.max_scans - tally_.scans_read));
      tally_.scans_read += long(cycle.size());
      tally_.cycles_read += tally_.rig() ? 1 : 0;
      const Result& r = estimator_->ProcessCycle(cycle);
      const Verdict verdict = Check(r, cycle, Where(r, cycle.size()), cut);
      if (verdict == Verdict::kStop) return kExitBadInput;
      if (verdict == Verdict::kSkip) continue;
      Keep(r, long(cycle.size()));
      last = r;
      any = true;
      PrintProgress();
    }
    // The last processed scan always gets a snapshot.
    if (any &&
        (options_.snapshot_every <= 0 || (tally_.calls - 1) % options_.snapshot_every != 0)) {
      Snapshot(last);
    }
    return kExitOk;
  }

  // Where a warning about call `r` on the `scans` first scans of the cycle read points: the
  // log's line (a rig's cycle: its lines) and the scan's (cycle's) index.
  std::string Where(const Result& r, std::size_t scans) const {
    std::string at = reader_->path() + ":" + std::to_string(cycles_->line());
    const std::size_t last = cycles_->line_of(scans > 0 ? scans - 1 : 0);
    if (last != cycles_->line()) at += "-" + std::to_string(last);
    return at + (tally_.rig() ? ": cycle " : ": scan ") + std::to_string(r.scan_index);
  }

  // Under --strict: prints why the run stops and returns true.
  bool StopsHere(const char* what) const {
    if (!options_.strict) return false;
    std::cerr << "freespace run: stopped (--strict) on " << what << "\n";
    return true;
  }

  // The reader's malformed lines; true when --strict stops the run. A note (what the reader
  // assumed for what the input lacks) is printed, neither counted nor stopped on.
  bool ReportIssues() {
    for (const LogIssue& issue : reader_->TakeIssues()) {
      if (issue.note) {
        std::cerr << "\nnote: " << issue.ToString() << "\n";
        continue;
      }
      ++tally_.malformed;
      warnings_.Print("input", issue.ToString());
      if (StopsHere("bad input")) return true;
    }
    return false;
  }

  // Counts and warns about what went wrong with one call's input (a scan, a rig's cycle; `cut`
  // short by --max-scans).
  Verdict Check(const Result& r, const std::vector<Scan>& cycle, const std::string& at, bool cut) {
    const ScanStats& st = r.stats;
    tally_.AddPoints(st);
    if (st.invalid_range + st.out_of_aperture + st.bad_layer > 0) {
      warnings_.Print("points", at + ": " + std::to_string(st.invalid_range) +
                                    " invalid range(s) used as no echo, " +
                                    std::to_string(st.out_of_aperture) +
                                    " angle(s) outside the aperture and " +
                                    std::to_string(st.bad_layer) + " bad layer(s) dropped");
      if (StopsHere("bad input")) return Verdict::kStop;
    }
    if (r.status == ScanStatus::kRejected) {
      tally_.AddRejected(r, long(cycle.size()));
      warnings_.Print(ToString(r.reject_reason), at + " skipped: " + r.message);
      return StopsHere("bad input") ? Verdict::kStop : Verdict::kSkip;
    }
    // A scan (of a rig: any sensor's) that added nothing, or a rig's sensor without a scan.
    const RunTally::Silent silent = tally_.AddSilent(r, cycle, cut);
    if (silent.scans + silent.missing > 0) {
      warnings_.Print(
          silent.scans > 0 ? "no_sensor_update" : "sensor_missing",
          at + ": " + r.message +
              (cut ? " (--max-scans cut the cycle after " + std::to_string(cycle.size()) + " scans)"
                   : ""));
      const bool empty = std::any_of(cycle.begin(), cycle.end(),
                                     [](const Scan& scan) { return scan.points.empty(); });
      if (empty && StopsHere("an empty scan")) return Verdict::kStop;
    }
    if (r.clock_stalled) {
      ++tally_.stalled;
      // Said once per stall, not once per scan.
      if (r.stall_detected) {
        warnings_.Print("clock_stalled", at + ": " + r.message);
        if (StopsHere("a stalled clock")) return Verdict::kStop;
      }
    }
    if (r.sweep_corrected) ++tally_.swept;
    if (r.timestamp_jitter) {
      ++tally_.jitter;
      warnings_.Print("timestamp_jitter", at + ": " + r.message);
      if (StopsHere("a timestamp going backwards")) return Verdict::kStop;
    }
    if (r.map_reset && tally_.calls > 0) {
      ++tally_.resets;
      warnings_.Print("reset", at + ": " + r.message);
    }
    return Verdict::kKeep;
  }

  // A processed call (`scans` scans): counted, its polygon line written, a snapshot every
  // --snapshot-every.
  void Keep(const Result& r, long scans) {
    tally_.AddProcessed(r, scans);
    polygons_->Write(PolygonLine(options_.polygon_format, r) + '\n');
    if (bag_out_.active()) bag_out_.Write(r, estimator_->map());
    if (options_.snapshot_every > 0 && (tally_.calls - 1) % options_.snapshot_every == 0) {
      Snapshot(r);
    }
  }

  void Snapshot(const Result& r) {
    char name[64];
    std::snprintf(name, sizeof name, "/snapshot_%06llu.png",
                  static_cast<unsigned long long>(r.scan_index));
    SnapshotOverlay overlay;
    char caption[160];
    std::snprintf(caption, sizeof caption, "scan %llu  t %.1f s  speed %.1f m/s  %zu vertices",
                  static_cast<unsigned long long>(r.scan_index), r.timestamp_s,
                  r.filtered_speed_mps, r.polygon.size());
    overlay.caption = caption;
    WritePng(options_.out + name, RenderSnapshot(estimator_->map(), r, overlay));
    ++tally_.snapshots;
  }

  // A progress line every second on a terminal, every 10 s otherwise.
  void PrintProgress() {
    const auto now = Clock::now();
    if (options_.quiet || now - last_progress_ <= std::chrono::seconds(tty_ ? 1 : 10)) return;
    last_progress_ = now;
    char line[200];
    std::snprintf(line, sizeof line,
                  "%s%3.0f%%  scan %ld  processed %ld  skipped %ld  median %.3f ms/%s",
                  tty_ ? "\r" : "", 100.0 * reader_->progress(), tally_.scans_read,
                  tally_.processed, tally_.scans_read - tally_.processed,
                  tally_.times.MedianTotal() / 1000.0, tally_.rig() ? "cycle" : "scan");
    std::cerr << line << (tty_ ? "" : "\n") << std::flush;
  }

  // summary.json; throws OutputError when it cannot be written in full.
  void WriteSummary() {
    seconds_ = std::chrono::duration<double>(Clock::now() - started_).count();
    nlohmann::json summary = tally_.Counts(config_);
    summary["log"] = options_.log;
    summary["backend"] = estimator_->backend_name();
    summary["wall_s"] = seconds_;
    summary["interrupted_by"] =
        signal_ != 0 ? nlohmann::json(SignalName(signal_)) : nlohmann::json();
    summary["stage_us"] = tally_.times.Summary();
    WriteTextFile(options_.out + "/summary.json", summary.dump(2) + "\n");
  }

  // The closing line on stderr, once everything is written.
  void PrintClosing() const {
    const RunTally& t = tally_;
    const long skipped = t.Rejected() + t.malformed;
    if (signal_ != 0) {
      std::cerr << (tty_ ? "\n" : "") << "freespace run: interrupted by " << SignalName(signal_)
                << " after " << t.scans_read << " scans of " << options_.log << " ("
                << int(100.0 * reader_->progress()) << " %); the rest was not read\n";
    }
    std::cerr << (tty_ ? "\r" : "") << "freespace run: " << t.processed << " scans"
              << (t.rig() ? " in " + std::to_string(t.calls) + " cycles" : std::string())
              << " processed, " << skipped << " skipped, median " << t.times.MedianTotal() / 1000.0
              << (t.rig() ? " ms/cycle" : " ms/scan") << "; wrote " << options_.out << "/"
              << PolygonFileName(options_.polygon_format) << ", summary.json and " << t.snapshots
              << " PNG(s)\n";
  }

  const RunOptions& options_;
  std::unique_ptr<LogReader> reader_;
  std::unique_ptr<Estimator> estimator_;
  std::unique_ptr<CycleReader> cycles_;
  std::unique_ptr<TextFile> polygons_;
  BagOutput bag_out_;
  Config config_;
  Warnings warnings_;
  RunTally tally_{1};
  bool tty_ = false;
  const InterruptGuard* interrupt_ = nullptr;
  int signal_ = 0;  // the signal that stopped the run, 0: none
  double seconds_ = 0;
  Clock::time_point started_, last_progress_;
};

}  // namespace

Command AddRunCommand(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* command = app.add_subcommand(
      "run",
      "Process a recorded log. Writes OUT/polygons.jsonl (one JSON object per processed scan:\n"
      "scan, t_s, status, frame, pose {x,y,yaw}, origin (world position of the map's cell (0,0)\n"
      "corner), vehicle_cells, map_yaw_rad, pose_correction {x,y,yaw}, speed_mps, polygon_status,\n"
      "polygon [[x,y],...]: a closed counter-clockwise ring in world metres, at most N distinct\n"
      "vertices),\n"
      "OUT/summary.json (scans, skipped, rejected by reason, point counts, stage_us median and\n"
      "p99 per stage) and OUT/snapshot_<scan>.png every K scans and for the last scan.\n"
      "Logs: CARMEN (FLASER, ROBOTLASER1), KITTI .bin frames and sequence folders (velodyne/,\n"
      "poses.txt, calib.txt, times.txt), FREESPACE_LOG (docs/formats.md), ROS 1 bags\n"
      "(sensor_msgs/LaserScan or PointCloud2 + nav_msgs/Odometry or /tf).\n"
      "Without a `sensor` section in --config the sensor geometry comes from the log.\n"
      "Ctrl-C (SIGINT) or SIGTERM stops the run after the scan at hand: every output is\n"
      "closed whole and summary.json names the signal (interrupted_by); the run then ends by\n"
      "that signal (a shell sees exit status 128 + signal).");
  command
      ->add_option("--log", options->log,
                   "Log file to process, or a KITTI odometry sequence folder")
      ->required()
      ->check(CLI::ExistingPath);
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  command->add_option("--format", options->format, "Log format")
      ->check(CLI::IsMember({"auto", "carmen", "kitti", "freespace"}))
      ->capture_default_str();
  command
      ->add_option("--snapshot-every", options->snapshot_every,
                   "PNG snapshot every K processed scans (0: only the last)")
      ->check(CLI::Range(0, 1 << 30))
      ->capture_default_str();
  command->add_option("--max-scans", options->max_scans, "Stop after this many scans (0: all)")
      ->check(CLI::Range(0, 1 << 30));
  command->add_flag("--strict", options->strict,
                    "Stop with exit code 1 at the first bad input instead of skipping it");
  command->add_flag("--quiet", options->quiet, "No progress line");
  AddSaveMapOption(command, &options->save_map);
  AddPolygonFormatOption(command, &options->polygon_format);
  AddBagOptions(command, &options->bag);
  AddEngineOptions(command, &options->engine);
  return {command, [options] { return LogRun(*options).Run(); }};
}

}  // namespace freespace::cli
