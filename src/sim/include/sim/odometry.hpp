// Odometry as the vehicle reports it: the true motion between two scans, distorted by a
// wheel-speed scale error, speed noise, a yaw-rate bias and yaw-rate noise, integrated from
// the true start pose. With every error zero the odometry is the truth, bit for bit.
#pragma once

#include <string>

#include "freespace/types.hpp"
#include "sim/random.hpp"

namespace freespace::sim {

struct OdometryNoise {
  double speed_scale_error = 0.0;   // relative error of the travelled distance (0.01 = +1 %)
  double speed_sigma_mps = 0.0;     // white noise on the speed, per scan
  double yaw_rate_bias_dps = 0.0;   // constant yaw-rate bias, deg/s
  double yaw_rate_sigma_dps = 0.0;  // white noise on the yaw rate, per scan, deg/s

  bool none() const {
    return speed_scale_error == 0.0 && speed_sigma_mps == 0.0 && yaw_rate_bias_dps == 0.0 &&
           yaw_rate_sigma_dps == 0.0;
  }
  // "none", "typical" (a production car's ESP odometry: 0.5 % scale, 0.1 deg/s bias) or "poor"
  // (2 %, 0.5 deg/s). Throws std::invalid_argument for other names.
  static OdometryNoise Preset(const std::string& name);
};

class Odometry {
 public:
  Odometry(const OdometryNoise& noise, std::uint64_t seed)
      : noise_(noise), rng_(seed, kStreamOdometry) {}

  // The odometry pose for the true pose `truth` at time t; the first call returns `truth`.
  Pose2D Update(double t, const Pose2D& truth);

 private:
  OdometryNoise noise_;
  Rng rng_;
  bool started_ = false;
  double last_t_ = 0.0;
  Pose2D last_truth_;
  Pose2D pose_;
};

}  // namespace freespace::sim
