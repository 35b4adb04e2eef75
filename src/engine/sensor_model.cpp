// The enhanced inverse sensor model (paper II: the full-scan polygon rasterized once, each cell
// updated at most once per scan) and the conventional one (the paper's baseline: a Bresenham ray
// per kept echo, no virtual points), each followed by its fusion.
#include "sensor_model.hpp"

#include <chrono>

namespace freespace {
namespace {

using Clock = std::chrono::steady_clock;

double Micros(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

class EnhancedModel final : public SensorModel {
 public:
  void Update(Preprocessor* preprocess, const Vec2& sensor, double yaw, Backend* backend,
              StageTimes* times) override {
    const Clock::time_point start = Clock::now();
    RasterJob job;
    preprocess->Project(sensor, yaw, backend->params().width, backend->params().height, &job);
    backend->Rasterize(job);
    const Clock::time_point rastered = Clock::now();
    backend->Fuse(job.row_begin, job.row_end);
    times->rasterize_us = Micros(start, rastered);
    times->fuse_us = Micros(rastered, Clock::now());
  }
};

class ConventionalModel final : public SensorModel {
 public:
  void Update(Preprocessor* preprocess, const Vec2& sensor, double yaw, Backend* backend,
              StageTimes* times) override {
    const Clock::time_point start = Clock::now();
    RayJob job;
    preprocess->ProjectRays(sensor, yaw, backend->params().width, backend->params().height, &job);
    backend->CastRays(job);
    const Clock::time_point cast = Clock::now();
    backend->FuseRays(job.row_begin, job.row_end);
    times->rasterize_us = Micros(start, cast);
    times->fuse_us = Micros(cast, Clock::now());
  }
};

}  // namespace

std::unique_ptr<SensorModel> MakeSensorModel(const Config& config) {
  if (config.sensor_model.kind == SensorModelKind::kConventional) {
    return std::make_unique<ConventionalModel>();
  }
  return std::make_unique<EnhancedModel>();
}

}  // namespace freespace
