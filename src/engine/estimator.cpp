// The Estimator: the pipeline of DESIGN.md for one scan, in order: validate, preprocess,
// align (vehicle on a circle, integer map shift), the sensor model and fusion (kernel stages 1
// and 2), classification and the in-sight scan (stages 3 and 4) on the backend, then the
// polygon in world coordinates.
#include "freespace/estimator.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/simplifier.hpp"
#include "engine/backend_factory.hpp"
#include "estimator_impl.hpp"

namespace freespace {
namespace {

using Clock = std::chrono::steady_clock;

double Micros(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

Config Validated(Config config) {
  config.Validate();
  return config;
}

}  // namespace

double MapView::Probability(int row, int col) const {
  return ProbabilityFromLogOdds(log_odds[std::size_t(row) * width + col]);
}

Estimator::Impl::Impl(const Config& config)
    : config_(Validated(config)),
      circle_(config_),
      movers_(MoverRule::Of(config_)),
      matcher_(MakeMatcher(config_)),
      heading_(config_.alignment.heading_drift_dps * M_PI / 180.0) {
  backend_ = CreateBackend(config_);
  preprocess_ = std::make_unique<Preprocessor>(config_);
  const Backend::CrewRequest crew = backend_->WantedCrew();
  if (crew.helpers > 0) {
    crew_ = std::make_unique<Crew>(crew.helpers, crew.linger, crew.window);
    backend_->UseCrew(crew_.get());
    preprocess_->UseCrew(crew_.get());
  }
  aligner_ = MakeMapAligner(config_);
  sensor_model_ = MakeSensorModel(config_);
  polygon_ = MakePolygonExtractor(config_, *backend_);
  const int labels = BorderLabelCount(config_.map.height_cells, config_.map.width_cells);
  result_.polygon.reserve(config_.polygon.max_vertices);
  result_.polygon_cells.reserve(config_.polygon.max_vertices);
  result_.edge_cells.reserve(labels);
  result_.message.reserve(256);
  backend_->Clear();
  if (config_.is_rig()) MakeRig();
}

void Estimator::Impl::Reset() {
  circle_.Reset();
  backend_->Clear();
  sweep_.Forget();
  for (RigSensor& unit : rig_) unit.sweep.Forget();
  movers_.Clear();
  correction_ = Pose2D{};
  map_has_scans_ = false;
}

// sensor.sweep_s: the sensor's motion since its last accepted scan (core/sweep.hpp). Call after
// Align(), so that a map reset forgets that scan. False when the scan stays at one pose.
bool Estimator::Impl::SweepMotionOf(SweepTracker* tracker, const SensorConfig& sensor,
                                    const Pose2D& sensor_pose, double t, SweepMotion* motion) {
  if (sensor.sweep_s == 0.0) return false;
  if (result_.map_reset) tracker->Forget();
  const bool moved = tracker->Motion(sensor_pose, t, config_.alignment.max_speed_mps, motion);
  tracker->Remember(sensor_pose, t);
  return moved;
}

// The scan's points placed from where its sensor was as each was taken, with that motion; its
// time counts as preprocessing.
bool Estimator::Impl::Sweep(Preprocessor* preprocess, SweepTracker* tracker,
                            const SensorConfig& sensor, const Pose2D& sensor_pose, double t) {
  const Clock::time_point start = Clock::now();
  SweepMotion motion;
  const bool moved = SweepMotionOf(tracker, sensor, sensor_pose, t, &motion);
  if (moved) preprocess->Deskew(motion);
  result_.times.preprocess_us += Micros(start, Clock::now());
  return moved;
}

void Estimator::Impl::Begin(const Scan& scan) {
  Result& r = result_;
  r.scan_index = scans_++;
  r.timestamp_s = scan.timestamp_s;
  r.status = ScanStatus::kOk;
  r.reject_reason = RejectReason::kNone;
  r.message.clear();
  r.map_reset = false;
  r.timestamp_jitter = false;
  r.clock_stalled = false;
  r.stall_detected = false;
  r.sweep_corrected = false;
  r.pose = scan.pose;
  r.pose_correction = correction_;
  r.pose_matched = false;
  r.times = StageTimes{};
  r.stats = ScanStats{};
  cycle_scanners_.clear();
  r.polygon.clear();
  r.polygon_cells.clear();
  r.edge_cells.clear();
  r.polygon_status = PolygonStatus::kNone;
  r.simplification_error_m = 0.0;
  r.polygon_contains_vehicle = false;
  r.cycle_sensors.clear();
  r.cycle_sensor_poses.clear();
  r.cycle_silent_sensors.clear();
}

const Result& Estimator::Impl::Reject(RejectReason reason, const char* text) {
  result_.status = ScanStatus::kRejected;
  result_.reject_reason = reason;
  result_.message.assign(text);
  result_.timestamp_jitter = false;  // a rejected call reports its rejection only
  result_.cycle_silent_sensors.clear();
  return result_;
}

// With backend.threads 0 the mover layer's detection runs beside the map's update and the face
// layer beside the classification, which need neither (SideWorkBeside()).
void Estimator::Impl::UpdateMap(bool has_update, const Scan& scan) {
  Result& r = result_;
  if (movers_.enabled()) StartMovers(scan.timestamp_s);
  faces_pending_ = false;
  if (has_update) {
    const auto detect = [&] {
      if (movers_.enabled())
        movers_.Detect(0, r.sensor_pose, scan.timestamp_s, preprocess_->beams());
    };
    const bool faces = FaceRule::Of(config_).tolerance_m > 0;
    const bool beside = (movers_.enabled() || faces) && SideWorkBeside();
    sensor_model_->Update(preprocess_.get(), r.vehicle_cells, r.yaw, backend_.get(), &r.times,
                          SideWork(&detect), beside);
    const std::vector<std::int32_t>& echoes = preprocess_->echo_cells();
    backend_->SetEchoes(echoes.data(), int(echoes.size()));
    faces_t_ = scan.timestamp_s;
    faces_pending_ = beside && faces;
    if (!faces_pending_) SetFaceLayer();
  } else {
    backend_->SetEchoes(nullptr, 0);
    const std::vector<std::int32_t> none;
    const std::vector<std::int32_t>& near = MoverCells(none, scan.timestamp_s);
    backend_->SetFaces(near.data(), int(near.size()), nullptr, 0);
    r.status = ScanStatus::kNoSensorUpdate;
    AddMessage(&r, scan.points.empty() ? "empty scan: no sensor update"
                                       : "no usable echo: no sensor update");
  }
}

void Estimator::Impl::SetFaceLayer() {
  const std::vector<std::int32_t>& near = MoverCells(preprocess_->face_near_cells(), faces_t_);
  const std::vector<std::int32_t>& seen = preprocess_->face_seen_cells();
  backend_->SetFaces(near.data(), int(near.size()), seen.data(), int(seen.size()));
}

bool Estimator::Impl::SideWorkBeside() const {
  return config_.backend.threads == 0 && !backend_->KernelsOnHostCores();
}

void Estimator::Impl::StartMovers(double t) {
  if (result_.map_reset) movers_.Clear();  // a jump of the poses: the tracks' places mean nothing
  movers_.BeginCycle(t);
}

const std::vector<std::int32_t>& Estimator::Impl::MoverCells(const std::vector<std::int32_t>& near,
                                                             double t) {
  if (!movers_.enabled()) return near;
  const Clock::time_point start = Clock::now();
  Result& r = result_;
  movers_.Commit();
  if (movers_.movers() == 0) {  // no hazard: the face layer's cells as they are
    r.times.rasterize_us += Micros(start, Clock::now());
    return near;
  }
  hazard_.assign(near.begin(), near.end());
  MapFrame frame;
  frame.origin = r.origin;
  frame.yaw = r.map_yaw;
  frame.resolution_m = config_.map.resolution_m;
  frame.width = config_.map.width_cells;
  frame.height = config_.map.height_cells;
  movers_.Hazard(t, frame, &hazard_);
  r.times.rasterize_us += Micros(start, Clock::now());
  return hazard_;
}

// Kernel stage 3 (classification + opening) and the border rays (stage 4).
// A face layer left by UpdateMap() is projected beside the classification; classify_us takes
// what it adds.
void Estimator::Impl::ClassifyAndScan() {
  const Clock::time_point start = Clock::now();
  if (faces_pending_) {
    const int width = config_.map.width_cells, height = config_.map.height_cells;
    tbb::parallel_invoke([&] { backend_->Classify(); },
                         [&] { preprocess_->ProjectFaces(width, height); });
  } else {
    backend_->Classify();
  }
  result_.times.classify_us = Micros(start, Clock::now());
  if (faces_pending_) {  // the mover layer's part counts in rasterize_us (MoverCells)
    faces_pending_ = false;
    SetFaceLayer();
  }
  polygon_->CastRays(result_.vehicle_cells, result_.vehicle_cell, cycle_scanners_, backend_.get(),
                     &result_.edge_cells, &result_.times);
}

// The polygon in map cells, then in world metres.
void Estimator::Impl::ExtractPolygon() {
  Result& r = result_;
  double error_cells = 0.0;
  if (!polygon_->Extract(r.edge_cells, r.vehicle_cells, &r.polygon_cells, &error_cells)) {
    r.polygon_status = PolygonStatus::kNoFreeSpace;
    if (polygon_->too_few_vertices()) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "the polygon pulled inside the free space collapsed to fewer than 3 distinct "
                    "vertices (polygon.max_vertices = %d): no polygon",
                    config_.polygon.max_vertices);
      AddMessage(&r, text);
    } else {
      AddMessage(&r, "nothing around the sensor is free: no polygon");
    }
    return;
  }
  r.polygon_status = PolygonStatus::kOk;
  const double res = config_.map.resolution_m;
  const double mc = std::cos(r.map_yaw), ms = std::sin(r.map_yaw);
  for (const Vec2& v : r.polygon_cells) {
    r.polygon.push_back(r.origin + Vec2(mc * v.x() - ms * v.y(), ms * v.x() + mc * v.y()) * res);
  }
  r.simplification_error_m = error_cells * res;
  r.polygon_contains_vehicle = PointInPolygon(r.polygon_cells, r.vehicle_cells);
}

