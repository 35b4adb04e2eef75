// The inverse sensor model and the fusion (kernel stages 1 and 2), one implementation per
// sensor_model.kind, chosen once when the estimator is built: the paper's enhanced full-scan
// polygon, or its baseline of one ray per echo.
#pragma once

#include <memory>

#include "core/backend.hpp"
#include "core/preprocess.hpp"
#include "freespace/config.hpp"
#include "freespace/result.hpp"

namespace freespace {

// One scan's projection into the map: what the model's kernels read, pointing into the
// preprocessor's buffers (valid until that preprocessor runs or projects again).
struct ScanProjection {
  RasterJob raster;  // the enhanced model's
  RayJob rays;       // the conventional model's
};

// Host work that runs beside the map's update: a call to a callable the caller keeps alive,
// made without copying it (no allocation per scan).
class SideWork {
 public:
  SideWork() = default;
  template <typename F>
  explicit SideWork(const F* work)
      : work_(work), call_([](const void* w) { (*static_cast<const F*>(w))(); }) {}
  void operator()() const {
    if (call_ != nullptr) call_(work_);
  }

 private:
  const void* work_ = nullptr;
  void (*call_)(const void*) = nullptr;
};

class SensorModel {
 public:
  virtual ~SensorModel() = default;

  // Projects the scan that `preprocess` holds into a map of width x height cells, the sensor at
  // `sensor` (map cells) heading `yaw` (radians, map frame); with `faces` false the face layer
  // is left to Preprocessor::ProjectFaces(). Host only and touches nothing but `preprocess` and
  // `out`: several sensors' scans may be projected at once.
  virtual void Project(Preprocessor* preprocess, const Vec2& sensor, double yaw, int width,
                       int height, ScanProjection* out, bool faces) const = 0;

  // Writes a projected scan into the map of `backend` (rasterization and fusion); adds to
  // times->rasterize_us and fuse_us.
  virtual void Apply(const ScanProjection& scan, Backend* backend, StageTimes* times) const = 0;

  // Project() then Apply(), the projection's time counted in times->rasterize_us; `beside`
  // (host work that reads the scan and writes neither the preprocessor nor the backend) runs
  // too. With `parallel` it runs beside both, times->rasterize_us takes what it adds to their
  // time, and the face layer is left to Preprocessor::ProjectFaces(); else in turn, the face
  // layer projected with the scan, all counted.
  void Update(Preprocessor* preprocess, const Vec2& sensor, double yaw, Backend* backend,
              StageTimes* times, SideWork beside = SideWork(), bool parallel = false) const;
};

std::unique_ptr<SensorModel> MakeSensorModel(const Config& config);

}  // namespace freespace
