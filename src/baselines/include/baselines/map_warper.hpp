// The paper's baseline alignment (alignment.kind rotate), which needs OpenCV and so lives apart
// from the engine: the warp of a vehicle-centred map, and the aligner that uses it.
#pragma once

#include <opencv2/core.hpp>

#include "freespace/config.hpp"
#include "freespace/types.hpp"

namespace freespace {

// The conventional alignment, kept as the paper's baseline (alignment.kind: rotate): a map
// centred on the vehicle and turning with it (the vehicle at the centre, heading along +x),
// resampled every scan by the vehicle's motion with bilinear interpolation (OpenCV
// warpAffine): the rotation and sub-pixel shift whose cost and blur the circle avoids.
class MapWarper {
 public:
  explicit MapWarper(const Config& config);

  // Resamples `map` (width x height, row 0 south) from the frame of the sensor pose `before`
  // to that of `now`. Cells with no source are unknown.
  void Warp(const Pose2D& before, const Pose2D& now, LogOdds* map);

  // The vehicle's place in the map: the centre, in cells.
  Vec2 centre() const { return centre_; }

 private:
  int width_, height_;
  double resolution_;
  Vec2 centre_;
  cv::Mat source_;
  cv::Mat target_;
};

}  // namespace freespace