const Result& Estimator::Impl::Process(const Scan& scan) {
  if (config_.is_rig()) return ProcessCycle(&scan, 1);
  const Clock::time_point t_begin = Clock::now();
  Result& r = result_;
  Begin(scan);
  const auto finish = [&]() -> const Result& {
    r.times.total_us = Micros(t_begin, Clock::now());
    return r;
  };
  if (!CheckInput(scan)) return finish();
  r.sensor_pose = SensorPose(Corrected(scan.pose), config_.sensor);
  r.cycle_sensors.push_back(0);
  r.cycle_sensor_poses.push_back(r.sensor_pose);

  // Preprocess (sensor frame): validation, DBSCAN, virtual points.
  const bool has_update = preprocess_->Run(scan, &r.stats);
  const Clock::time_point t_pre = Clock::now();
  r.times.preprocess_us = Micros(t_begin, t_pre);
  if (!Align(scan)) return finish();
  const Clock::time_point t_align = Clock::now();
  r.times.align_us = Micros(t_pre, t_align);
  // Sweep() remembers the pose for the next scan's motion, a scan without echoes too.
  const bool swept =
      Sweep(preprocess_.get(), &sweep_, config_.sensor, r.sensor_pose, scan.timestamp_s);
  r.sweep_corrected = swept && has_update;
  MatchPose(has_update);
  r.cycle_sensor_poses.back() = r.sensor_pose;

  UpdateMap(has_update, scan);
  map_has_scans_ = map_has_scans_ || has_update;
  return Conclude(t_begin);
}

