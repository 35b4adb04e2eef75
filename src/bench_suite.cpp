// Measurements for `freespace bench`.
#include "bench_suite.hpp"

#include <algorithm>
#include <cmath>

#include "freespace/estimator.hpp"
#include "host_backend.hpp"
#include "preprocess.hpp"
#include "reference_map.hpp"

namespace freespace {
namespace {

nlohmann::json StageJson(const StageSeries& s) {
  nlohmann::json out = s.Summary();
  return out;
}

}  // namespace

nlohmann::json PipelineRun::ToJson() const {
  const double mean = times.Mean("total");
  return {{"backend", backend},
          {"scans", scans},
          {"stage_us", StageJson(times)},
          {"scans_per_s", mean > 0 ? 1e6 / mean : 0.0}};
}

PipelineRun TimePipeline(const Config& config, const std::vector<Scan>& scans, int warmup) {
  Estimator estimator(config);
  PipelineRun run;
  run.backend = estimator.backend_name();
  for (const Scan& scan : scans) {
    const Result& r = estimator.Process(scan);
    if (r.status == ScanStatus::kRejected) continue;
    if (run.scans++ >= warmup) run.times.Add(r.times);
  }
  return run;
}

nlohmann::json CoverageStats::ToJson() const {
  return {{"footprint_cells", footprint_cells},
          {"enhanced_holes", enhanced_holes},
          {"conventional_holes", conventional_holes},
          {"conventional_mean_updates", conventional_mean_updates},
          {"conventional_max_updates", conventional_max_updates}};
}

CoverageStats SensorModelCoverage(const Config& config, const std::vector<Scan>& scans, int every) {
  const int width = config.map.width_cells, height = config.map.height_cells;
  const KernelParams params = MakeKernelParams(config);
  HostBackend backend(params, config.backend.threads);
  Preprocessor preprocess(config);
  const std::size_t cells = std::size_t(width) * height;
  std::vector<std::uint8_t> mask(cells), footprint(cells), row(width);
  std::vector<std::int32_t> counts(cells), vertices;
  CoverageStats out;
  int n = 0;
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
    // Conventional: count the updates per cell.
    RayJob rays;
    preprocess.ProjectRays(sensor, 0.0, width, height, &rays);
    std::fill(counts.begin(), counts.end(), 0);
    for (int i = 0; i < rays.ray_count; ++i) {
      host::AccumulateRay(counts.data(), width, height, rays.origin_col, rays.origin_row,
                          rays.ends[2 * i], rays.ends[2 * i + 1], 1, 1);
    }
    double fp = 0, enhanced_holes = 0, conventional_holes = 0, updated = 0, updates = 0;
    double max_updates = 0;
    for (std::size_t i = 0; i < cells; ++i) {
      if (!footprint[i]) continue;
      ++fp;
      enhanced_holes += mask[i] == kUpdateNone;
      if (counts[i] == 0) {
        ++conventional_holes;
      } else {
        ++updated;
        updates += counts[i];
        max_updates = std::max(max_updates, double(counts[i]));
      }
    }
    out.footprint_cells += fp;
    out.enhanced_holes += enhanced_holes;
    out.conventional_holes += conventional_holes;
    out.conventional_mean_updates += updated > 0 ? updates / updated : 0.0;
    out.conventional_max_updates += max_updates;
    ++n;
  }
  if (n > 0) {
    out.footprint_cells /= n;
    out.enhanced_holes /= n;
    out.conventional_holes /= n;
    out.conventional_mean_updates /= n;
    out.conventional_max_updates /= n;
  }
  return out;
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
  circle.alignment.kind = AlignmentKind::kCircle;
  rotate.alignment.kind = AlignmentKind::kRotate;
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
