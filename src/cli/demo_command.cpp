// `freespace demo`: the main job. Simulates a drive of a built-in scenario, runs the estimator
// on it scan by scan, scores every scan against the truth and writes the drive's logs and
// truth, polygons.jsonl, eval.json, a video and PNG snapshots; prints per-stage timings and
// the quality summary.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "commands.hpp"
#include "engine_options.hpp"
#include "eval/scorer.hpp"
#include "freespace/freespace.hpp"
#include "output/render.hpp"
#include "output/report.hpp"
#include "quality_report.hpp"
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
  bool no_video = false;
  bool quiet = false;
  EngineOptions engine;
};

// Median of a series of microsecond timings, in milliseconds.
double MedianMs(std::vector<double> v) { return Quantile(v, 0.5) / 1000.0; }

// The engine config the demo runs without --config: the defaults with the polygon of
// configs/scala.yaml, the conservative shape with a one-cell margin in front of occupied cells
// (60 degree cone), N = 128 and epsilon 0.12 m, which meets the quality aims on the three
// scenarios (docs/metrics.md); the paper's shape covers about half of every obstacle cell
// along its border, and without the margin the map's sliver cells put the conservative
// polygon's intrusion at several cells a scan.
Config RoadConfig() {
  Config config;
  config.polygon.shape = PolygonShape::kInside;
  config.polygon.max_vertices = 128;
  config.polygon.epsilon_m = 0.12;
  config.polygon.margin_cells = 1;
  config.polygon.margin_cone_deg = 60.0;
  return config;
}

