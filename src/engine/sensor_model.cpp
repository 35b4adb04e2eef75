// The enhanced inverse sensor model (paper II: the full-scan polygon rasterized once, each cell
// updated at most once per scan) and the conventional one (the paper's baseline: a Bresenham ray
// per kept echo, no virtual points), each followed by its fusion.
#include "sensor_model.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <chrono>

namespace freespace {
namespace {

using Clock = std::chrono::steady_clock;

double Micros(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

class EnhancedModel final : public SensorModel {
 public:
  void Project(Preprocessor* preprocess, const Vec2& sensor, double yaw, int width, int height,
               ScanProjection* out, bool faces) const override {
    out->raster = RasterJob{};
    preprocess->Project(sensor, yaw, width, height, &out->raster, faces);
  }

  void Apply(const ScanProjection& scan, Backend* backend, StageTimes* times) const override {
    const Clock::time_point start = Clock::now();
    backend->Rasterize(scan.raster);
    const Clock::time_point rastered = Clock::now();
    backend->Fuse(scan.raster.row_begin, scan.raster.row_end);
    times->rasterize_us += Micros(start, rastered);
    times->fuse_us += Micros(rastered, Clock::now());
  }
};

class ConventionalModel final : public SensorModel {
 public:
  void Project(Preprocessor* preprocess, const Vec2& sensor, double yaw, int width, int height,
               ScanProjection* out, bool /*faces: none drawn*/) const override {
    out->rays = RayJob{};
    preprocess->ProjectRays(sensor, yaw, width, height, &out->rays);
  }

  void Apply(const ScanProjection& scan, Backend* backend, StageTimes* times) const override {
    const Clock::time_point start = Clock::now();
    backend->CastRays(scan.rays);
    const Clock::time_point cast = Clock::now();
    backend->FuseRays(scan.rays.row_begin, scan.rays.row_end);
    times->rasterize_us += Micros(start, cast);
    times->fuse_us += Micros(cast, Clock::now());
  }
};

}  // namespace

void SensorModel::Update(Preprocessor* preprocess, const Vec2& sensor, double yaw, Backend* backend,
                         StageTimes* times, SideWork beside, bool parallel) const {
  const int width = backend->params().width, height = backend->params().height;
  const Clock::time_point start = Clock::now();
  ScanProjection scan;
  Project(preprocess, sensor, yaw, width, height, &scan, !parallel);
  if (!parallel) beside();
  const Clock::time_point projected = Clock::now();
  times->rasterize_us += Micros(start, projected);
  if (!parallel) {
    Apply(scan, backend, times);
    return;
  }
  double apply_us = 0.0;
  tbb::parallel_invoke([&] { beside(); },
                       [&] {
                         const Clock::time_point begin = Clock::now();
                         Apply(scan, backend, times);
                         apply_us = Micros(begin, Clock::now());
                       });
  times->rasterize_us += std::max(0.0, Micros(projected, Clock::now()) - apply_us);
}

std::unique_ptr<SensorModel> MakeSensorModel(const Config& config) {
  if (config.sensor_model.kind == SensorModelKind::kConventional) {
    return std::make_unique<ConventionalModel>();
  }
  return std::make_unique<EnhancedModel>();
}

}  // namespace freespace
