// Measurements for `freespace bench`.
#include "eval/bench_suite.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>

#include "core/preprocess.hpp"
#include "eval/reference_map.hpp"
#include "eval/scorer.hpp"
#include "freespace/baselines.hpp"
#include "freespace/estimator.hpp"
#include "host/host_backend.hpp"

namespace freespace {
namespace {

nlohmann::json StageJson(const StageSeries& s) {
  nlohmann::json out = s.Summary();
  return out;
}

}  // namespace

nlohmann::json PipelineRun::ToJson() const {
  const double mean = times.Mean("total");
  nlohmann::json out = {{"backend", backend},
                        {"scans", scans},
                        {"stage_us", StageJson(times)},
                        {"scans_per_s", mean > 0 ? 1e6 / mean : 0.0}};
  if (!opencl_wait.empty()) {
    out["opencl_wait"] = opencl_wait;
    out["opencl_spin_us"] = opencl_spin_us;
  }
  return out;
}

namespace {

PipelineRun StartRun(const Config& config, const Estimator& estimator) {
  PipelineRun run;
  run.backend = estimator.backend_name();
  if (run.backend.rfind("opencl", 0) == 0) {
    run.opencl_wait = ToString(config.backend.opencl_wait);
    run.opencl_spin_us = config.backend.opencl_spin_us;
  }
  return run;
}

}  // namespace

PipelineRun TimePipeline(const Config& config, const std::vector<Scan>& scans, int warmup) {
  return TimePipelinesInTurn({config}, scans, warmup).front();
}

std::vector<PipelineRun> TimePipelinesInTurn(const std::vector<Config>& configs,
                                             const std::vector<Scan>& scans, int warmup) {
  std::vector<std::unique_ptr<Estimator>> estimators;
  std::vector<PipelineRun> runs;
  for (const Config& config : configs) {
    estimators.push_back(std::make_unique<Estimator>(config));
    runs.push_back(StartRun(config, *estimators.back()));
  }
  for (const Scan& scan : scans) {
    for (std::size_t k = 0; k < estimators.size(); ++k) {
      const Result& r = estimators[k]->Process(scan);
      if (r.status == ScanStatus::kRejected) continue;
      if (runs[k].scans++ >= warmup) runs[k].times.Add(r.times);
    }
  }
  return runs;
}

PipelineRun TimeCycles(const Config& config, const std::vector<std::vector<Scan>>& cycles,
                       int warmup) {
  Estimator estimator(config);
  PipelineRun run = StartRun(config, estimator);
  for (const std::vector<Scan>& cycle : cycles) {
    const Result& r = estimator.ProcessCycle(cycle);
    if (r.status == ScanStatus::kRejected) continue;
    if (run.scans++ >= warmup) run.times.Add(r.times);
  }
  return run;
}

nlohmann::json FootprintStats::ToJson() const {
  return {{"holes", holes},
          {"moire", moire},
          {"conflicts", conflicts},
          {"conflicts_free", conflicts_free},
          {"mean_updates", mean_updates},
          {"max_updates", max_updates}};
}

nlohmann::json CoverageStats::ToJson() const {
  return {{"scans", scans},
          {"footprint_cells", footprint_cells},
          {"enhanced", enhanced.ToJson()},
          {"conventional", conventional.ToJson()}};
}

namespace {

// Accumulates one scan's footprint statistics of one model. `updates[i]`: updates cell i got
// in the scan (0: none).
class FootprintCounter {
 public:
  FootprintCounter(int width, int height, double resolution_rad)
      : width_(width), height_(height), resolution_rad_(resolution_rad) {}

  void Add(const std::vector<std::uint8_t>& footprint, const Vec2& sensor,
           const std::function<int(std::size_t)>& updates, FootprintStats* out) const {
    double holes = 0, moire = 0, updated = 0, sum = 0, max_updates = 0;
    for (int r = 0; r < height_; ++r) {
      for (int c = 0; c < width_; ++c) {
        const std::size_t i = std::size_t(r) * width_ + c;
        if (!footprint[i]) continue;
        const int n = updates(i);
        if (n > 0) {
          ++updated;
          sum += n;
          max_updates = std::max(max_updates, double(n));
          continue;
        }
        ++holes;
        moire += IsMoire(r, c, sensor, updates);
      }
    }
    out->holes += holes;
    out->moire += moire;
    out->mean_updates += updated > 0 ? sum / updated : 0.0;
    out->max_updates += max_updates;
  }