const Result& Estimator::Impl::Conclude(Clock::time_point t_begin) {
  Result& r = result_;
  ClassifyAndScan();
  ToInputFrame();
  const Clock::time_point t_polygon = Clock::now();
  ExtractPolygon();
  const Clock::time_point t_end = Clock::now();
  r.times.polygon_us = Micros(t_polygon, t_end);
  if (!config_.is_rig()) {
    backend_->KernelTimes(&r.times);
  } else {
    // The backend times its last stages only: a cycle's several updates keep their summed wall
    // times.
    StageTimes kernel = r.times;
    if (backend_->KernelTimes(&kernel)) {
      kernel.rasterize_us = r.times.rasterize_us;
      kernel.fuse_us = r.times.fuse_us;
      r.times = kernel;
    }
  }
  r.times.total_us = Micros(t_begin, t_end);
  return r;
}

MapView Estimator::Impl::LogOddsView() const {
  MapView v;
  v.width = config_.map.width_cells;
  v.height = config_.map.height_cells;
  v.resolution_m = config_.map.resolution_m;
  v.origin = result_.origin;
  v.map_yaw = result_.map_yaw;
  v.log_odds = backend_->HostLogOdds();
  if (v.log_odds == nullptr) {
    map_mirror_.resize(std::size_t(v.width) * v.height);
    backend_->ReadLogOdds(map_mirror_.data());
    v.log_odds = map_mirror_.data();
  }
  return v;
}

MapView Estimator::Impl::map() const {
  MapView v = LogOddsView();
  const std::size_t cells = std::size_t(v.width) * v.height;
  v.free = backend_->HostFree();
  if (v.free == nullptr) {
    free_mirror_.resize(cells);
    backend_->ReadFree(free_mirror_.data());
    v.free = free_mirror_.data();
  }
  return v;
}

Estimator::Estimator(const Config& config) : impl_(std::make_unique<Impl>(config)) {}
Estimator::~Estimator() = default;
const Result& Estimator::Process(const Scan& scan) { return impl_->Process(scan); }
const Result& Estimator::ProcessCycle(const Scan* scans, int count) {
  return impl_->ProcessCycle(scans, count);
}
void Estimator::Reset() { impl_->Reset(); }
MapView Estimator::map() const { return impl_->map(); }
const Config& Estimator::config() const { return impl_->config(); }
std::string Estimator::backend_name() const { return impl_->backend().name(); }

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

const char* ToString(PolygonStatus status) {
  switch (status) {
    case PolygonStatus::kOk:
      return "ok";
    case PolygonStatus::kNoFreeSpace:
      return "no_free_space";
    case PolygonStatus::kNone:
      return "none";
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
    case RejectReason::kTimestampOutOfRange:
      return "timestamp_out_of_range";
    case RejectReason::kPoseOutOfRange:
      return "pose_out_of_range";
    case RejectReason::kPoseJump:
      return "pose_jump";
    case RejectReason::kBadCycle:
      return "bad_cycle";
  }
  return "?";
}

}  // namespace freespace
