// The rotated, vehicle-centred map of the paper's baseline alignment: OpenCV's warpAffine with
// bilinear interpolation resamples the whole map every scan.
#include "baselines/map_warper.hpp"

#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>

namespace freespace {

MapWarper::MapWarper(const Config& config)
    : width_(config.map.width_cells),
      height_(config.map.height_cells),
      resolution_(config.map.resolution_m),
      centre_(0.5 * config.map.width_cells, 0.5 * config.map.height_cells),
      source_(config.map.height_cells, config.map.width_cells, CV_16SC1),
      target_(config.map.height_cells, config.map.width_cells, CV_16SC1) {}

void MapWarper::Warp(const Pose2D& before, const Pose2D& now, LogOdds* map) {
  // A cell p' of the new map shows the world point now + R(yaw_now) (p' - C) res, which the
  // old map held at p = C + R(-yaw_before) (world - before) / res. So p = A p' + b with
  // A = R(yaw_now - yaw_before), b = C + R(-yaw_before) (now - before) / res - A C.
  const double turn = now.yaw - before.yaw;
  const double ca = std::cos(turn), sa = std::sin(turn);
  const double cb = std::cos(before.yaw), sb = std::sin(before.yaw);
  const double mx = (now.x - before.x) / resolution_, my = (now.y - before.y) / resolution_;
  const Vec2 moved(cb * mx + sb * my, -sb * mx + cb * my);
  const double cx = centre_.x(), cy = centre_.y();
  double bx = cx + moved.x() - (ca * cx - sa * cy);
  double by = cy + moved.y() - (sa * cx + ca * cy);
  // OpenCV puts pixel centres at integers, this map at +0.5: p_cv = A p'_cv + b + A h - h.
  bx += 0.5 * (ca - sa) - 0.5;
  by += 0.5 * (sa + ca) - 0.5;
  const cv::Matx23d inverse(ca, -sa, bx, sa, ca, by);  // maps target pixels to source pixels
  std::memcpy(source_.data, map, std::size_t(width_) * height_ * sizeof(LogOdds));
  cv::warpAffine(source_, target_, inverse, target_.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_CONSTANT, cv::Scalar(0));
  std::memcpy(map, target_.data, std::size_t(width_) * height_ * sizeof(LogOdds));
}

}  // namespace freespace