 private:
  // A hole with an updated cell on both sides along its arc about the sensor, within one beam
  // spacing of arc (at least one cell), sampled every cell of arc.
  bool IsMoire(int r, int c, const Vec2& sensor,
               const std::function<int(std::size_t)>& updates) const {
    const Vec2 d(c + 0.5 - sensor.x(), r + 0.5 - sensor.y());
    const double range = std::hypot(d.x(), d.y());
    if (range < 1.0) return false;
    const int steps = std::max(1, int(std::ceil(range * resolution_rad_)));
    for (const int side : {-1, 1}) {
      bool found = false;
      for (int j = 1; j <= steps && !found; ++j) {
        const double a = side * j / range, ca = std::cos(a), sa = std::sin(a);
        const int qc = int(std::floor(sensor.x() + ca * d.x() - sa * d.y()));
        const int qr = int(std::floor(sensor.y() + sa * d.x() + ca * d.y()));
        if (qc < 0 || qr < 0 || qc >= width_ || qr >= height_) break;
        found = updates(std::size_t(qr) * width_ + qc) > 0;
      }
      if (!found) return false;
    }
    return true;
  }

  int width_, height_;
  double resolution_rad_;
};

}  // namespace

CoverageStats SensorModelCoverage(const Config& config, const std::vector<Scan>& scans, int every) {
  const int width = config.map.width_cells, height = config.map.height_cells;
  const KernelParams params = MakeKernelParams(config);
  HostBackend backend(params, config.backend.threads);
  Preprocessor preprocess(config);
  const std::size_t cells = std::size_t(width) * height;
  std::vector<std::uint8_t> mask(cells), footprint(cells), row(width);
  std::vector<std::int32_t> free_counts(cells), occupied_counts(cells), vertices;
  const FootprintCounter counter(width, height, config.sensor.angular_resolution_deg * M_PI / 180);
  CoverageStats out;
  const Vec2 sensor(0.5 * width + 0.37, 0.5 * height + 0.21);  // off-centre of a cell
  for (std::size_t k = 0; k < scans.size(); k += std::max(1, every)) {
    ScanStats stats;
    if (!preprocess.Run(scans[k], &stats)) continue;
    RasterJob job;
    preprocess.Project(sensor, 0.0, width, height, &job);
    backend.Rasterize(job);
    backend.ReadUpdateMask(mask.data());
    // The footprint: the fan triangles between consecutive real returns, virtual ones left
    // out. Each run of real returns is a fan from the sensor; the runs are joined through the
    // sensor's vertex, so the even-odd fill is their union.
    vertices.clear();
    const auto& beams = preprocess.beams();
    for (std::size_t b = 0; b < beams.size(); ++b) {
      if (beams[b].is_virtual) continue;
      if (b == 0 || beams[b - 1].is_virtual) {
        vertices.push_back(job.vertices[0]);
        vertices.push_back(job.vertices[1]);
      }
      vertices.push_back(job.vertices[2 * (b + 1)]);
      vertices.push_back(job.vertices[2 * (b + 1) + 1]);
    }
    std::fill(footprint.begin(), footprint.end(), 0);
    for (int r = job.row_begin; r < job.row_end; ++r) {
      host::RasterizeRow(vertices.data(), int(vertices.size() / 2), width, r, row.data());
      std::copy(row.begin(), row.end(), footprint.begin() + std::size_t(r) * width);
    }
    for (int i = 0; i < job.occupied_count; ++i) footprint[job.occupied[i]] = 1;
    // Conventional: count the free and the occupied updates per cell apart.
    RayJob rays;
    preprocess.ProjectRays(sensor, 0.0, width, height, &rays);
    std::fill(free_counts.begin(), free_counts.end(), 0);
    std::fill(occupied_counts.begin(), occupied_counts.end(), 0);
    for (int i = 0; i < rays.ray_count; ++i) {
      const int ec = rays.ends[2 * i], er = rays.ends[2 * i + 1];
      host::AccumulateRay(free_counts.data(), width, height, rays.origin_col, rays.origin_row, ec,
                          er, 1, 0);
      host::AccumulateRay(occupied_counts.data(), width, height, rays.origin_col, rays.origin_row,
                          ec, er, 0, 1);
    }
    out.footprint_cells += double(std::count(footprint.begin(), footprint.end(), 1));
    counter.Add(
        footprint, sensor, [&](std::size_t i) { return mask[i] == kUpdateNone ? 0 : 1; },
        &out.enhanced);
    counter.Add(
        footprint, sensor, [&](std::size_t i) { return free_counts[i] + occupied_counts[i]; },
        &out.conventional);
    double conflicts = 0, conflicts_free = 0;
    for (std::size_t i = 0; i < cells; ++i) {
      if (free_counts[i] == 0 || occupied_counts[i] == 0) continue;
      ++conflicts;
      conflicts_free += std::int64_t(free_counts[i]) * params.l_free +
                            std::int64_t(occupied_counts[i]) * params.l_occupied <
                        0;
    }
    out.conventional.conflicts += conflicts;
    out.conventional.conflicts_free += conflicts_free;
    ++out.scans;
  }
  if (out.scans > 0) {
    const double n = out.scans;
    out.footprint_cells /= n;
    for (FootprintStats* s : {&out.enhanced, &out.conventional}) {
      s->holes /= n;
      s->moire /= n;
      s->conflicts /= n;
      s->conflicts_free /= n;
      s->mean_updates /= n;
      s->max_updates /= n;
    }
  }
  return out;
}

nlohmann::json TruthQuality::ToJson() const {
  return {{"scans", scans},
          {"accuracy", accuracy},
          {"accuracy_mean", accuracy_mean},
          {"observed_cells", observed_cells},
          {"false_free_rate", false_free_rate},
          {"false_occupied", false_occupied},
          {"coverage", coverage},
          {"summary", summary}};
}

TruthQuality ScoreAgainstTruth(const Config& config, const std::vector<Scan>& scans,
                               const sim::Truth& truth) {
  Estimator estimator(config);
  sim::TruthScorer scorer(truth);
  MetricsSeries series;
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const Result& r = estimator.Process(scans[k]);
    if (r.status == ScanStatus::kRejected) continue;
    series.Add(scorer.Score(k, estimator.map(), r));
  }
  TruthQuality out;
  double correct = 0, observed = 0, false_free = 0, occupied = 0, covered = 0, reference = 0;
  double accuracy_sum = 0, accuracy_n = 0;
  for (const ScanMetrics& m : series.scans()) {
    correct += double(m.correct);
    observed += double(m.observed);
    false_free += double(m.false_free);
    occupied += double(m.observed_occupied);
    covered += m.covered_free_m2;
    reference += m.reference_free_m2;
    out.false_occupied += double(m.false_occupied);
    if (std::isfinite(m.accuracy)) accuracy_sum += m.accuracy, ++accuracy_n;
  }
  out.scans = long(series.size());
  const double n = std::max<double>(1.0, double(series.size()));
  out.accuracy = observed > 0 ? correct / observed : NAN;
  out.accuracy_mean = accuracy_n > 0 ? accuracy_sum / accuracy_n : NAN;
  out.observed_cells = observed / n;
  out.false_free_rate = occupied > 0 ? false_free / occupied : NAN;
  out.false_occupied /= n;
  out.coverage = reference > 0 ? covered / reference : NAN;
  out.summary = series.Summary();
  return out;
}

