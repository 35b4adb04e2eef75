// The estimator's checks of a scan's input (time, pose, sensor) and the vehicle-on-a-circle
// alignment with the map's shift, each rejection with the message that says why.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "estimator_impl.hpp"

namespace freespace {
namespace {

bool Finite(const Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw);
}

}  // namespace

bool Estimator::Impl::CheckInput(const Scan& scan) {
  char text[200];
  if (!std::isfinite(scan.timestamp_s)) {
    std::snprintf(text, sizeof text, "timestamp %g is not finite", scan.timestamp_s);
    Reject(RejectReason::kTimestampNotFinite, text);
    return false;
  }
  if (!Finite(scan.pose)) {
    std::snprintf(text, sizeof text, "pose (%g, %g, %g) is not finite", scan.pose.x, scan.pose.y,
                  scan.pose.yaw);
    Reject(RejectReason::kPoseNotFinite, text);
    return false;
  }
  // Finite but extreme values would overflow the map's integer origin and cell indices: the
  // bounds of freespace/scan.hpp keep every derived quantity representable.
  if (!(std::abs(scan.timestamp_s) <= kMaxTimestampS)) {
    std::snprintf(text, sizeof text,
                  "timestamp %.6g s is out of range (|t| <= %.0e s; another unit than seconds?)",
                  scan.timestamp_s, kMaxTimestampS);
    Reject(RejectReason::kTimestampOutOfRange, text);
    return false;
  }
  if (!(std::abs(scan.pose.x) <= kMaxCoordinateM && std::abs(scan.pose.y) <= kMaxCoordinateM)) {
    std::snprintf(text, sizeof text, "pose (%.6g, %.6g) m is out of range (|x|, |y| <= %.0e m)",
                  scan.pose.x, scan.pose.y, kMaxCoordinateM);
    Reject(RejectReason::kPoseOutOfRange, text);
    return false;
  }
  if (!config_.is_rig() && scan.sensor != 0) {
    std::snprintf(text, sizeof text,
                  "the scan names sensor %d, but the config has one sensor (a rig is a "
                  "'sensors' list)",
                  scan.sensor);
    Reject(RejectReason::kBadCycle, text);
    return false;
  }
  return true;
}

// Vehicle on a circle, then the aligner moves the map (an integer shift, or for the baseline a
// rotation and sub-pixel shift of a vehicle-centred map).
bool Estimator::Impl::Align(const Scan& scan) {
  Result& r = result_;
  char text[320];
  const double previous_t = circle_.last_timestamp();
  const bool restart = circle_.started();  // a reset now restarts a map
  const AlignStep step = circle_.Align(scan.timestamp_s, r.sensor_pose);
  if (!step.accepted) {
    if (step.reason == RejectReason::kTimestampNotIncreasing) {
      std::snprintf(
          text, sizeof text,
          "timestamp %.6f s is %.3f s before the latest accepted scan's %.6f s (more than "
          "alignment.time_jitter_s %.3f s); %d in a row behind the clock (the map restarts "
          "after %d when the clock would take longer to catch up than it has been behind)",
          scan.timestamp_s, previous_t - scan.timestamp_s, previous_t,
          config_.alignment.time_jitter_s, circle_.consecutive_behind(),
          config_.alignment.reset_after_jumps);
    } else if (step.reason == RejectReason::kPoseOutOfRange) {
      std::snprintf(text, sizeof text,
                    "sensor pose (%.6g, %.6g) m moves the map by more cells than an integer "
                    "holds at map.resolution_m %g",
                    r.sensor_pose.x, r.sensor_pose.y, config_.map.resolution_m);
    } else {
      std::snprintf(text, sizeof text,
                    "pose jumped %.1f m in %.3f s (limit %.0f m/s + %.1f m); jump %d of %d "
                    "before the map restarts",
                    std::hypot(r.sensor_pose.x - last_sensor_.x, r.sensor_pose.y - last_sensor_.y),
                    scan.timestamp_s - previous_t, config_.alignment.max_speed_mps,
                    config_.alignment.jump_slack_m, circle_.consecutive_jumps(),
                    config_.alignment.reset_after_jumps);
    }
    Reject(step.reason, text);
    return false;
  }
  if (step.timestamp_jitter) {
    r.timestamp_jitter = true;
    std::snprintf(
        text, sizeof text,
        "timestamp %.6f s is not after the latest accepted scan's %.6f s: clock jitter, used "
        "without a speed sample",
        scan.timestamp_s, previous_t);
    AddMessage(&r, text);
  }
  r.clock_stalled = step.clock_stalled;
  r.stall_detected = step.stall_detected;
  if (step.stall_detected) {
    std::snprintf(text, sizeof text,
                  "the clock has stalled: %d scans in a row stamped %.6f s; until it advances, "
                  "poses are used without a jump test and give no speed",
                  kStalledClockScans, scan.timestamp_s);
    AddMessage(&r, text);
  }
  const Pose2D before = last_sensor_;
  last_sensor_ = r.sensor_pose;
  if (step.reset) {
    backend_->Clear();
    r.map_reset = true;
    if (step.clock_restart) {
      std::snprintf(text, sizeof text,
                    "the clock stayed behind the latest accepted scan's %.6f s for %d scans in a "
                    "row: the map restarted at this scan's %.6f s",
                    previous_t, config_.alignment.reset_after_jumps, scan.timestamp_s);
      AddMessage(&r, text);
    } else if (restart) {
      std::snprintf(text, sizeof text,
                    "the pose jumped %d time(s) in a row (alignment.reset_after_jumps): the map "
                    "restarted at this pose",
                    config_.alignment.reset_after_jumps);
      AddMessage(&r, text);
    }
  }
  r.filtered_speed_mps = step.filtered_speed_mps;
  aligner_->Apply(step, circle_, before, r.sensor_pose, backend_.get(), &r);
  const int width = config_.map.width_cells, height = config_.map.height_cells;
  r.vehicle_cell = {std::clamp(int(std::floor(r.vehicle_cells.y())), 0, height - 1),
                    std::clamp(int(std::floor(r.vehicle_cells.x())), 0, width - 1)};
  return true;
}

// The sensor model and the fusion (kernel stages 1, 2), and this scan's echoes for the veto.

}  // namespace freespace
