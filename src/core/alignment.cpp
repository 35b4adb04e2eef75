// Vehicle on a circle: the paper's eqs. (1)-(7) in cell units.
//
// With P_local^{t-1} = (W^{t-1} - O^{t-1}) / res, eq. (3) becomes
// P_shift = (W^t - O^{t-1}) / res - P_c, so the map origin O moves by floor(P_shift) whole
// cells (eqs. 4, 5) and the vehicle sits at P_c + frac(P_shift) (eqs. 6, 7). The origin is
// kept as an integer count of cells from a fixed anchor, so it never accumulates rounding.
#include "core/alignment.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace freespace {

double WrapAngle(double a) {
  a = std::remainder(a, 2.0 * M_PI);  // [-pi, pi]
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

CircleAligner::CircleAligner(const Config& config)
    : config_(config.alignment),
      resolution_(config.map.resolution_m),
      centre_(0.5 * config.map.width_cells, 0.5 * config.map.height_cells),
      max_radius_cells_(0.5 * std::min(config.map.width_cells, config.map.height_cells) -
                        config.alignment.margin_m / config.map.resolution_m - 1.0),
      distances_(config.alignment.speed_window, 0.0),
      intervals_(config.alignment.speed_window, 0.0) {
  max_radius_cells_ = std::max(0.0, max_radius_cells_);
}

void CircleAligner::Reset() {
  started_ = false;
  jumps_ = 0;
  behind_ = 0;
}

Vec2 CircleAligner::origin_world() const {
  return anchor_ + Vec2(double(origin_x_), double(origin_y_)) * resolution_;
}

void CircleAligner::Start(double t, const Pose2D& sensor, AlignStep* step) {
  // Initially P_local^0 = P_c^1 with zero speed: the vehicle at the map centre.
  started_ = true;
  last_t_ = t;
  last_ = sensor;
  anchor_ = Vec2(sensor.x, sensor.y) - centre_ * resolution_;
  origin_x_ = origin_y_ = 0;
  std::fill(distances_.begin(), distances_.end(), 0.0);
  std::fill(intervals_.begin(), intervals_.end(), 0.0);
  speed_count_ = speed_next_ = 0;
  jumps_ = 0;
  repeats_ = 0;
  behind_ = 0;
  step->accepted = true;
  step->reset = true;
  step->local = centre_;
  step->yaw = WrapAngle(sensor.yaw);
  step->circle_centre = centre_;
  step->circle_point = centre_;
}

AlignStep CircleAligner::Align(double t, const Pose2D& sensor) {
  AlignStep step;
  if (!started_) {
    Start(t, sensor, &step);
    return step;
  }
  const double dt = t - last_t_;
  // A clock that repeats one time for kStalledClockScans scans has stalled: without time, the
  // jump test (a speed limit) and the speed (eq. 1) cannot be judged, so the odometry is taken
  // as it comes, at speed 0, until the clock advances again (docs/behaviour.md).
  repeats_ = dt == 0.0 ? repeats_ + 1 : 0;
  const bool stalled = repeats_ >= kStalledClockScans - 1;
  const bool jitter = !(dt > 0.0) && !stalled;
  if (!(dt > 0.0) && !(-dt <= config_.time_jitter_s)) {
    // A clock that stays behind (one scan stamped far ahead was accepted, or the log joins two
    // drives): after reset_after_jumps such scans in a row, each later than the one before, the
    // map restarts at the last, as after repeated pose jumps; but not while the clock would
    // catch up sooner than it has been behind (a scan stamped a second or two ahead).
    const bool run = behind_ > 0 && t > behind_t_;
    behind_ = run ? behind_ + 1 : 1;
    behind_since_ = run ? behind_since_ : t;
    behind_t_ = t;
    const double to_catch_up = last_t_ - config_.time_jitter_s - t, been = t - behind_since_;
    if (behind_ < config_.reset_after_jumps || !(to_catch_up > been)) {
      step.reason = RejectReason::kTimestampNotIncreasing;
      return step;
    }
    Start(t, sensor, &step);
    step.clock_restart = true;
    return step;
  }
  behind_ = 0;
  // The pose in cells from the anchor must stay below 2^52, where every integer is a double:
  // the origin (within a map of it) then stays exact and the casts below defined. Beyond (a
  // pose far away at a tiny resolution, an overflow to infinity) the scan is rejected before
  // anything changes.
  constexpr double kMaxCells = 4503599627370496.0;  // 2^52
  const Vec2 cells = (Vec2(sensor.x, sensor.y) - anchor_) / resolution_;
  if (!(std::abs(cells.x()) <= kMaxCells && std::abs(cells.y()) <= kMaxCells)) {
    step.reason = RejectReason::kPoseOutOfRange;
    return step;
  }
  const Vec2 d(sensor.x - last_.x, sensor.y - last_.y);
  const double distance = d.norm();
  if (!stalled && !(distance <= config_.max_speed_mps * std::max(dt, 0.0) + config_.jump_slack_m)) {
    if (++jumps_ < config_.reset_after_jumps) {
      step.reason = RejectReason::kPoseJump;
      return step;
    }
    // The odometry stays at the new place: restart the map there.
    Start(t, sensor, &step);
    return step;
  }
  jumps_ = 0;

  // S_t: the displacement, negative against the previous heading (reversing), over dt.
  // Eq. (1) with a_k = dt_k / sum(dt): the window's signed distance over its time. At a
  // constant scan rate that is the paper's a_k = 1 / n; with a jittery clock (scans stamped a
  // millisecond apart) it stays the true speed where a plain mean of samples would not. A
  // scan with clock jitter adds its displacement but no time.
  const double forward = d.x() * std::cos(last_.yaw) + d.y() * std::sin(last_.yaw);
  const double signed_distance = forward < 0.0 ? -distance : distance;
  const bool timeless = jitter || stalled;
  const double speed = timeless ? 0.0 : signed_distance / dt;
  distances_[speed_next_] = stalled ? 0.0 : signed_distance;
  intervals_[speed_next_] = timeless ? 0.0 : dt;
  speed_next_ = (speed_next_ + 1) % int(distances_.size());
  speed_count_ = std::min(speed_count_ + 1, int(distances_.size()));
  double window_distance = 0.0, window_time = 0.0;
  for (int i = 0; i < speed_count_; ++i) {
    window_distance += distances_[i];
    window_time += intervals_[i];
  }
  // No speed beyond max_speed_mps is believed (the jump test's rule): a window of a few
  // denormal-small intervals would otherwise give an infinite speed.
  const double filtered =
      window_time > 0.0
          ? std::clamp(window_distance / window_time, -config_.max_speed_mps, config_.max_speed_mps)
          : 0.0;

  // P_c: on the circle, heading along the radius; behind the centre when moving forward.
  const double yaw = WrapAngle(sensor.yaw);  // eq. (2)
  const double radius =
      std::min(config_.gain_s * std::abs(filtered) / resolution_, max_radius_cells_);
  const double side = filtered < 0.0 ? -1.0 : 1.0;
  const Vec2 circle_point = centre_ - side * radius * Vec2(std::cos(yaw), std::sin(yaw));

  // Eq. (3) with P_local^{t-1} expressed through the previous origin.
  const Vec2 shift = cells - Vec2(double(origin_x_), double(origin_y_)) - circle_point;
  const double kx = std::floor(shift.x()), ky = std::floor(shift.y());
  origin_x_ += std::int64_t(kx);
  origin_y_ += std::int64_t(ky);
  last_t_ = std::max(last_t_, t);  // the clock of accepted scans never runs backwards
  last_ = sensor;
  step.timestamp_jitter = jitter;
  step.clock_stalled = stalled;
  step.stall_detected = stalled && repeats_ == kStalledClockScans - 1;

  step.accepted = true;
  step.shift_x = int(std::clamp(kx, -1e9, 1e9));
  step.shift_y = int(std::clamp(ky, -1e9, 1e9));
  step.local = circle_point + Vec2(shift.x() - kx, shift.y() - ky);  // eqs. (6), (7)
  step.yaw = yaw;
  step.speed_mps = speed;
  step.filtered_speed_mps = filtered;
  step.radius_m = radius * resolution_;
  step.circle_centre = centre_;
  step.circle_point = circle_point;
  return step;
}

}  // namespace freespace