std::vector<Scan> SimulateScans(const sim::SimulationOptions& options, int limit,
                                SensorConfig* sensor) {
  sim::Simulation simulation(options);
  *sensor = simulation.truth().scanner.EngineSensor();
  std::vector<Scan> scans;
  Scan scan;
  while ((limit <= 0 || int(scans.size()) < limit) && simulation.Next(&scan)) {
    scans.push_back(scan);
  }
  return scans;
}

double LogLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (!(x[i] > 0) || !(y[i] > 0)) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    n += 1, sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  const double den = n * sxx - sx * sx;
  if (n < 2 || !(std::abs(den) > 0)) return NAN;
  return (n * sxy - sx * sy) / den;
}

nlohmann::json AlignmentError::ToJson() const {
  return {{"cells_compared", cells_compared},
          {"different_fraction", different_fraction},
          {"class_mismatch", class_mismatch},
          {"mean_abs_probability", mean_abs_probability}};
}

AlignmentComparison CompareAlignment(const Config& config, const std::vector<Scan>& scans,
                                     int warmup) {
  Config circle = config, rotate = config;
  // The paper's alignments and its reference map place every point from the scan's one pose.
  circle.sensor.sweep_s = rotate.sensor.sweep_s = 0.0;
  circle.alignment.kind = AlignmentKind::kCircle;
  rotate.alignment.kind = AlignmentKind::kRotate;
  RegisterBaselines();
  circle.backend.kind = rotate.backend.kind = BackendKind::kTbb;
  Estimator a(circle), b(rotate);
  ReferenceMap reference(circle);
  AlignmentComparison out;
  out.circle.backend = a.backend_name();
  out.rotate.backend = b.backend_name();
  int n = 0;
  auto add = [](AlignmentError* e, const MapDifference& d) {
    e->cells_compared += double(d.compared);
    if (d.compared > 0) {
      e->different_fraction += double(d.different) / double(d.compared);
      e->class_mismatch += double(d.class_mismatch) / double(d.compared);
      e->mean_abs_probability += d.mean_abs_probability;
    }
  };
  for (const Scan& scan : scans) {
    const Result& ra = a.Process(scan);
    reference.Update(scan, ra);
    if (ra.status == ScanStatus::kRejected) continue;
    if (out.circle.scans++ >= warmup) out.circle.times.Add(ra.times);
    add(&out.circle_error, reference.CompareCircle(a.map(), ra));
    const Result& rb = b.Process(scan);
    if (out.rotate.scans++ >= warmup) out.rotate.times.Add(rb.times);
    add(&out.rotate_error, reference.CompareRotated(b.map(), rb));
    ++n;
  }
  for (AlignmentError* e : {&out.circle_error, &out.rotate_error}) {
    if (n == 0) break;
    e->cells_compared /= n;
    e->different_fraction /= n;
    e->class_mismatch /= n;
    e->mean_abs_probability /= n;
  }
  return out;
}

}  // namespace freespace