int Demo(const DemoOptions& options) {
  const Clock::time_point started = Clock::now();
  std::unique_ptr<sim::Simulation> simulation;
  std::unique_ptr<sim::SimulationWriter> writer;
  std::unique_ptr<Estimator> estimator;
  std::ofstream polygons;
  Config config;
  try {
    simulation = std::make_unique<sim::Simulation>(MakeSimulationOptions(options.sim));
    MakeDirectories(options.out);
    writer = std::make_unique<sim::SimulationWriter>(options.out, simulation->truth().scanner);
    const SensorConfig sensor = simulation->truth().scanner.EngineSensor();
    config = LoadEngineConfig(options.engine, &sensor, RoadConfig());
    estimator = std::make_unique<Estimator>(config);
    std::ofstream(options.out + "/config.yaml") << config.ToYaml();
    polygons.open(options.out + "/polygons.jsonl", std::ios::trunc);
    if (!polygons) throw InputError(options.out + "/polygons.jsonl: cannot create");
  } catch (const std::exception& e) {
    std::cerr << "freespace demo: " << e.what() << "\n";
    return kExitSetup;
  }
  const sim::Scenario& scenario = simulation->scenario();
  const std::size_t total = simulation->scan_count();
  std::cout << "freespace demo: " << scenario.name << " (seed " << options.sim.seed
            << "): " << scenario.description << "\n"
            << "freespace demo: " << total << " scans over "
            << double(total - 1) * simulation->truth().scanner.scan_period_s << " s, odometry "
            << options.sim.odometry_noise << "; backend " << estimator->backend_name() << ", map "
            << config.map.width_cells << " x " << config.map.height_cells << " at "
            << config.map.resolution_m << " m\n";

  sim::TruthScorer scorer(simulation->truth());
  MetricsSeries metrics;
  StageSeries times;
  std::vector<double> simulate_us, score_us, render_us;
  EchoCounts echoes;
  cv::VideoWriter video;
  const std::string video_path = options.out + "/demo.avi";
  std::size_t snapshots = 0, frames = 0;
  long rejected = 0;
  const bool tty = isatty(STDERR_FILENO);
  Clock::time_point last_progress = started;
  const double fps = 1.0 / (simulation->truth().scanner.scan_period_s * options.video_every);
  const double map_w = config.map.width_cells * config.map.resolution_m;
  const double map_h = config.map.height_cells * config.map.resolution_m;

  try {
    Scan scan;
    std::vector<sim::EchoSource> sources;
    for (std::size_t index = 0;; ++index) {
      const Clock::time_point t0 = Clock::now();
      if (!simulation->Next(&scan, &sources)) break;
      const Clock::time_point t1 = Clock::now();
      simulate_us.push_back(Micros(t0, t1));
      echoes.Add(sources);
      writer->Write(scan);

      const Result& r = estimator->Process(scan);
      if (r.status == ScanStatus::kRejected) {
        ++rejected;
        std::cerr << "freespace demo: scan " << index << " rejected: " << r.message << "\n";
        continue;
      }
      times.Add(r.times);
      polygons << PolygonJsonLine(r.scan_index, r) << '\n';
      const MapView map = estimator->map();
      const Clock::time_point t2 = Clock::now();
      const ScanMetrics m = scorer.Score(index, map, r);
      const Clock::time_point t3 = Clock::now();
      score_us.push_back(Micros(t2, t3));
      metrics.Add(m);

      const bool last = index + 1 == total;
      const bool frame = !options.no_video && index % options.video_every == 0;
      const bool snapshot =
          last || (options.snapshot_every > 0 && index % options.snapshot_every == 0);
      if (frame || snapshot) {
        const std::vector<std::vector<Vec2>> truth =
            scorer.Outlines(index, map.origin, map.origin + Vec2(map_w, map_h));
        SnapshotOverlay overlay;
        overlay.truth = &truth;
        char caption[200];
        std::snprintf(caption, sizeof caption,
                      "%s  t %.2f s  %.0f km/h  accuracy %.3f  intrusion %.2f m2  coverage %.2f",
                      scenario.name.c_str(), r.timestamp_s, simulation->last().speed * 3.6,
                      m.accuracy, m.intrusion_m2, m.coverage);
        overlay.caption = caption;
        const cv::Mat image = RenderSnapshot(map, r, overlay);
        if (frame) {
          if (!video.isOpened()) {
            video.open(video_path, cv::CAP_OPENCV_MJPEG,
                       cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, image.size());
            if (!video.isOpened()) throw InputError(video_path + ": cannot open a MJPG writer");
            video.set(cv::VIDEOWRITER_PROP_QUALITY, 75);
          }
          video.write(image);
          ++frames;
        }
        if (snapshot) {
          char name[64];
          std::snprintf(name, sizeof name, "/snapshot_%06zu.png", index);
          WritePng(options.out + name, image);
          ++snapshots;
        }
      }
      const Clock::time_point t4 = Clock::now();
      if (frame || snapshot) render_us.push_back(Micros(t3, t4));

      if (!options.quiet && tty && t4 - last_progress > std::chrono::seconds(1)) {
        last_progress = t4;
        std::fprintf(stderr, "\r%3.0f%%  scan %zu of %zu", 100.0 * double(index + 1) / total,
                     index + 1, total);
      }
    }
    if (!options.quiet && tty) std::fprintf(stderr, "\r%40s\r", "");
    video.release();
    polygons.close();
    writer->Close(simulation->truth());
  } catch (const std::exception& e) {
    std::cerr << "\nfreespace demo: " << e.what() << "\n";
    return kExitSetup;
  }

  ReportContext context;
  context.scenario = scenario.name;
  context.log = writer->log_path();
  context.truth = writer->truth_path();
  context.backend = estimator->backend_name();
  context.scans_read = long(simulation->truth().scans.size());
  context.rejected = rejected;
  const nlohmann::json report = QualityReport(context, metrics, times);
  try {
    WriteJson(options.out + "/eval.json", report);
  } catch (const std::exception& e) {
    std::cerr << "freespace demo: " << e.what() << "\n";
    return kExitSetup;
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - started).count();

  const nlohmann::json& stage = report.at("stage_us");
  auto ms = [&](const char* name) { return stage.at(name).at("median").get<double>() / 1000.0; };
  char line[320];
  std::cout << "freespace demo: simulated " << echoes.ToString() << "\n";
  std::snprintf(line, sizeof line,
                "freespace demo: median ms per scan: simulate %.2f | estimator %.3f (preprocess "
                "%.3f, align %.3f, rasterize %.3f, fuse %.3f, classify %.3f, insight %.3f, "
                "polygon %.3f) | score %.2f | render + video %.2f per frame\n",
                MedianMs(simulate_us), ms("total"), ms("preprocess"), ms("align"), ms("rasterize"),
                ms("fuse"), ms("classify"), ms("insight"), ms("polygon"), MedianMs(score_us),
                MedianMs(render_us));
  std::cout << line;
  std::cout << "freespace demo: quality over " << metrics.size() << " scans (docs/metrics.md):\n";
  PrintQuality(std::cout, report.at("summary"));
  std::cout << "freespace demo: wrote " << options.out << "/: sim.fslog, sim.clf, truth.json, "
            << "config.yaml, polygons.jsonl, eval.json, "
            << (frames > 0 ? "demo.avi (" + std::to_string(frames) + " frames), " : "") << snapshots
            << " snapshot PNG(s); " << seconds << " s in all\n";
  return kExitOk;
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
      "polygon with a one-cell margin, N = 128).");
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
  command->add_flag("--no-video", options->no_video, "Write no video");
  command->add_flag("--quiet", options->quiet, "No progress line");
  AddEngineOptions(command, &options->engine);
  return {command, [options] { return Demo(*options); }};
}

}  // namespace freespace::cli
