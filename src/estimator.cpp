// The Estimator: the pipeline of DESIGN.md for one scan, in order: validate, preprocess,
// align (vehicle on a circle, integer map shift), kernel stages 1-4 on the backend, then the
// capped Douglas-Peucker polygon in world coordinates (for the inside polygon on the free mask
// with the vehicle's cells and the safety margin).
#include "freespace/estimator.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "alignment.hpp"
#include "backend.hpp"
#include "polygon.hpp"
#include "preprocess.hpp"

namespace freespace {
namespace {

using Clock = std::chrono::steady_clock;

double Micros(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

bool Finite(const Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw);
}

}  // namespace

double MapView::Probability(int row, int col) const {
  return ProbabilityFromLogOdds(log_odds[std::size_t(row) * width + col]);
}

Estimator::Estimator(const Config& config) : config_(config) {
  config_.Validate();
  backend_ = CreateBackend(config_);
  preprocess_ = std::make_unique<Preprocessor>(config_);
  preprocess_->UseCrew(backend_->HostCrew());
  aligner_ = std::make_unique<CircleAligner>(config_);
  if (config_.alignment.kind == AlignmentKind::kRotate) {
    warper_ = std::make_unique<MapWarper>(config_);
    warp_buffer_.resize(std::size_t(config_.map.width_cells) * config_.map.height_cells);
  }
  const int labels = BorderLabelCount(config_.map.height_cells, config_.map.width_cells);
  simplifier_ = std::make_unique<PolygonSimplifier>(
      config_.polygon.max_vertices, config_.polygon.epsilon_m / config_.map.resolution_m);
  if (config_.polygon.shape == PolygonShape::kInside) {
    inside_ = std::make_unique<InsidePolygonBuilder>(
        config_.map.width_cells, config_.map.height_cells, config_.polygon.max_vertices,
        config_.polygon.epsilon_m / config_.map.resolution_m, config_.backend.threads);
    free_scan_.resize(std::size_t(config_.map.width_cells) * config_.map.height_cells);
    if (backend_->HostLogOdds() == nullptr) log_odds_scan_.resize(free_scan_.size());
    if (config_.polygon.margin_cells > 0) {
      margin_ = std::make_unique<PolygonMargin>(config_.map.width_cells, config_.map.height_cells,
                                                config_.polygon.margin_cells,
                                                config_.polygon.margin_cone_deg);
    }
  }
  result_.polygon.reserve(config_.polygon.max_vertices);
  result_.polygon_cells.reserve(config_.polygon.max_vertices);
  result_.edge_cells.reserve(labels);
  result_.message.reserve(256);
  ring_.reserve(labels);
  kept_.reserve(labels);
  backend_->Clear();
}

Estimator::~Estimator() = default;

std::string Estimator::backend_name() const { return backend_->name(); }

void Estimator::Reset() {
  aligner_->Reset();
  backend_->Clear();
}

const LogOdds* Estimator::PolygonLogOdds() {
  const LogOdds* log_odds = backend_->HostLogOdds();
  if (log_odds != nullptr) return log_odds;
  if (!log_odds_scan_read_) {
    backend_->ReadLogOdds(log_odds_scan_.data());
    log_odds_scan_read_ = true;
  }
  return log_odds_scan_.data();
}

// The opening removes free space narrower than the vehicle, and so the apex of the scans'
// free wedge at the sensor, where the vehicle itself stands (on the first scans that is all
// there is near it). For the conservative polygon the sensor's own cell is free (as it never
// stops an in-sight ray), and so is every cell within the opening's radius of it that the
// scans saw free more often than occupied (log-odds below 0).
void Estimator::FreeWhereTheVehicleStands(const Vec2& sensor) {
  const int width = config_.map.width_cells, height = config_.map.height_cells;
  const int col = int(std::floor(sensor.x())), row = int(std::floor(sensor.y()));
  if (col < 0 || row < 0 || col >= width || row >= height) return;
  free_scan_[std::size_t(row) * width + col] = 1;
  const int h = backend_->params().opening_radius;
  const LogOdds* log_odds = nullptr;
  for (int r = std::max(0, row - h); r <= std::min(height - 1, row + h); ++r) {
    for (int c = std::max(0, col - h); c <= std::min(width - 1, col + h); ++c) {
      const std::size_t i = std::size_t(r) * width + c;
      if (free_scan_[i]) continue;
      // Only now: on a device backend the map is read back for this.
      if (log_odds == nullptr) log_odds = PolygonLogOdds();
      if (log_odds[i] < 0) free_scan_[i] = 1;
    }
  }
}

const Result& Estimator::Process(const Scan& scan) {
  const Clock::time_point t_begin = Clock::now();
  Result& r = result_;
  r.scan_index = scans_++;
  r.timestamp_s = scan.timestamp_s;
  r.status = ScanStatus::kOk;
  r.reject_reason = RejectReason::kNone;
  r.message.clear();
  r.map_reset = false;
  r.timestamp_jitter = false;
  r.pose = scan.pose;
  r.times = StageTimes{};
  r.stats = ScanStats{};
  r.polygon.clear();
  r.polygon_cells.clear();
  r.edge_cells.clear();
  r.simplification_error_m = 0.0;
  r.polygon_contains_vehicle = false;

  char text[200];
  auto reject = [&](RejectReason reason) -> const Result& {
    r.status = ScanStatus::kRejected;
    r.reject_reason = reason;
    r.message.assign(text);
    r.times.total_us = Micros(t_begin, Clock::now());
    return r;
  };
  if (!std::isfinite(scan.timestamp_s)) {
    std::snprintf(text, sizeof text, "timestamp %g is not finite", scan.timestamp_s);
    return reject(RejectReason::kTimestampNotFinite);
  }
  if (!Finite(scan.pose)) {
    std::snprintf(text, sizeof text, "pose (%g, %g, %g) is not finite", scan.pose.x, scan.pose.y,
                  scan.pose.yaw);
    return reject(RejectReason::kPoseNotFinite);
  }

  // The sensor's world pose: the odometry pose composed with the mount.
  const SensorConfig& s = config_.sensor;
  const double cy = std::cos(scan.pose.yaw), sy = std::sin(scan.pose.yaw);
  r.sensor_pose.x = scan.pose.x + cy * s.mount_x_m - sy * s.mount_y_m;
  r.sensor_pose.y = scan.pose.y + sy * s.mount_x_m + cy * s.mount_y_m;
  r.sensor_pose.yaw = WrapAngle(scan.pose.yaw + s.mount_yaw_deg * M_PI / 180.0);

  // Preprocess (sensor frame): validation, DBSCAN, virtual points.
  const bool has_update = preprocess_->Run(scan, &r.stats);
  const Clock::time_point t_pre = Clock::now();
  r.times.preprocess_us = Micros(t_begin, t_pre);

  // Align: vehicle on a circle, then the integer shift of the map (or, for the baseline
  // alignment, the rotation and sub-pixel shift of a vehicle-centred map).
  const double previous_t = aligner_->last_timestamp();
  const AlignStep step = aligner_->Align(scan.timestamp_s, r.sensor_pose);
  if (!step.accepted) {
    if (step.reason == RejectReason::kTimestampNotIncreasing) {
      std::snprintf(text, sizeof text,
                    "timestamp %.6f s is %.3f s before the previous scan's %.6f s (more than "
                    "alignment.time_jitter_s %.3f s)",
                    scan.timestamp_s, previous_t - scan.timestamp_s, previous_t,
                    config_.alignment.time_jitter_s);
    } else {
      std::snprintf(text, sizeof text,
                    "pose jumped %.1f m in %.3f s (limit %.0f m/s + %.1f m); jump %d of %d "
                    "before the map restarts",
                    std::hypot(r.sensor_pose.x - last_sensor_.x, r.sensor_pose.y - last_sensor_.y),
                    scan.timestamp_s - previous_t, config_.alignment.max_speed_mps,
                    config_.alignment.jump_slack_m, aligner_->consecutive_jumps(),
                    config_.alignment.reset_after_jumps);
    }
    return reject(step.reason);
  }
  if (step.timestamp_jitter) {
    r.timestamp_jitter = true;
    std::snprintf(text, sizeof text,
                  "timestamp %.6f s is not after the previous scan's %.6f s: clock jitter, used "
                  "without a speed sample",
                  scan.timestamp_s, previous_t);
    r.message.assign(text);
  }
  const Pose2D previous_sensor = last_sensor_;
  last_sensor_ = r.sensor_pose;
  const int width = config_.map.width_cells, height = config_.map.height_cells;
  const double res = config_.map.resolution_m;
  Vec2 local = step.local;  // the sensor in the map, cells
  double local_yaw = step.yaw;
  if (step.reset) {
    backend_->Clear();
    r.map_reset = true;
  } else if (warper_ == nullptr) {
    backend_->Shift(step.shift_x, step.shift_y);  // eqs. (4), (5)
  } else {
    backend_->ReadLogOdds(warp_buffer_.data());
    warper_->Warp(previous_sensor, r.sensor_pose, warp_buffer_.data());
    backend_->WriteLogOdds(warp_buffer_.data());
  }
  r.filtered_speed_mps = step.filtered_speed_mps;
  if (warper_ == nullptr) {
    r.circle_radius_m = step.radius_m;
    r.circle_centre_cells = step.circle_centre;
    r.origin = aligner_->origin_world();
    r.origin_cell_x = aligner_->origin_x();
    r.origin_cell_y = aligner_->origin_y();
    r.map_yaw = 0.0;
  } else {
    // Vehicle-centred and turning with the vehicle: the sensor at the centre facing +x.
    local = warper_->centre();
    local_yaw = 0.0;
    r.circle_radius_m = 0.0;
    r.circle_centre_cells = local;
    r.map_yaw = r.sensor_pose.yaw;
    const double c = std::cos(r.map_yaw), s_yaw = std::sin(r.map_yaw);
    r.origin = Vec2(r.sensor_pose.x, r.sensor_pose.y) -
               Vec2(c * local.x() - s_yaw * local.y(), s_yaw * local.x() + c * local.y()) * res;
    r.origin_cell_x = r.origin_cell_y = 0;
  }
  r.vehicle_cells = local;
  r.yaw = local_yaw;
  r.vehicle_cell = {std::clamp(int(std::floor(local.y())), 0, height - 1),
                    std::clamp(int(std::floor(local.x())), 0, width - 1)};
  const Clock::time_point t_align = Clock::now();
  r.times.align_us = Micros(t_pre, t_align);

  // Kernel stages 1 and 2: the enhanced inverse sensor model and the fusion.
  Clock::time_point t_fuse = t_align;
  if (has_update && config_.sensor_model.kind == SensorModelKind::kEnhanced) {
    RasterJob job;
    preprocess_->Project(local, local_yaw, width, height, &job);
    backend_->Rasterize(job);
    const Clock::time_point t_raster = Clock::now();
    r.times.rasterize_us = Micros(t_align, t_raster);
    backend_->Fuse(job.row_begin, job.row_end);
    t_fuse = Clock::now();
    r.times.fuse_us = Micros(t_raster, t_fuse);
  } else if (has_update) {
    // The paper's baseline: one ray per kept echo, no virtual points.
    RayJob job;
    preprocess_->ProjectRays(local, local_yaw, width, height, &job);
    backend_->CastRays(job);
    const Clock::time_point t_raster = Clock::now();
    r.times.rasterize_us = Micros(t_align, t_raster);
    backend_->FuseRays(job.row_begin, job.row_end);
    t_fuse = Clock::now();
    r.times.fuse_us = Micros(t_raster, t_fuse);
  } else {
    r.status = ScanStatus::kNoSensorUpdate;
    r.message.assign(scan.points.empty() ? "empty scan: no sensor update"
                                         : "no usable echo: no sensor update");
  }

  // Kernel stage 3 and 4: classification + opening, in-sight edges.
  backend_->Classify();
  const Clock::time_point t_classify = Clock::now();
  r.times.classify_us = Micros(t_fuse, t_classify);
  backend_->InSight(r.vehicle_cell, &r.edge_cells);
  const Clock::time_point t_insight = Clock::now();
  r.times.insight_us = Micros(t_classify, t_insight);

  // Polygon: C_Edge cell centres (paper) or the conservative polygon on the free mask (inside),
  // capped Douglas-Peucker, world coordinates.
  double error_cells = 0.0;
  if (inside_ != nullptr) {
    backend_->ReadFree(free_scan_.data());
    log_odds_scan_read_ = false;
    FreeWhereTheVehicleStands(local);
    // The margin after: it may keep out cells near the vehicle, but never the sensor's own.
    if (margin_ != nullptr) margin_->Apply(PolygonLogOdds(), local, free_scan_.data());
    error_cells = inside_->Build(free_scan_.data(), local, &r.polygon_cells);
  } else {
    ring_.clear();
    for (const CellIndex& c : r.edge_cells) ring_.emplace_back(c.col + 0.5, c.row + 0.5);
    error_cells = simplifier_->Simplify(ring_, local, &kept_);
    for (const int i : kept_) r.polygon_cells.push_back(ring_[i]);
  }
  const double mc = std::cos(r.map_yaw), ms = std::sin(r.map_yaw);
  for (const Vec2& v : r.polygon_cells) {
    r.polygon.push_back(r.origin + Vec2(mc * v.x() - ms * v.y(), ms * v.x() + mc * v.y()) * res);
  }
  r.simplification_error_m = error_cells * res;
  r.polygon_contains_vehicle = PointInPolygon(r.polygon_cells, local);
  const Clock::time_point t_end = Clock::now();
  r.times.polygon_us = Micros(t_insight, t_end);
  backend_->KernelTimes(&r.times);
  r.times.total_us = Micros(t_begin, t_end);
  return r;
}

MapView Estimator::map() const {
  MapView v;
  v.width = config_.map.width_cells;
  v.height = config_.map.height_cells;
  v.resolution_m = config_.map.resolution_m;
  v.origin = result_.origin;
  v.map_yaw = result_.map_yaw;
  const std::size_t cells = std::size_t(v.width) * v.height;
  v.log_odds = backend_->HostLogOdds();
  if (v.log_odds == nullptr) {
    map_mirror_.resize(cells);
    backend_->ReadLogOdds(map_mirror_.data());
    v.log_odds = map_mirror_.data();
  }
  v.free = backend_->HostFree();
  if (v.free == nullptr) {
    free_mirror_.resize(cells);
    backend_->ReadFree(free_mirror_.data());
    v.free = free_mirror_.data();
  }
  return v;
}

const char* ToString(ScanStatus status) {
  switch (status) {
    case ScanStatus::kOk:
      return "ok";
    case ScanStatus::kNoSensorUpdate:
      return "no_sensor_update";
    case ScanStatus::kRejected:
      return "rejected";
  }
  return "?";
}

const char* ToString(RejectReason reason) {
  switch (reason) {
    case RejectReason::kNone:
      return "none";
    case RejectReason::kTimestampNotFinite:
      return "timestamp_not_finite";
    case RejectReason::kTimestampNotIncreasing:
      return "timestamp_not_increasing";
    case RejectReason::kPoseNotFinite:
      return "pose_not_finite";
    case RejectReason::kPoseJump:
      return "pose_jump";
  }
  return "?";
}

}  // namespace freespace
