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

class SensorModel {
 public:
  virtual ~SensorModel() = default;

  // Writes the scan that `preprocess` holds into the map of `backend`, the sensor at `sensor`
  // (map cells) heading `yaw` (radians, map frame); sets times->rasterize_us and fuse_us.
  virtual void Update(Preprocessor* preprocess, const Vec2& sensor, double yaw, Backend* backend,
                      StageTimes* times) = 0;
};

std::unique_ptr<SensorModel> MakeSensorModel(const Config& config);

}  // namespace freespace
