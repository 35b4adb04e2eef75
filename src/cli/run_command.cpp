// `freespace run`: processes a recorded log scan by scan and writes polygons.jsonl,
// summary.json and PNG snapshots (docs/formats.md). Bad input is reported with file and line,
// skipped and counted; with --strict the first bad input stops the run with exit code 1.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>

#include "commands.hpp"
#include "engine_options.hpp"
#include "eval/stage_stats.hpp"
#include "freespace/freespace.hpp"
#include "output/render.hpp"
#include "output/report.hpp"

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

int Run(const RunOptions& options) {
  std::unique_ptr<LogReader> reader;
  std::unique_ptr<Estimator> estimator;
  std::ofstream polygons;
  Config config;
  try {
    LogOptions log_options;
    log_options.format = ParseFormat(options.format);
    reader = OpenLog(options.log, log_options);
    config = LoadEngineConfig(options.engine, &reader->sensor());
    MakeDirectories(options.out);
    estimator = std::make_unique<Estimator>(config);
    polygons.open(options.out + "/polygons.jsonl", std::ios::trunc);
    if (!polygons) throw InputError(options.out + "/polygons.jsonl: cannot create");
  } catch (const std::exception& e) {
    std::cerr << "freespace run: " << e.what() << "\n";
    return kExitSetup;
  }
  const SensorConfig& s = config.sensor;
  std::cerr << "freespace run: " << options.log << ": " << s.layers << " layer(s), "
            << s.min_angle_deg << " .. " << s.max_angle_deg << " deg at "
            << s.angular_resolution_deg << " deg, no echo at >= " << s.max_range_m << " m; backend "
            << estimator->backend_name() << "; map " << config.map.width_cells << " x "
            << config.map.height_cells << " at " << config.map.resolution_m << " m\n";

  const bool tty = isatty(STDERR_FILENO);
  Warnings warnings;
  StageSeries times;
  std::map<std::string, long> rejected;
  long scans_read = 0, processed = 0, no_update = 0, malformed = 0, resets = 0, jitter = 0;
  long invalid_range = 0, out_of_aperture = 0, bad_layer = 0, clutter = 0, virtual_points = 0;
  long points = 0, max_vertices = 0, vehicle_outside = 0;
  double vertex_sum = 0;
  int exit_code = kExitOk;
  Scan scan;
  auto last_progress = std::chrono::steady_clock::now();
  const auto started = last_progress;
  std::size_t snapshots = 0;

  auto snapshot = [&](const Result& r) {
    char name[64];
    std::snprintf(name, sizeof name, "/snapshot_%06llu.png",
                  static_cast<unsigned long long>(r.scan_index));
    SnapshotOverlay overlay;
    char caption[160];
    std::snprintf(caption, sizeof caption, "scan %llu  t %.1f s  speed %.1f m/s  %zu vertices",
                  static_cast<unsigned long long>(r.scan_index), r.timestamp_s,
                  r.filtered_speed_mps, r.polygon.size());
    overlay.caption = caption;
    WritePng(options.out + name, RenderSnapshot(estimator->map(), r, overlay));
    ++snapshots;
  };

  const Result* last = nullptr;
  try {
    while (options.max_scans <= 0 || scans_read < options.max_scans) {
      const bool more = reader->Next(&scan);
      for (const LogIssue& issue : reader->TakeIssues()) {
        ++malformed;
        warnings.Print("input", issue.ToString());
        if (options.strict) {
          std::cerr << "freespace run: stopped (--strict) on bad input\n";
          return kExitBadInput;
        }
      }
      if (!more) break;
      ++scans_read;
      const std::string where = reader->path() + ":" + std::to_string(reader->line());
      const Result& r = estimator->Process(scan);
      const ScanStats& st = r.stats;
      points += st.points;
      invalid_range += st.invalid_range;
      out_of_aperture += st.out_of_aperture;
      bad_layer += st.bad_layer;
      clutter += st.clutter;
      virtual_points += st.virtual_points;
      if (st.invalid_range + st.out_of_aperture + st.bad_layer > 0) {
        warnings.Print("points", where + ": scan " + std::to_string(r.scan_index) + ": " +
                                     std::to_string(st.invalid_range) +
                                     " invalid range(s) used as no echo, " +
                                     std::to_string(st.out_of_aperture) +
                                     " angle(s) outside the aperture and " +
                                     std::to_string(st.bad_layer) + " bad layer(s) dropped");
        if (options.strict) {
          std::cerr << "freespace run: stopped (--strict) on bad input\n";
          return kExitBadInput;
        }
      }
      if (r.status == ScanStatus::kRejected) {
        ++rejected[ToString(r.reject_reason)];
        warnings.Print(ToString(r.reject_reason),
                       where + ": scan " + std::to_string(r.scan_index) + " skipped: " + r.message);
        if (options.strict) {
          std::cerr << "freespace run: stopped (--strict) on bad input\n";
          return kExitBadInput;
        }
        continue;
      }
      if (r.status == ScanStatus::kNoSensorUpdate) {
        ++no_update;
        warnings.Print("no_sensor_update",
                       where + ": scan " + std::to_string(r.scan_index) + ": " + r.message);
        if (options.strict && scan.points.empty()) {
          std::cerr << "freespace run: stopped (--strict) on an empty scan\n";
          return kExitBadInput;
        }
      }
      if (r.timestamp_jitter) {
        ++jitter;
        warnings.Print("timestamp_jitter",
                       where + ": scan " + std::to_string(r.scan_index) + ": " + r.message);
        if (options.strict) {
          std::cerr << "freespace run: stopped (--strict) on a timestamp going backwards\n";
          return kExitBadInput;
        }
      }
      if (r.map_reset && processed > 0) {
        ++resets;
        warnings.Print("reset", where + ": scan " + std::to_string(r.scan_index) +
                                    ": the map restarted here after repeated pose jumps");
      }
      ++processed;
      times.Add(r.times);
      vertex_sum += double(r.polygon.size());
      max_vertices = std::max<long>(max_vertices, long(r.polygon.size()));
      vehicle_outside += r.polygon_contains_vehicle ? 0 : 1;
      polygons << PolygonJsonLine(r.scan_index, r) << '\n';
      last = &r;
      if (options.snapshot_every > 0 && (processed - 1) % options.snapshot_every == 0) snapshot(r);

      const auto now = std::chrono::steady_clock::now();
      if (!options.quiet && now - last_progress > std::chrono::seconds(tty ? 1 : 10)) {
        last_progress = now;
        char line[200];
        std::snprintf(line, sizeof line,
                      "%s%3.0f%%  scan %ld  processed %ld  skipped %ld  median %.3f ms/scan",
                      tty ? "\r" : "", 100.0 * reader->progress(), scans_read, processed,
                      scans_read - processed, times.MedianTotal() / 1000.0);
        std::cerr << line << (tty ? "" : "\n") << std::flush;
      }
    }
    if (last != nullptr &&
        (options.snapshot_every <= 0 || (processed - 1) % options.snapshot_every != 0)) {
      snapshot(*last);
    }
  } catch (const std::exception& e) {
    std::cerr << "\nfreespace run: " << e.what() << "\n";
    return kExitSetup;
  }
  polygons.close();

  long rejected_total = 0;
  nlohmann::json rejected_json = nlohmann::json::object();
  for (const auto& [reason, n] : rejected) {
    rejected_json[reason] = n;
    rejected_total += n;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  nlohmann::json summary = {
      {"log", options.log},
      {"backend", estimator->backend_name()},
      {"scans_read", scans_read},
      {"scans", processed},
      {"skipped", rejected_total + malformed},
      {"rejected", rejected_json},
      {"malformed_lines", malformed},
      {"no_sensor_update", no_update},
      {"map_resets", resets},
      {"timestamp_jitter", jitter},
      {"points",
       {{"total", points},
        {"invalid_range", invalid_range},
        {"out_of_aperture", out_of_aperture},
        {"bad_layer", bad_layer},
        {"clutter", clutter},
        {"virtual", virtual_points}}},
      {"polygon",
       {{"max_vertices", max_vertices},
        {"mean_vertices", processed ? vertex_sum / processed : 0.0},
        {"vehicle_outside", vehicle_outside}}},
      {"snapshots", snapshots},
      {"wall_s", seconds},
      {"stage_us", times.Summary()},
  };
  std::ofstream(options.out + "/summary.json") << summary.dump(2) << "\n";
  std::cerr << (tty ? "\r" : "") << "freespace run: " << processed << " scans processed, "
            << rejected_total + malformed << " skipped, median " << times.MedianTotal() / 1000.0
            << " ms/scan; wrote " << options.out << "/polygons.jsonl, summary.json and "
            << snapshots << " PNG(s)\n";
  return exit_code;
}

}  // namespace

