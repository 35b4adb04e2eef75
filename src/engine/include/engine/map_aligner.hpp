// How the estimator keeps its map aligned with the vehicle (alignment.kind), one interface with
// an implementation per kind, chosen once when the estimator is built. The circle (paper III) is
// built in; the rotated map, the paper's baseline, needs OpenCV and registers itself from the
// baselines library (freespace/baselines.hpp), so that the engine itself does not link OpenCV.
#pragma once

#include <memory>

#include "core/alignment.hpp"
#include "core/backend.hpp"
#include "freespace/config.hpp"
#include "freespace/result.hpp"

namespace freespace {

class MapAligner {
 public:
  virtual ~MapAligner() = default;

  // Moves the map held by `backend` for the accepted step `step` of `circle` (the sensor having
  // moved from the pose `before` to `now`) and writes where the map and the sensor now are into
  // `r`: origin, map_yaw, vehicle_cells, yaw and the circle. When the step resets the map, the
  // map has been cleared already and is not moved.
  virtual void Apply(const AlignStep& step, const CircleAligner& circle, const Pose2D& before,
                     const Pose2D& now, Backend* backend, Result* r) = 0;
};

using MapAlignerFactory = std::unique_ptr<MapAligner> (*)(const Config& config);

// Makes `factory` the one that builds the aligner of `kind`. Thread-safe.
void RegisterMapAligner(AlignmentKind kind, MapAlignerFactory factory);

// The aligner of config.alignment.kind. Throws ConfigError when that kind is not registered.
std::unique_ptr<MapAligner> MakeMapAligner(const Config& config);

}  // namespace freespace
