// `freespace demo`: the main job. Simulates a drive of a built-in scenario, runs the estimator
// on it scan by scan, scores every scan against the truth and writes the drive's logs and
// truth, polygons.jsonl, eval.json, a video and PNG snapshots; prints per-stage timings and
// the quality summary.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "commands.hpp"
#include "engine_options.hpp"
#include "eval/scorer.hpp"
#include "freespace/freespace.hpp"
#include "interrupt.hpp"
#include "output/render.hpp"
#include "output/report.hpp"
#include "output/text_file.hpp"
#include "output_options.hpp"
#include "quality_report.hpp"
#include "seed_runs.hpp"
#include "sim/rig.hpp"
#include "sim_options.hpp"

namespace freespace::cli {
namespace {

using Clock = std::chrono::steady_clock;

double Micros(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

struct DemoOptions {
  SimOptions sim;
  std::string out = "out/demo";
  int snapshot_every = 125;
  int video_every = 2;
  // demo.avi stops before it passes this size: OpenCV's AVI writer holds at most 4 GiB.
  int video_max_mb = 3840;
  bool no_video = false;
  bool quiet = false;
  std::string save_map;  // --save-map PREFIX
  EngineOptions engine;
  SeedOptions seeds;
};

// Median of a series of microsecond timings, in milliseconds.
double MedianMs(std::vector<double> v) { return Quantile(v, 0.5) / 1000.0; }

// The engine config the demo runs without --config: the defaults with the sensor model's
// outline rule (no free update where the scan's outline touches a cell) and the polygon of
// configs/scala.yaml, the conservative shape with a one-cell margin in front of occupied cells
// and unknown cells (10 degree cone) and the face layer (0.05 m), N = 128 and epsilon 0.12 m,
// which keeps the static world's intrusion within the aims (docs/metrics.md); the paper's shape
// covers about half of every obstacle cell along its border, and without the margin the map's
// sliver cells put the conservative polygon's intrusion at several cells a scan.
Config RoadConfig() {
  Config config;
  config.polygon.shape = PolygonShape::kInside;
  config.polygon.max_vertices = 128;
  config.polygon.epsilon_m = 0.12;
  config.polygon.margin_cells = 1;
  config.polygon.margin_cone_deg = 10.0;
  config.polygon.face_tolerance_m = 0.05;
  config.polygon.mover_memory_s = 3.0;
  config.sensor_model.free_on_outline = false;
  return config;
}

// One `freespace demo`: the simulated drive, the estimator, the scorer and what they write.
class DemoRun {
 public:
  // With `interrupt`, a signal it caught stops the drive after the scan at hand; the outputs
  // then hold the scans done, eval.json naming the signal (interrupted()).
  explicit DemoRun(const DemoOptions& options, const InterruptGuard* interrupt = nullptr)
      : options_(options), interrupt_(interrupt) {}

  int Run() {
    started_ = last_progress_ = Clock::now();
    if (!Open()) return kExitSetup;
    PrintSetup();
    try {
      Drive();
      SaveMapIfAsked(options_.save_map, estimator_->map(), "demo");
    } catch (const std::exception& e) {
      std::cerr << "\nfreespace demo: " << e.what() << "\n";
      return kExitSetup;
    }
    return Report();
  }

  // The drive's scores and times, after Run().
  DriveEvaluation Evaluation() const {
    DriveEvaluation d;
    d.scenario = simulation_->scenario().name;
    d.seed = options_.sim.seed;
    d.metrics = metrics_;
    d.times = times_;
    d.rejected = rejected_;
    return d;
  }
  const Config& config() const { return config_; }
  int interrupted() const { return signal_; }

 private:
  // Opens the drive, its writer, the config, the estimator and polygons.jsonl, and writes
  // config.yaml; false (printed) when one fails.
  bool Open() {
    try {
      std::vector<NamedPath> outputs;
      using Writer = sim::SimulationWriter;
      for (const char* name : {"config.yaml", "polygons.jsonl", "eval.json", "demo.avi",
                               Writer::kLogName, Writer::kCarmenName, Writer::kTruthName})
        outputs.push_back({"--out", options_.out + "/" + name});
      AddMapOutputs(options_.save_map, &outputs);
      RefuseOverwritingInputs({{"--config", options_.engine.config_path}}, outputs);
      simulation_ = std::make_unique<sim::Simulation>(MakeSimulationOptions(options_.sim));
      config_ = DriveConfig();
      MakeDirectories(options_.out);
      writer_ = std::make_unique<sim::SimulationWriter>(options_.out, truth());
      estimator_ = std::make_unique<Estimator>(config_);
      WriteTextFile(options_.out + "/config.yaml", config_.ToYaml());
      polygons_ = std::make_unique<TextFile>(options_.out + "/polygons.jsonl");
    } catch (const std::exception& e) {
      std::cerr << "freespace demo: " << e.what() << "\n";
      return false;
    }
    scorer_ = std::make_unique<sim::TruthScorer>(truth());
    return true;
  }

  const sim::Truth& truth() const { return simulation_->truth(); }

  // The engine's config for the drive: the config file and --set over the road setup, with the
  // drive's scanner unless the config has a sensor section (whose sensors must then be as many
  // as the drive's scanners). A rig of several scanners always brings its own sensors and
  // vehicle (as eval --seeds does), so --set sensor.* and rig.* are refused with it.
  Config DriveConfig() const {
    const sim::Rig& rig = truth().rig;
    const LogSensors sensors{sim::EngineSensors(rig), rig.vehicle};
    Config config;
    if (rig.several()) {
      RefuseSimulatedRigSettings(options_.engine, rig.name);
      config = sim::WithRig(LoadEngineConfig(options_.engine, sensors, RoadConfig()), rig);
      config.Validate();
    } else {
      config = LoadEngineConfig(options_.engine, sensors, RoadConfig());
    }
    if (config.sensor_count() != int(rig.scanners.size())) {
      throw ConfigError("config: the drive's rig '" + rig.name + "' has " +
                        std::to_string(rig.scanners.size()) + " scanner(s), the config " +
                        std::to_string(config.sensor_count()) + " sensors");
    }
    return config;
  }

  void PrintSetup() const {
    const sim::Scenario& scenario = simulation_->scenario();
    const std::size_t total = simulation_->scan_count();
    std::cout << "freespace demo: " << scenario.name << " (seed " << options_.sim.seed << ", rig "
              << truth().rig.name << "): " << scenario.description << "\n"
              << "freespace demo: " << total << " scans over "
              << double(total - 1) * truth().scanner.scan_period_s << " s, odometry "
              << options_.sim.odometry_noise << "; backend " << estimator_->backend_name()
              << ", map " << config_.map.width_cells << " x " << config_.map.height_cells << " at "
              << config_.map.resolution_m << " m\n";
  }

  // Simulates, estimates, scores and draws every scan of the drive, then closes its files.
  void Drive() {
    std::vector<Scan> cycle;
    std::vector<sim::EchoSource> sources;
    for (std::size_t index = 0;; ++index) {
      if (interrupt_ != nullptr && (signal_ = interrupt_->caught()) != 0) break;
      const Clock::time_point t0 = Clock::now();
      sources.clear();
      if (!simulation_->NextCycle(&cycle, &sources)) break;
      simulate_us_.push_back(Micros(t0, Clock::now()));
      echoes_.Add(sources);
      writer_->Write(cycle, simulation_->last());

      const Result& r = estimator_->ProcessCycle(cycle);
      if (r.status == ScanStatus::kRejected) {
        ++rejected_;
        std::cerr << "freespace demo: scan " << index << " rejected: " << r.message << "\n";
        continue;
      }
      times_.Add(r.times);
      polygons_->Write(PolygonJsonLine(r.scan_index, r) + '\n');
      const MapView map = estimator_->map();
      const Clock::time_point t2 = Clock::now();
      const ScanMetrics m = scorer_->Score(index, map, r);
      const Clock::time_point t3 = Clock::now();
      score_us_.push_back(Micros(t2, t3));
      metrics_.Add(m);
      const bool drawn = Draw(index, map, r, m, cycle);
      const Clock::time_point t4 = Clock::now();
      if (drawn) render_us_.push_back(Micros(t3, t4));
      PrintProgress(index, t4);
    }
    if (!options_.quiet && tty_) std::fprintf(stderr, "\r%40s\r", "");
    if (video_.isOpened()) CloseVideo();
    polygons_->Close();
    writer_->Close();
  }

  // A video frame every --video-every scans, a snapshot every --snapshot-every and of the last
  // scan: the map, the polygon, the vehicle and the true outlines. True when one was drawn.
  bool Draw(std::size_t index, const MapView& map, const Result& r, const ScanMetrics& m,
            const std::vector<Scan>& cycle) {
    const bool last = index + 1 == simulation_->scan_count();
    const bool frame = !options_.no_video && !video_full_ && index % options_.video_every == 0;
    const bool snapshot =
        last || (options_.snapshot_every > 0 && index % options_.snapshot_every == 0);
    if (!frame && !snapshot) return false;
    // The outlines that may cross the map: within the box round its corners (its axes turned by
    // map_yaw with alignment rotate or scan_match).
    const double w = map.width * map.resolution_m, h = map.height * map.resolution_m;
    const double c = std::cos(map.map_yaw), s = std::sin(map.map_yaw);
    Vec2 lo = map.origin, hi = map.origin;
    for (const Vec2& corner : {Vec2(w, 0), Vec2(0, h), Vec2(w, h)}) {
      const Vec2 at =
          map.origin + Vec2(c * corner.x() - s * corner.y(), s * corner.x() + c * corner.y());
      lo = lo.cwiseMin(at);
      hi = hi.cwiseMax(at);
    }
    const std::vector<std::vector<Vec2>> outlines = scorer_->Outlines(index, lo, hi);
    const std::vector<ScannerRays> rays = CycleRays(cycle, r, 6);
    SnapshotOverlay overlay;
    overlay.truth = &outlines;
    overlay.rays = &rays;
    char caption[200];
    std::snprintf(caption, sizeof caption,
                  "%s  t %.2f s  %.0f km/h  accuracy %.3f  intrusion %.2f m2  coverage %.2f",
                  simulation_->scenario().name.c_str(), r.timestamp_s,
                  simulation_->last().speed * 3.6, m.accuracy, m.intrusion_m2, m.coverage);
    overlay.caption = caption;
    const cv::Mat image = RenderSnapshot(map, r, overlay);
    if (frame) AddFrame(image, index);
    if (snapshot) {
      char name[64];
      std::snprintf(name, sizeof name, "/snapshot_%06zu.png", index);
      WritePng(options_.out + name, image);
      ++snapshots_;
    }
    return true;
  }

  // Appends `image` (of scan `index`) to demo.avi, opening it on the first frame; closes the
  // video instead, said, once it has passed --video-max-mb less room for a frame.
  void AddFrame(const cv::Mat& image, std::size_t index) {
    const std::string path = options_.out + "/demo.avi";
    if (video_.isOpened() && VideoFull(path, image)) {
      CloseVideo();
      video_full_ = true;
      std::cerr << "freespace demo: demo.avi stops before scan " << index << " at "
                << options_.video_max_mb << " MiB (--video-max-mb; an AVI file holds at most "
                << "4 GiB): no later frames\n";
      return;
    }
    if (!video_.isOpened()) {
      const double fps = 1.0 / (truth().scanner.scan_period_s * options_.video_every);
      video_.open(path, cv::CAP_OPENCV_MJPEG, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps,
                  image.size());
      if (!video_.isOpened()) throw OutputError(path + ": cannot open a MJPG writer");
      video_.set(cv::VIDEOWRITER_PROP_QUALITY, 75);
    }
    video_.write(image);
    ++frames_;
  }

  // Whether the next frame might take demo.avi past --video-max-mb: its size on disk (the
  // writer's buffer aside) and room for twice the raw image (a JPEG frame is far smaller).
  bool VideoFull(const std::string& path, const cv::Mat& image) const {
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(path, error);
    if (error) return false;  // checked when the video closes
    const std::uintmax_t room = 2 * image.total() * image.elemSize() + (std::uintmax_t(1) << 20);
    return size + room > std::uintmax_t(options_.video_max_mb) << 20;
  }

  void CloseVideo() {
    // OpenCV's writer reports no write errors: the file must be as long as its header says.
    video_.release();
    CheckAviWritten(options_.out + "/demo.avi");
  }

  // The share of the drive done, once a second on a terminal.
  void PrintProgress(std::size_t index, Clock::time_point now) {
    if (options_.quiet || !tty_ || now - last_progress_ <= std::chrono::seconds(1)) return;
    last_progress_ = now;
    const std::size_t total = simulation_->scan_count();
    std::fprintf(stderr, "\r%3.0f%%  scan %zu of %zu", 100.0 * double(index + 1) / total, index + 1,
                 total);
  }

  // eval.json and the printed timings and quality.
  int Report() {
    ReportContext context;
    context.scenario = simulation_->scenario().name;
    context.log = writer_->log_path();
    context.truth = writer_->truth_path();
    context.backend = estimator_->backend_name();
    context.scans_read = long(truth().scans.size());
    context.rejected = rejected_;
    context.interrupted_by = signal_;
    if (signal_ != 0) {
      std::cerr << "freespace demo: interrupted by " << SignalName(signal_) << " after "
                << metrics_.size() + std::size_t(rejected_) << " of " << simulation_->scan_count()
                << " scans\n";
    }
    const nlohmann::json report = QualityReport(context, metrics_, times_);
    try {
      WriteJson(options_.out + "/eval.json", report);
    } catch (const std::exception& e) {
      std::cerr << "freespace demo: " << e.what() << "\n";
      return kExitSetup;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - started_).count();
    PrintTimings(report.at("stage_us"));
    std::cout << "freespace demo: quality over " << metrics_.size()
              << " scans (docs/metrics.md):\n";
    PrintQuality(std::cout, report.at("summary"));
    std::cout << "freespace demo: wrote " << options_.out << "/: sim.fslog, "
              << (writer_->writes_carmen() ? "sim.clf, " : "")
              << "truth.json, config.yaml, polygons.jsonl, eval.json, "
              << (frames_ > 0 ? "demo.avi (" + std::to_string(frames_) + " frames" +
                                    (video_full_ ? ", stopped at --video-max-mb" : "") + "), "
                              : "")
              << snapshots_ << " snapshot PNG(s); " << seconds << " s in all\n";
    return kExitOk;
  }

  void PrintTimings(const nlohmann::json& stage) const {
    auto ms = [&](const char* name) { return stage.at(name).at("median").get<double>() / 1000.0; };
    char line[320];
    std::cout << "freespace demo: simulated " << echoes_.ToString() << "\n";
    std::snprintf(line, sizeof line,
                  "freespace demo: median ms per scan: simulate %.2f | estimator %.3f (preprocess "
                  "%.3f, align %.3f, rasterize %.3f, fuse %.3f, classify %.3f, mask %.3f, "
                  "insight %.3f, polygon %.3f) | score %.2f | render + video %.2f per frame\n",
                  MedianMs(simulate_us_), ms("total"), ms("preprocess"), ms("align"),
                  ms("rasterize"), ms("fuse"), ms("classify"), ms("mask"), ms("insight"),
                  ms("polygon"), MedianMs(score_us_), MedianMs(render_us_));
    std::cout << line;
  }

  const DemoOptions& options_;
  std::unique_ptr<sim::Simulation> simulation_;
  std::unique_ptr<sim::SimulationWriter> writer_;
  std::unique_ptr<Estimator> estimator_;
  std::unique_ptr<sim::TruthScorer> scorer_;
  std::unique_ptr<TextFile> polygons_;
  Config config_;
  MetricsSeries metrics_;
  StageSeries times_;
  std::vector<double> simulate_us_, score_us_, render_us_;
  EchoCounts echoes_;
  cv::VideoWriter video_;
  std::size_t snapshots_ = 0, frames_ = 0;
  bool video_full_ = false;  // demo.avi reached --video-max-mb
  long rejected_ = 0;
  const InterruptGuard* interrupt_;
  int signal_ = 0;  // the signal that stopped the drive, 0: none
  const bool tty_ = isatty(STDERR_FILENO);
  Clock::time_point started_, last_progress_;
};

// One drive: the demo's outputs, ended by the signal that stopped it (DemoRun).
int DemoOne(const DemoOptions& options) {
  const InterruptGuard interrupt;
  DemoRun run(options, &interrupt);
  if (const int code = run.Run(); code != kExitOk) return code;
  return interrupt.Finish(run.interrupted());
}

// The options of the drive (scenario, seed) of --seeds: in OUT/<scenario>-<seed>/, without video,
// the last snapshot only, its map under a prefix of its own (one prefix would keep the last
// drive's only).
DemoOptions SeedDrive(const DemoOptions& options, const std::string& scenario, std::uint64_t seed) {
  DemoOptions one = options;
  one.sim.scenario = scenario;
  one.sim.seed = seed;
  const std::string tag = scenario + "-" + std::to_string(seed);
  one.out = options.out + "/" + tag;
  one.no_video = true;
  one.snapshot_every = 0;
  if (!options.save_map.empty()) one.save_map = options.save_map + "-" + tag;
  return one;
}

// --seeds: one demo per (scenario, seed) (SeedDrive), then the table over seeds and
// OUT/seeds.json. A signal stops the drive at hand (its folder holds what it did) and the rest:
// the table and seeds.json hold the drives done before it, then the command ends by the signal.
int DemoSeeds(const DemoOptions& options) {
  std::vector<std::uint64_t> seeds;
  std::vector<std::string> scenarios;
  try {
    seeds = ParseSeeds(options.seeds.seeds);
    scenarios = ParseScenarios(options.seeds.scenarios, options.sim.scenario);
    MakeDirectories(options.out);
  } catch (const std::exception& e) {
    std::cerr << "freespace demo: " << e.what() << "\n";
    return kExitSetup;
  }
  const InterruptGuard interrupt;
  const std::size_t planned = scenarios.size() * seeds.size();
  int signal = 0;
  std::vector<DriveEvaluation> drives;
  Config config;
  for (std::size_t k = 0; k < planned; ++k) {
    // A signal between two drives: the next one's folder is not touched.
    if ((signal = interrupt.caught()) != 0) break;
    const DemoOptions one =
        SeedDrive(options, scenarios[k / seeds.size()], seeds[k % seeds.size()]);
    DemoRun run(one, &interrupt);  // holds a reference to `one`
    if (const int code = run.Run(); code != kExitOk) return code;
    config = run.config();  // a cut drive's too: seeds.json names the config even without drives
    if ((signal = run.interrupted()) != 0) break;  // a drive cut short is no seed's score
    drives.push_back(run.Evaluation());
  }
  if (signal != 0) {
    std::cerr << "freespace demo: interrupted by " << SignalName(signal) << " after "
              << drives.size() << " of " << planned << " drives\n";
  }
  const nlohmann::json summary = SeedSummary(drives);
  try {
    WriteSeeds(options.out + "/seeds.json", config, summary, signal);
  } catch (const std::exception& e) {
    std::cerr << "freespace demo: " << e.what() << "\n";
    return kExitSetup;
  }
  std::cout << "freespace demo: quality over " << drives.size()
            << " drives (docs/metrics.md, means over seeds, worst seed in brackets):\n";
  PrintSeedTable(std::cout, summary);
  std::cout << "freespace demo: wrote " << options.out << "/seeds.json\n";
  return interrupt.Finish(signal);
}

}  // namespace

Command AddDemoCommand(CLI::App& app) {
  auto options = std::make_shared<DemoOptions>();
  CLI::App* command = app.add_subcommand(
      "demo",
      "The main job: simulate a drive (default: urban, 32 s) with a ScaLa-like scanner, run\n"
      "the estimator on every scan, score it against the exact truth and write OUT/: the\n"
      "drive's logs and truth (as `simulate`), polygons.jsonl, eval.json (as `eval`), the\n"
      "engine's config.yaml, demo.avi (MJPG) and snapshot PNGs (map, polygon, vehicle,\n"
      "position circle, true outlines in green). Prints per-stage median timings and quality.\n"
      "Without --config the engine runs the road setup of configs/scala.yaml (conservative\n"
      "polygon with a one-cell margin, N = 128). With --seeds: one such drive per seed (and\n"
      "scenario of --scenarios) in OUT/<scenario>-<seed>/, without video, then the table of\n"
      "means over seeds, worst seed and pooled figures, and OUT/seeds.json.");
  AddSimOptions(command, &options->sim);
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  command
      ->add_option("--snapshot-every", options->snapshot_every,
                   "PNG snapshot every K scans, and of the last (0: only the last)")
      ->check(CLI::Range(0, 1 << 30))
      ->capture_default_str();
  command
      ->add_option("--video-every", options->video_every,
                   "A video frame every K scans (2: 12.5 frames per second of drive)")
      ->check(CLI::Range(1, 1 << 30))
      ->capture_default_str();
  command
      ->add_option("--video-max-mb", options->video_max_mb,
                   "demo.avi stops (said) before it passes this size, MiB (an AVI file holds at "
                   "most 4 GiB)")
      ->check(CLI::Range(1, 3840))
      ->capture_default_str();
  command->add_flag("--no-video", options->no_video, "Write no video");
  command->add_flag("--quiet", options->quiet, "No progress line");
  AddSaveMapOption(command, &options->save_map);
  AddEngineOptions(command, &options->engine);
  AddSeedOptions(command, &options->seeds);
  LinkSeedOptions(command);
  for (const char* name : {"--video-every", "--video-max-mb", "--snapshot-every"}) {
    command->get_option("--seeds")->excludes(command->get_option(name));  // no video, no PNGs
  }
  return {command, [options] {
            return options->seeds.seeds.empty() ? DemoOne(*options) : DemoSeeds(*options);
          }};
}

}  // namespace freespace::cli
