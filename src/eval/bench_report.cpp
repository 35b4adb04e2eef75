// The measurements of `freespace bench`, taken into a BenchReport: see bench_report.hpp.
#include "eval/bench_report.hpp"

#include <algorithm>
#include <cstdio>

#include "freespace/errors.hpp"
#include "freespace/io.hpp"

namespace freespace {
namespace {

double MeanPoints(const std::vector<Scan>& scans) {
  double sum = 0;
  for (const Scan& s : scans) sum += double(s.points.size());
  return scans.empty() ? 0.0 : sum / double(scans.size());
}

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
// How much less time `a` takes than `b`, in percent of `b`.
double SavedPercent(double a, double b) { return 100.0 * (1.0 - Ratio(a, b)); }

void Progress(const BenchOptions& options, const std::string& step) {
  if (options.progress) options.progress(step);
}

// The pipeline per backend; an unavailable backend is noted, not thrown.
std::vector<BackendPipeline> TimeBackends(const Config& config, const std::vector<Scan>& scans,
                                          const BenchOptions& options) {
  std::vector<BackendPipeline> out;
  for (const BackendKind kind : options.backends) {
    Config c = config;
    c.backend.kind = kind;
    Progress(options, std::string("pipeline on ") + ToString(kind));
    BackendPipeline pipeline;
    pipeline.kind = kind;
    try {
      pipeline.run = TimePipeline(c, scans, options.warmup);
    } catch (const BackendError& e) {
      pipeline.error = e.what();
      if (options.unavailable) options.unavailable(ToString(kind), e.what());
    }
    out.push_back(pipeline);
  }
  return out;
}

// Enhanced vs conventional inverse sensor model, same scans in turn, same backend (TBB); against
// the truth on a simulated drive.
void CompareSensorModels(const Config& config, const BenchSource& source,
                         const BenchOptions& options, BenchReport* report) {
  Progress(options, "enhanced vs conventional inverse sensor model");
  Config enhanced = config, conventional = config;
  enhanced.backend.kind = conventional.backend.kind = BackendKind::kTbb;
  enhanced.sensor_model.kind = SensorModelKind::kEnhanced;
  conventional.sensor_model.kind = SensorModelKind::kConventional;
  // The paper's two models as the paper has them: the enhanced one updates free every cell
  // whose centre its polygon covers (the conventional one draws no outline, so neither has the
  // face layer), and every point is placed from the scan's one pose.
  enhanced.sensor_model.free_on_outline = conventional.sensor_model.free_on_outline = true;
  enhanced.polygon.face_tolerance_m = conventional.polygon.face_tolerance_m = 0.0;
  enhanced.sensor.sweep_s = conventional.sensor.sweep_s = 0.0;
  std::vector<PipelineRun> runs =
      TimePipelinesInTurn({enhanced, conventional}, source.scans, options.warmup);
  report->enhanced = std::move(runs[0]);
  report->conventional = std::move(runs[1]);
  report->coverage = SensorModelCoverage(enhanced, source.scans, 5);
  if (source.truth != nullptr) {
    Progress(options, "enhanced vs conventional against the truth");
    report->enhanced_quality = ScoreAgainstTruth(enhanced, source.scans, *source.truth);
    report->conventional_quality = ScoreAgainstTruth(conventional, source.scans, *source.truth);
  }
}

// The paper's polygon against the conservative one, same scans in turn, TBB (issue 21's aims: the
// conservative polygon stage at most 3 times the paper's, the pipeline at most 1.3 times).
void ComparePolygonShapes(const Config& config, const BenchSource& source,
                          const BenchOptions& options, BenchReport* report) {
  Progress(options, "paper vs conservative polygon");
  Config paper = config, inside = config;
  paper.backend.kind = inside.backend.kind = BackendKind::kTbb;
  paper.polygon.shape = PolygonShape::kPaper;
  paper.polygon.margin_cells = 0;
  paper.polygon.face_tolerance_m = 0.0;
  paper.polygon.mover_memory_s = 0.0;
  inside.polygon.shape = PolygonShape::kInside;
  if (config.polygon.shape != PolygonShape::kInside) {
    inside.polygon.margin_cells = 1;
    inside.polygon.margin_cone_deg = 10.0;
    inside.polygon.face_tolerance_m = 0.05;
    inside.polygon.mover_memory_s = 3.0;
  }
  std::vector<PipelineRun> runs =
      TimePipelinesInTurn({paper, inside}, source.scans, options.warmup);
  report->paper_shape = std::move(runs[0]);
  report->inside_shape = std::move(runs[1]);
}

// The exponent of time against x per series, over all points and over x >= from.
std::map<std::string, ScaleExponent> Exponents(const std::vector<ScaleSeries>& series,
                                               double from) {
  std::map<std::string, ScaleExponent> out;
  for (const ScaleSeries& s : series) {
    std::vector<double> x, y;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (s.x[i] >= from) x.push_back(s.x[i]), y.push_back(s.y[i]);
    }
    out[s.name] = {LogLogSlope(s.x, s.y), LogLogSlope(x, y)};
  }
  return out;
}

// Total time against map size, per backend that ran.
void ScaleMapSize(const Config& config, const std::vector<Scan>& scans, int warmup,
                  const BenchReport& report, const BenchOptions& options, ScalingResults* out) {
  for (const BackendPipeline* pipeline : report.Ran()) {
    const BackendKind kind = pipeline->kind;
    for (const int cells : kMapSizes) {
      Config c = config;
      c.backend.kind = kind;
      c.map.width_cells = c.map.height_cells = cells;
      Progress(options, std::string("map scaling ") + ToString(kind) + " " + std::to_string(cells));
      const PipelineRun r = TimePipeline(c, scans, warmup);
      ScalePoint point{ToString(kind), "enhanced", double(cells) * cells};
      point.cells = cells;
      point.total_us = TotalUs(r);
      point.model_us = ModelUs(r);
      out->map.push_back(point);
    }
  }
  out->map_exponent = Exponents(GroupScalePoints(out->map, false), 600.0 * 600.0);
}

// Total time against points per scan, per backend that ran and sensor model, on a simulated
// drive of as many scans as `scan_count`.
void ScalePointsPerScan(const Config& config, std::size_t scan_count, int warmup,
                        const BenchReport& report, const BenchOptions& options,
                        ScalingResults* out) {
  sim::SimulationOptions sweep = options.sweep;
  out->points_scenario = sweep.scenario;
  for (const int beams : kSweepBeams) {
    sweep.scanner.resolution_deg =
        (sweep.scanner.max_angle_deg - sweep.scanner.min_angle_deg) / (beams - 1);
    Progress(options, "points scaling: simulating " + std::to_string(beams * sweep.scanner.layers) +
                          " points a scan");
    SensorConfig sensor;
    const std::vector<Scan> sweep_run = SimulateScans(sweep, int(scan_count), &sensor);
    const double points = MeanPoints(sweep_run);
    for (const BackendPipeline* pipeline : report.Ran()) {
      for (const SensorModelKind model :
           {SensorModelKind::kEnhanced, SensorModelKind::kConventional}) {
        Config c = config;
        c.sensor = sensor;
        c.backend.kind = pipeline->kind;
        c.sensor_model.kind = model;
        c.sensor_model.free_on_outline =
            config.sensor_model.free_on_outline || model == SensorModelKind::kConventional;
        if (model == SensorModelKind::kConventional)
          c.polygon.face_tolerance_m = 0.0;  // no outline
        const PipelineRun r = TimePipeline(c, sweep_run, warmup);
        out->points.push_back({ToString(pipeline->kind), ToString(model), points, 0,
                               sensor.angular_resolution_deg, TotalUs(r), ModelUs(r)});
      }
    }
  }
  out->points_exponent = Exponents(GroupScalePoints(out->points, true), 2000.0);
}

// Scaling: total time against map size, per backend; against points per scan, per backend and
// sensor model, on a simulated drive. Each run takes at most kScalingScans scans.
ScalingResults MeasureScaling(const Config& config, const std::vector<Scan>& scans,
                              const BenchReport& report, const BenchOptions& options) {
  const std::vector<Scan> subset(
      scans.begin(), scans.begin() + std::min<std::size_t>(scans.size(), kScalingScans));
  const int warmup = std::min(options.warmup, 10);
  ScalingResults out;
  ScaleMapSize(config, subset, warmup, report, options, &out);
  ScalePointsPerScan(config, subset.size(), warmup, report, options, &out);
  return out;
}

// The paper's comparisons (docs/bench.md, "comparisons").
BenchComparisons Compare(const BenchReport& report) {
  BenchComparisons out;
  const PipelineRun &e = report.enhanced, &c = report.conventional;
  out.enhanced_model_speedup = Ratio(ModelUs(c), ModelUs(e));
  out.enhanced_map_speedup = Ratio(MapUs(c), MapUs(e));
  out.enhanced_total_speedup = Ratio(TotalUs(c), TotalUs(e));
  out.enhanced_time_saved_percent = SavedPercent(TotalUs(e), TotalUs(c));
  out.enhanced_map_time_saved_percent = SavedPercent(MapUs(e), MapUs(c));
  const AlignmentComparison& a = report.alignment;
  out.circle_time_saved_percent = SavedPercent(TotalUs(a.circle), TotalUs(a.rotate));
  out.circle_map_time_saved_percent = SavedPercent(MapUs(a.circle), MapUs(a.rotate));
  out.circle_different_fraction = a.circle_error.different_fraction;
  out.rotate_different_fraction = a.rotate_error.different_fraction;
  const std::vector<const BackendPipeline*> ran = report.Ran();
  if (ran.size() == 2) {
    out.opencl_over_tbb_total = Ratio(TotalUs(ran[1]->run), TotalUs(ran[0]->run));
  }
  return out;
}

}  // namespace

