// alignment.scan_match: the odometry's heading corrected by matching each scan to the map
// (core/scan_match.hpp; docs/design.md, "Heading correction").
#include <algorithm>
#include <chrono>
#include <cmath>

#include "estimator_impl.hpp"

namespace freespace {
namespace {

// The largest rotation one match finds: 0.2 degrees (a scan takes a share of it).
constexpr double kMaxStepRad = 0.2 * M_PI / 180.0;

Pose2D Compose(const Pose2D& a, const Pose2D& b) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, WrapAngle(a.yaw + b.yaw)};
}

Pose2D Inverse(const Pose2D& a) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {-(c * a.x + s * a.y), s * a.x - c * a.y, WrapAngle(-a.yaw)};
}

// The rotation by `angle` about the point `centre` (world).
Pose2D RotationAbout(const Vec2& centre, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {centre.x() - (c * centre.x() - s * centre.y()),
          centre.y() - (s * centre.x() + c * centre.y()), angle};
}

}  // namespace

ScanMatcher Estimator::Impl::MakeMatcher(const Config& config) {
  return ScanMatcher(kMaxStepRad, LogOddsFromProbability(config.sensor_model.p_max));
}

Pose2D Estimator::Impl::Corrected(const Pose2D& odometry) const {
  return config_.alignment.scan_match ? Compose(correction_, odometry) : odometry;
}

// After Align() and Sweep(), before the map's update: the scan's kept echoes (deskewed) matched
// against the map of the scans before it, in its aligned frame; the sensor's yaw in the world
// and in the map turned by the share of the match that the heading filter gives (HeadingFilter),
// and the correction kept for the next scan. A cleared map starts a heading that is exact by
// definition.
void Estimator::Impl::MatchPose(bool has_update) {
  Result& r = result_;
  if (!config_.alignment.scan_match) return;
  if (r.map_reset || !map_has_scans_) {
    heading_.Reset(r.timestamp_s);
    return;
  }
  if (!has_update) return;
  const auto start = std::chrono::steady_clock::now();
  const MatchResult m = matcher_.Match(LogOddsView(), preprocess_->kept(), r.sensor_pose);
  if (m.applied) Turn(heading_.Share(m.std_rad, r.timestamp_s) * m.dyaw);
  r.pose_matched = m.applied;
  r.pose_correction = correction_;
  r.times.align_us +=
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
}

void Estimator::Impl::ToInputFrame() {
  if (!config_.alignment.scan_match) return;
  Result& r = result_;
  const Pose2D back = Inverse(correction_);
  const Pose2D map = Compose(back, Pose2D{r.origin.x(), r.origin.y(), r.map_yaw});
  r.origin = Vec2(map.x, map.y);
  r.map_yaw = map.yaw;
  r.sensor_pose = Compose(back, r.sensor_pose);
  for (Pose2D& p : r.cycle_sensor_poses) p = Compose(back, p);
}

// The sensor's heading, in the world and in the map, and the correction turned by `angle` about
// the sensor's position.
void Estimator::Impl::Turn(double angle) {
  if (angle == 0.0) return;
  Result& r = result_;
  correction_ = Compose(RotationAbout(Vec2(r.sensor_pose.x, r.sensor_pose.y), angle), correction_);
  r.sensor_pose.yaw = WrapAngle(r.sensor_pose.yaw + angle);
  r.yaw = WrapAngle(r.yaw + angle);
}

}  // namespace freespace
