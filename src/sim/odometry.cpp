// Odometry errors: see odometry.hpp.
#include "sim/odometry.hpp"

#include <cmath>
#include <stdexcept>

#include "geometry/geometry.hpp"

namespace freespace::sim {

OdometryNoise OdometryNoise::Preset(const std::string& name) {
  OdometryNoise n;
  if (name == "none") return n;
  if (name == "typical") {
    n.speed_scale_error = 0.005;
    n.speed_sigma_mps = 0.02;
    n.yaw_rate_bias_dps = 0.1;
    n.yaw_rate_sigma_dps = 0.05;
    return n;
  }
  if (name == "poor") {
    n.speed_scale_error = 0.02;
    n.speed_sigma_mps = 0.1;
    n.yaw_rate_bias_dps = 0.5;
    n.yaw_rate_sigma_dps = 0.2;
    return n;
  }
  throw std::invalid_argument("odometry noise '" + name + "': expected none, typical or poor");
}

Pose2D Odometry::Update(double t, const Pose2D& truth) {
  if (!started_) {
    started_ = true;
    last_t_ = t;
    last_truth_ = pose_ = truth;
    return pose_;
  }
  if (noise_.none()) {
    last_t_ = t;
    last_truth_ = pose_ = truth;
    return pose_;
  }
  const double dt = t - last_t_;
  // The true motion in the previous vehicle frame, distorted as wheel speed and yaw rate are.
  const Pose2D step = geometry::Compose(geometry::Inverse(last_truth_), truth);
  const double distance = std::hypot(step.x, step.y);
  const double noisy =
      distance * (1.0 + noise_.speed_scale_error) + noise_.speed_sigma_mps * dt * rng_.Normal();
  const double scale = distance > 0.0 ? noisy / distance : 0.0;
  const double dyaw = step.yaw + (noise_.yaw_rate_bias_dps * M_PI / 180.0) * dt +
                      (noise_.yaw_rate_sigma_dps * M_PI / 180.0) * dt * rng_.Normal();
  pose_ = geometry::Compose(pose_, Pose2D{step.x * scale, step.y * scale, dyaw});
  last_t_ = t;
  last_truth_ = truth;
  return pose_;
}

}  // namespace freespace::sim