std::string BenchSource::Describe() const {
  return scenario.empty() ? log : "scenario " + scenario + " (seed " + std::to_string(seed) + ")";
}

BenchSource LogBenchSource(const std::string& path, int limit, SensorConfig* sensor) {
  auto reader = OpenLog(path);
  *sensor = reader->sensor();
  BenchSource source;
  source.log = path;
  std::vector<Scan>& scans = source.scans;
  Scan scan;
  while ((limit <= 0 || int(scans.size()) < limit) && reader->Next(&scan)) scans.push_back(scan);
  if (scans.size() == 1) {
    const Scan frame = scans[0];
    for (int k = 1; k < std::max(limit, 200); ++k) {
      scans.push_back(frame);
      scans.back().timestamp_s = frame.timestamp_s + 0.04 * k;
    }
  }
  return source;
}

BenchSource DriveBenchSource(sim::Simulation& simulation, const std::string& scenario,
                             std::uint64_t seed, int limit, SensorConfig* sensor) {
  BenchSource source;
  source.scenario = scenario;
  source.seed = seed;
  source.truth = &simulation.truth();
  *sensor = simulation.truth().scanner.EngineSensor();
  Scan scan;
  while ((limit <= 0 || int(source.scans.size()) < limit) && simulation.Next(&scan)) {
    source.scans.push_back(scan);
  }
  return source;
}

