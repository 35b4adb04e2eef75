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
  if (!parallel) {
    Project(preprocess, sensor, yaw, width, height, &scan, true);
    beside();
    times->rasterize_us += Micros(start, Clock::now());
    Apply(scan, backend, times);
    return;
  }
  // The side work from the start: the projection, one thread's work, leaves a core to it.
  double own_us = 0.0;  // the projection's and Apply()'s time on their branch
  tbb::parallel_invoke([&] { beside(); },
                       [&] {
                         const Clock::time_point begin = Clock::now();
                         Project(preprocess, sensor, yaw, width, height, &scan, false);
                         times->rasterize_us += Micros(begin, Clock::now());
                         Apply(scan, backend, times);
                         own_us = Micros(begin, Clock::now());
                       });
  times->rasterize_us += std::max(0.0, Micros(start, Clock::now()) - own_us);
}

std::unique_ptr<SensorModel> MakeSensorModel(const Config& config) {
  if (config.sensor_model.kind == SensorModelKind::kConventional) {
    return std::make_unique<ConventionalModel>();
  }
  return std::make_unique<EnhancedModel>();
}

}  // namespace freespace
