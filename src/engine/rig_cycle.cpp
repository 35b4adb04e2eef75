// A rig's cycle (docs/design.md, "A rig of sensors"): every scan of the cycle is preprocessed by
// its own sensor's preprocessor (in parallel), then fused as the paper fuses one scan, from its
// own sensor pose at its own time, one scan after the other in the rig's order; the vehicle's
// footprint is fused as free last. The circle, the classification, the border rays and the
// polygon then run once, around the rig's reference point at the newest scan's pose.
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "estimator_impl.hpp"

namespace freespace {
namespace {

using Clock = std::chrono::steady_clock;

double Micros(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

void AddStats(const ScanStats& s, ScanStats* sum) {
  sum->points += s.points;
  sum->echoes += s.echoes;
  sum->no_echo += s.no_echo;
  sum->invalid_range += s.invalid_range;
  sum->out_of_aperture += s.out_of_aperture;
  sum->bad_layer += s.bad_layer;
  sum->clutter += s.clutter;
  sum->kept += s.kept;
  sum->beams += s.beams;
  sum->virtual_points += s.virtual_points;
}

// A world pose in the map's cells (fractional) and its yaw in the map, as the aligner placed
// the map and the reference point in `r`: the reference's cells plus the offset from it, so that
// a sensor at the reference point lands exactly where the aligner put the reference.
Vec2 MapCells(const Pose2D& p, const Result& r, double resolution, double* yaw) {
  const double c = std::cos(r.map_yaw), s = std::sin(r.map_yaw);
  const double dx = p.x - r.sensor_pose.x, dy = p.y - r.sensor_pose.y;
  *yaw = WrapAngle(p.yaw - r.map_yaw);
  return r.vehicle_cells + Vec2(c * dx + s * dy, -s * dx + c * dy) / resolution;
}

}  // namespace

void Estimator::Impl::MakeRig() {
  rig_arena_ = ThreadArena(config_.backend.threads);
  rig_.resize(config_.sensors.size());
  for (std::size_t i = 0; i < rig_.size(); ++i) {
    rig_[i].config = config_;
    rig_[i].config.sensor = config_.sensors[i];
    rig_[i].config.sensors.clear();
    rig_[i].preprocess = std::make_unique<Preprocessor>(rig_[i].config);
  }
  cycle_order_.reserve(rig_.size());
  result_.cycle_sensors.reserve(rig_.size());
  result_.cycle_sensor_poses.reserve(rig_.size());
}

// One scan per sensor at most, every index in the rig; fills cycle_order_ (scans by sensor).
bool Estimator::Impl::CheckCycle(const Scan* scans, int count) {
  char text[200];
  if (count < 1 || scans == nullptr) {
    Reject(RejectReason::kBadCycle, "an empty cycle: no scan to process");
    return false;
  }
  const int sensors = config_.sensor_count();
  if (count > sensors) {
    std::snprintf(text, sizeof text, "a cycle of %d scans from a rig of %d sensors", count,
                  sensors);
    Reject(RejectReason::kBadCycle, text);
    return false;
  }
  cycle_order_.clear();
  for (int i = 0; i < count; ++i) {
    const int s = scans[i].sensor;
    if (s < 0 || s >= sensors) {
      std::snprintf(text, sizeof text, "scan %d of the cycle names sensor %d; the rig has 0 .. %d",
                    i, s, sensors - 1);
      Reject(RejectReason::kBadCycle, text);
      return false;
    }
    for (int j : cycle_order_) {
      if (scans[j].sensor == s) {
        std::snprintf(text, sizeof text, "sensor %d (%s) has two scans in one cycle", s,
                      config_.sensor_at(s).name.c_str());
        Reject(RejectReason::kBadCycle, text);
        return false;
      }
    }
    cycle_order_.push_back(i);
  }
  std::sort(cycle_order_.begin(), cycle_order_.end(),
            [&](int a, int b) { return scans[a].sensor < scans[b].sensor; });
  return true;
}

// Every scan no earlier than the latest accepted time less alignment.time_jitter_s, as Process()
// takes a scan: the alignment sees the cycle's newest scan only, and an older one of another
// sensor would otherwise be fused however stale.
bool Estimator::Impl::CheckCycleTimes(const Scan* scans, int count, int newest) {
  if (!circle_.started()) return true;
  const double previous = circle_.last_timestamp(), jitter = config_.alignment.time_jitter_s;
  // The whole cycle behind: the alignment judges its newest scan (and restarts the map when the
  // clock stays behind).
  if (scans[newest].timestamp_s - previous < -jitter) return true;
  for (int i = 0; i < count; ++i) {
    const Scan& scan = scans[i];
    if (scan.timestamp_s - previous >= -jitter) continue;
    char text[240];
    std::snprintf(text, sizeof text,
                  "the scan of sensor %d (%s) at %.6f s is %.3f s before the latest accepted "
                  "scan's %.6f s (more than alignment.time_jitter_s %.3f s)",
                  scan.sensor, config_.sensors[scan.sensor].name.c_str(), scan.timestamp_s,
                  previous - scan.timestamp_s, previous, jitter);
    Reject(RejectReason::kTimestampNotIncreasing, text);
    return false;
  }
  return true;
}

// After an accepted alignment: a scan other than the newest at or before the time the latest
// accepted scan had (`previous`), within the jitter, is clock jitter as in Process() (the
// alignment reports the newest); not while the clock stalls, which repeats one time.
void Estimator::Impl::NoteCycleJitter(const Scan* scans, int count, int newest, double previous) {
  Result& r = result_;
  if (r.map_reset || r.clock_stalled) return;
  for (int i = 0; i < count; ++i) {
    const Scan& scan = scans[i];
    if (i == newest || scan.timestamp_s > previous) continue;
    r.timestamp_jitter = true;
    char text[240];
    std::snprintf(text, sizeof text,
                  "the scan of sensor %d (%s) at %.6f s is not after the latest accepted scan's "
                  "%.6f s: clock jitter, used",
                  scan.sensor, config_.sensors[scan.sensor].name.c_str(), scan.timestamp_s,
                  previous);
    AddMessage(&r, text);
  }
}

// Every scan's sensor within reach of the reference point: no farther from it than its mount
// plus what the vehicle can travel between the two scans' times (alignment.max_speed_mps and
// jump_slack_m), and inside the map's diagonal, so that each scan lands in the map. Fills
// Result::cycle_sensors and cycle_sensor_poses in the rig's order.
bool Estimator::Impl::CheckCycleSpread(const Scan* scans, int newest) {
  Result& r = result_;
  const AlignmentConfig& a = config_.alignment;
  const double diagonal =
      std::hypot(config_.map.width_cells, config_.map.height_cells) * config_.map.resolution_m;
  for (int index : cycle_order_) {
    const Scan& scan = scans[index];
    const SensorConfig& s = config_.sensors[scan.sensor];
    const Pose2D sensor = SensorPose(scan.pose, s);
    const double mount = std::hypot(s.mount_x_m - config_.rig.reference_x_m,
                                    s.mount_y_m - config_.rig.reference_y_m);
    const double dt = std::abs(scan.timestamp_s - scans[newest].timestamp_s);
    const double limit = std::min(mount + a.max_speed_mps * dt + a.jump_slack_m, diagonal);
    const double d = std::hypot(sensor.x - r.sensor_pose.x, sensor.y - r.sensor_pose.y);
    r.cycle_sensors.push_back(scan.sensor);
    r.cycle_sensor_poses.push_back(sensor);
    if (!(d <= limit)) {
      r.cycle_sensors.clear();
      r.cycle_sensor_poses.clear();
      char text[200];
      std::snprintf(text, sizeof text,
                    "the scan of sensor %d (%s) lies %.6g m from the cycle's reference point, "
                    "more than %.6g m (its mount, the travel in %.3g s, the map)",
                    scan.sensor, s.name.c_str(), d, limit, dt);
      Reject(RejectReason::kPoseJump, text);
      return false;
    }
  }
  return true;
}

// Each scan through its sensor's preprocessor, the sensors in parallel (on at most
// backend.threads threads). False when no scan has a kept echo.
bool Estimator::Impl::PreprocessCycle(const Scan* scans) {
  const int n = int(cycle_order_.size());
  const auto run = [&](int k) {
    const Scan& scan = scans[cycle_order_[k]];
    RigSensor& unit = rig_[scan.sensor];
    unit.stats = ScanStats{};
    unit.has_update = unit.preprocess->Run(scan, &unit.stats);
  };
  if (n == 1) {
    run(0);
  } else {
    rig_arena_.execute([&] { tbb::parallel_for(0, n, run); });
  }
  bool any = false;
  for (int k = 0; k < n; ++k) {
    const RigSensor& unit = rig_[scans[cycle_order_[k]].sensor];
    AddStats(unit.stats, &result_.stats);
    any = any || unit.has_update;
  }
  NoteSilentSensors(scans);
  return any;
}

// Result::cycle_silent_sensors and a message naming them: the rig's sensors without a scan in
// the cycle, or whose scan has no usable echo.
void Estimator::Impl::NoteSilentSensors(const Scan* scans) {
  Result& r = result_;
  const int sensors = config_.sensor_count();
  int scan_of[kMaxSensors];
  std::fill_n(scan_of, sensors, -1);
  for (int index : cycle_order_) scan_of[scans[index].sensor] = index;
  for (int s = 0; s < sensors; ++s) {
    const int index = scan_of[s];
    if (index >= 0 && rig_[std::size_t(s)].has_update) continue;
    r.cycle_silent_sensors.push_back(s);
    char text[200];
    std::snprintf(text, sizeof text, "sensor %d (%s): %s", s, config_.sensors[s].name.c_str(),
                  index < 0                     ? "no scan in this cycle"
                  : scans[index].points.empty() ? "empty scan, no update from it"
                                                : "no usable echo, no update from it");
    AddMessage(&r, text);
  }
}

// Each scan's update from its own sensor's pose in the aligned map: every sensor's motion
// during its sweep (one after the other: the trackers follow the map's resets), then each scan
// deskewed and projected, the sensors in parallel (host work on each sensor's own buffers, its
// time in rasterize_us); then the sensor model's kernels and the fusion in the rig's order, and
// the footprint, while each scan's face layer and, with the mover layer, its comparison with its
// sensor's earlier outline run beside them (SideWorkBeside(); else after them). The veto
// and face layers hold every scan's echoes and faces, the mover layer the cycle's hazard, and
// the polygon mask's margin follows the lines of sight of the scanners that updated the map.
void Estimator::Impl::UpdateMapCycle(const Scan* scans) {
  Result& r = result_;
  const int n = int(cycle_order_.size());
  bool all_swept = true, any_update = false;  // of the scans with something to place
  for (int k = 0; k < n; ++k) {
    const Scan& scan = scans[cycle_order_[k]];
    RigSensor& unit = rig_[scan.sensor];
    unit.swept = SweepMotionOf(&unit.sweep, unit.config.sensor, r.cycle_sensor_poses[k],
                               scan.timestamp_s, &unit.motion);
    if (!unit.has_update) continue;
    any_update = true;
    all_swept = all_swept && unit.swept;
  }
  r.sweep_corrected = any_update && all_swept;

  const Clock::time_point start = Clock::now();
  const double res = config_.map.resolution_m;
  const int width = config_.map.width_cells, height = config_.map.height_cells;
  double newest = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) newest = std::max(newest, scans[cycle_order_[k]].timestamp_s);
  if (movers_.enabled()) StartMovers(newest);
  const auto each_sensor = [&](auto&& work) {
    if (n == 1) {
      work(0);
    } else {
      rig_arena_.execute([&] { tbb::parallel_for(0, n, work); });
    }
  };
  each_sensor([&](int k) {
    const Scan& scan = scans[cycle_order_[k]];
    RigSensor& unit = rig_[scan.sensor];
    if (unit.swept) unit.preprocess->Deskew(unit.motion);
    if (!unit.has_update) return;
    double yaw = 0.0;
    unit.cells = MapCells(r.cycle_sensor_poses[k], r, res, &yaw);  // CheckCycleSpread's pose
    sensor_model_->Project(unit.preprocess.get(), unit.cells, yaw, width, height, &unit.projection,
                           /*faces=*/false);
  });
  const Clock::time_point projected = Clock::now();
  r.times.rasterize_us += Micros(start, projected);