Command AddRunCommand(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* command = app.add_subcommand(
      "run",
      "Process a recorded log. Writes OUT/polygons.jsonl (one JSON object per processed scan:\n"
      "scan, t, status, pose {x,y,yaw}, origin (world position of the map's cell (0,0) corner),\n"
      "vehicle_cells, speed, polygon [[x,y],...] in world metres, at most N vertices),\n"
      "OUT/summary.json (scans, skipped, rejected by reason, point counts, stage_us median and\n"
      "p99 per stage) and OUT/snapshot_<scan>.png every K scans and for the last scan.\n"
      "Logs: CARMEN (FLASER, ROBOTLASER1), KITTI .bin frames, FREESPACE_LOG (docs/formats.md).\n"
      "Without a `sensor` section in --config the sensor geometry comes from the log.");
  command->add_option("--log", options->log, "Log file to process")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  command->add_option("--format", options->format, "Log format")
      ->check(CLI::IsMember({"auto", "carmen", "kitti", "freespace"}))
      ->capture_default_str();
  command
      ->add_option("--snapshot-every", options->snapshot_every,
                   "PNG snapshot every K processed scans (0: only the last)")
      ->check(CLI::Range(0, 1 << 30))
      ->capture_default_str();
  command->add_option("--max-scans", options->max_scans, "Stop after this many scans (0: all)");
  command->add_flag("--strict", options->strict,
                    "Stop with exit code 1 at the first bad input instead of skipping it");
  command->add_flag("--quiet", options->quiet, "No progress line");
  AddEngineOptions(command, &options->engine);
  return {command, [options] { return Run(*options); }};
}

}  // namespace freespace::cli