std::vector<ScaleSeries> GroupScalePoints(const std::vector<ScalePoint>& points, bool by_model) {
  std::vector<ScaleSeries> out;
  for (const ScalePoint& p : points) {
    const std::string name = by_model ? p.backend + " " + p.sensor_model : p.backend;
    auto it = std::find_if(out.begin(), out.end(), [&](auto& s) { return s.name == name; });
    if (it == out.end()) it = out.insert(out.end(), ScaleSeries{name, {}, {}});
    it->x.push_back(p.x);
    it->y.push_back(p.total_us);
  }
  return out;
}

std::vector<const BackendPipeline*> BenchReport::Ran() const {
  std::vector<const BackendPipeline*> out;
  for (const BackendPipeline& p : pipelines) {
    if (p.error.empty()) out.push_back(&p);
  }
  return out;
}

double ModelUs(const PipelineRun& r) {
  return r.times.Quantile("rasterize", 0.5) + r.times.Quantile("fuse", 0.5);
}
double MapUs(const PipelineRun& r) {
  return r.times.Quantile("preprocess", 0.5) + r.times.Quantile("align", 0.5) + ModelUs(r);
}
double TotalUs(const PipelineRun& r) { return r.times.Quantile("total", 0.5); }

BenchReport RunBenchSuite(const Config& config, const BenchSource& source,
                          const BenchOptions& options) {
  BenchReport report;
  report.source = {source.log, source.scenario, source.seed, nullptr, {}};
  report.scans = source.scans.size();
  report.warmup = options.warmup;
  report.points_per_scan = MeanPoints(source.scans);
  report.map_width = config.map.width_cells;
  report.map_height = config.map.height_cells;
  report.resolution_m = config.map.resolution_m;
  report.load_before = LoadAverage();

  report.pipelines = TimeBackends(config, source.scans, options);
  CompareSensorModels(config, source, options, &report);
  ComparePolygonShapes(config, source, options, &report);
  // Vehicle on a circle vs a rotated, sub-pixel shifted map, against the reference map.
  Progress(options, "circle vs rotate alignment");
  report.alignment = CompareAlignment(config, source.scans, options.warmup);
  if (options.scaling) report.scaling = MeasureScaling(config, source.scans, report, options);
  report.comparisons = Compare(report);
  report.load_after = LoadAverage();
  return report;
}

}  // namespace freespace