  const auto beside = [&] {
    each_sensor([&](int k) {
      const Scan& scan = scans[cycle_order_[k]];
      RigSensor& unit = rig_[scan.sensor];
      if (!unit.has_update) return;
      unit.preprocess->ProjectFaces(width, height);
      if (movers_.enabled()) {
        movers_.Detect(scan.sensor, r.cycle_sensor_poses[k], scan.timestamp_s,
                       unit.preprocess->beams());
      }
    });
  };
  double apply_us = 0.0;
  const auto apply = [&] {
    const Clock::time_point begin = Clock::now();
    cycle_scanners_.clear();
    for (int k = 0; k < n; ++k) {
      RigSensor& unit = rig_[scans[cycle_order_[k]].sensor];
      if (!unit.has_update) continue;
      cycle_scanners_.push_back(unit.cells);
      sensor_model_->Apply(unit.projection, backend_.get(), &r.times);
    }
    FuseFootprint();
    apply_us = Micros(begin, Clock::now());
  };
  if (SideWorkBeside()) {
    tbb::parallel_invoke(beside, apply);
  } else {
    beside();
    apply();
  }
  r.times.rasterize_us += std::max(0.0, Micros(projected, Clock::now()) - apply_us);

  cycle_echoes_.clear();
  cycle_face_near_.clear();
  cycle_face_seen_.clear();
  for (int k = 0; k < n; ++k) {
    RigSensor& unit = rig_[scans[cycle_order_[k]].sensor];
    if (!unit.has_update) continue;
    const std::vector<std::int32_t>& echoes = unit.preprocess->echo_cells();
    cycle_echoes_.insert(cycle_echoes_.end(), echoes.begin(), echoes.end());
    const std::vector<std::int32_t>& near = unit.preprocess->face_near_cells();
    cycle_face_near_.insert(cycle_face_near_.end(), near.begin(), near.end());
    const std::vector<std::int32_t>& seen = unit.preprocess->face_seen_cells();
    cycle_face_seen_.insert(cycle_face_seen_.end(), seen.begin(), seen.end());
  }
  backend_->SetEchoes(cycle_echoes_.data(), int(cycle_echoes_.size()));
  const std::vector<std::int32_t>& near = MoverCells(cycle_face_near_, newest);
  backend_->SetFaces(near.data(), int(near.size()), cycle_face_seen_.data(),
                     int(cycle_face_seen_.size()));
}

// The footprint rectangle around the reference point, turned with the vehicle, fused as one
// scan that sees it free.
void Estimator::Impl::FuseFootprint() {
  const RigConfig& rig = config_.rig;
  if (rig.footprint_length_m <= 0.0 || rig.footprint_width_m <= 0.0) return;
  const Result& r = result_;
  const double res = config_.map.resolution_m;
  double yaw = 0.0;
  const Vec2 centre = MapCells(r.sensor_pose, r, res, &yaw);
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double hl = 0.5 * rig.footprint_length_m / res, hw = 0.5 * rig.footprint_width_m / res;
  const double corners[4][2] = {{hl, -hw}, {hl, hw}, {-hl, hw}, {-hl, -hw}};
  double ymin = 1e300, ymax = -1e300;
  for (int i = 0; i < 4; ++i) {
    const double x = centre.x() + c * corners[i][0] - s * corners[i][1];
    const double y = centre.y() + s * corners[i][0] + c * corners[i][1];
    footprint_[2 * i] = ToFixed(x);
    footprint_[2 * i + 1] = ToFixed(y);
    ymin = std::min(ymin, y);
    ymax = std::max(ymax, y);
  }
  const int height = config_.map.height_cells;
  RasterJob job;
  job.vertices = footprint_;
  job.vertex_count = 4;
  job.row_begin = std::clamp(int(std::floor(ymin)) - 1, 0, height);
  job.row_end = std::clamp(int(std::ceil(ymax)) + 1, 0, height);
  if (job.row_begin >= job.row_end) return;
  const Clock::time_point start = Clock::now();
  backend_->Rasterize(job);
  const Clock::time_point rastered = Clock::now();
  backend_->Fuse(job.row_begin, job.row_end);
  result_.times.rasterize_us += Micros(start, rastered);
  result_.times.fuse_us += Micros(rastered, Clock::now());
}

const Result& Estimator::Impl::ProcessCycle(const Scan* scans, int count) {
  if (!config_.is_rig() && count == 1 && scans != nullptr) return Process(scans[0]);
  const Clock::time_point t_begin = Clock::now();
  Result& r = result_;
  int newest = 0;
  for (int i = 1; scans != nullptr && i < count; ++i) {
    if (scans[i].timestamp_s > scans[newest].timestamp_s) newest = i;
  }
  Begin(count > 0 && scans != nullptr ? scans[newest] : Scan{});
  const auto finish = [&]() -> const Result& {
    r.times.total_us = Micros(t_begin, Clock::now());
    return r;
  };
  if (!config_.is_rig()) {
    Reject(RejectReason::kBadCycle, count <= 0 || scans == nullptr
                                        ? "an empty cycle: no scan to process"
                                        : "a cycle of several scans needs a rig (a "
                                          "'sensors' list in the config)");
    return finish();
  }
  if (!CheckCycle(scans, count)) return finish();
  for (int i = 0; i < count; ++i) {
    if (CheckInput(scans[i])) continue;
    const int s = scans[i].sensor;
    r.message.insert(0, "the scan of sensor " + std::to_string(s) + " (" +
                            config_.sensors[std::size_t(s)].name + "): ");
    return finish();
  }
  if (!CheckCycleTimes(scans, count, newest)) return finish();
  SensorConfig reference;
  reference.mount_x_m = config_.rig.reference_x_m;
  reference.mount_y_m = config_.rig.reference_y_m;
  r.sensor_pose = SensorPose(scans[newest].pose, reference);
  if (!CheckCycleSpread(scans, newest)) return finish();

  const bool has_update = PreprocessCycle(scans);
  const Clock::time_point t_pre = Clock::now();
  r.times.preprocess_us = Micros(t_begin, t_pre);
  const double previous = circle_.last_timestamp();
  if (!Align(scans[newest])) return finish();
  NoteCycleJitter(scans, count, newest, previous);
  const Clock::time_point t_align = Clock::now();
  r.times.align_us = Micros(t_pre, t_align);

  UpdateMapCycle(scans);
  if (!has_update) {
    r.status = ScanStatus::kNoSensorUpdate;
    AddMessage(&r, "no usable echo in any scan of the cycle: no sensor update");
  }
  return Conclude(t_begin);
}

}  // namespace freespace
