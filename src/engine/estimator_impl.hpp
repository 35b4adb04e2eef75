// The estimator's inside (freespace/estimator.hpp keeps it behind a pointer): the stages of
// DESIGN.md's pipeline, each behind the interface chosen once from the config.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/alignment.hpp"
#include "core/backend.hpp"
#include "core/crew.hpp"
#include "core/movers.hpp"
#include "core/preprocess.hpp"
#include "core/scan_match.hpp"
#include "core/sweep.hpp"
#include "core/thread_arena.hpp"
#include "engine/map_aligner.hpp"
#include "freespace/estimator.hpp"
#include "polygon_extractor.hpp"
#include "sensor_model.hpp"

namespace freespace {

// The sensor's world pose: the odometry pose composed with the mount.
inline Pose2D SensorPose(const Pose2D& pose, const SensorConfig& s) {
  const double cy = std::cos(pose.yaw), sy = std::sin(pose.yaw);
  Pose2D sensor;
  sensor.x = pose.x + cy * s.mount_x_m - sy * s.mount_y_m;
  sensor.y = pose.y + sy * s.mount_x_m + cy * s.mount_y_m;
  sensor.yaw = WrapAngle(pose.yaw + s.mount_yaw_deg * M_PI / 180.0);
  return sensor;
}

// Adds `text` to the result's message: one scan can be both a clock's jitter and a scan with
// no usable echo, and each is said.
inline void AddMessage(Result* r, const char* text) {
  if (!r->message.empty()) r->message += "; ";
  r->message += text;
}

class Estimator::Impl {
 public:
  explicit Impl(const Config& config);

  const Result& Process(const Scan& scan);
  const Result& ProcessCycle(const Scan* scans, int count);
  void Reset();
  MapView map() const;
  // The map's frame and log-odds (the backend's own on the host, or read back into
  // map_mirror_), without the free mask.
  MapView LogOddsView() const;

  const Config& config() const { return config_; }
  const Backend& backend() const { return *backend_; }

 private:
  // The steps of Process(), in order. Each false return ends the scan (rejected).
  void Begin(const Scan& scan);
  bool CheckInput(const Scan& scan);
  bool Align(const Scan& scan);
  // alignment.scan_match (pose_correction.cpp): the odometry pose in the corrected frame, and
  // after Align() this scan's correction from the map (before the map's update).
  static ScanMatcher MakeMatcher(const Config& config);
  Pose2D Corrected(const Pose2D& odometry) const;
  void MatchPose(bool has_update);
  void Turn(double angle);
  // The result's world positions (origin, map_yaw, sensor poses; the polygon after it) from the
  // corrected frame the map is kept in to the frame of the input poses.
  void ToInputFrame();
  void UpdateMap(bool has_update, const Scan& scan);
  // Whether the side work of a map update (the mover layer's detection, the face layer) runs
  // beside the update: with backend.threads 0, unless the kernels run on the host's cores on
  // threads of their own.
  bool SideWorkBeside() const;
  // polygon.mover_memory_s: a cycle of the mover layer at time t (forgotten on a map reset),
  // before its scans' MoverTracker::Detect(); then their observations to the tracks and the
  // hazard at time t with the face layer's `near` cells into hazard_: the cells the polygon mask
  // keeps out (`near` itself when the layer is off).
  void StartMovers(double t);
  const std::vector<std::int32_t>& MoverCells(const std::vector<std::int32_t>& near, double t);
  // The face layer of the scan at faces_t_ with the mover layer's hazard to the backend.
  void SetFaceLayer();
  void ClassifyAndScan();
  void ExtractPolygon();
  // Classification, border rays and polygon, then the times; ends every accepted scan or cycle.
  const Result& Conclude(std::chrono::steady_clock::time_point t_begin);
  const Result& Reject(RejectReason reason, const char* text);
  // sensor.sweep_s: the sensor's motion during this scan from its tracker (forgotten on a map
  // reset), and the tracker told this scan's pose; false when there is no motion to correct.
  bool SweepMotionOf(SweepTracker* tracker, const SensorConfig& sensor, const Pose2D& sensor_pose,
                     double t, SweepMotion* motion);
  // The same, and the preprocessed scan deskewed with it (its time in preprocess_us).
  bool Sweep(Preprocessor* preprocess, SweepTracker* tracker, const SensorConfig& sensor,
             const Pose2D& sensor_pose, double t);

  // A rig's cycle (rig_cycle.cpp): checks, each sensor's preprocessing (in parallel), then each
  // scan's update from its own sensor pose and the footprint.
  struct RigSensor {
    Config config;  // the estimator's, with `sensor` this sensor
    std::unique_ptr<Preprocessor> preprocess;
    ScanStats stats;
    bool has_update = false;
    SweepTracker sweep;  // sensor.sweep_s: this sensor's last accepted pose
    // This cycle's motion during the sweep (when `swept`), the sensor's map cells and the
    // scan's projection into the map.
    SweepMotion motion;
    bool swept = false;
    Vec2 cells;
    ScanProjection projection;
  };
  void MakeRig();
  bool CheckCycle(const Scan* scans, int count);
  bool CheckCycleTimes(const Scan* scans, int count, int newest);
  bool CheckCycleSpread(const Scan* scans, int newest);
  bool PreprocessCycle(const Scan* scans);
  void NoteSilentSensors(const Scan* scans);
  void NoteCycleJitter(const Scan* scans, int count, int newest, double previous);
  void UpdateMapCycle(const Scan* scans);
  void FuseFootprint();

  Config config_;
  std::unique_ptr<Backend> backend_;
  std::unique_ptr<Crew> crew_;  // the backend's helpers, if it wants any (Backend::WantedCrew)
  std::unique_ptr<Preprocessor> preprocess_;
  CircleAligner circle_;
  std::unique_ptr<MapAligner> aligner_;
  std::unique_ptr<SensorModel> sensor_model_;
  std::unique_ptr<PolygonExtractor> polygon_;
  Result result_;
  std::uint64_t scans_ = 0;
  Pose2D last_sensor_;          // sensor pose of the last accepted scan
  SweepTracker sweep_;          // the same, for sensor.sweep_s
  std::vector<RigSensor> rig_;  // a rig's sensors (empty for a single sensor)
  // Their parallel loops: in the caller's arena, or in one of backend.threads (a rig only).
  ThreadArena rig_arena_{0};
  std::vector<int> cycle_order_;               // the cycle's scans by sensor index
  std::vector<std::int32_t> cycle_echoes_;     // echo cells of every scan of the cycle
  std::vector<std::int32_t> cycle_face_near_;  // the face layer of every scan of the cycle:
  std::vector<std::int32_t> cycle_face_seen_;  // near, seen
  MoverTracker movers_;                        // polygon.mover_memory_s
  std::vector<std::int32_t> hazard_;           // its cells and the face layer's near ones
  bool faces_pending_ = false;                 // this scan's face layer waits for ClassifyAndScan()
  double faces_t_ = 0.0;              // the time of the scan whose face layer SetFaceLayer() sets
  std::vector<Vec2> cycle_scanners_;  // map cells of the cycle's scanners with an update
  std::int32_t footprint_[8] = {};    // the footprint's corners, fixed point
  ScanMatcher matcher_;               // alignment.scan_match
  Pose2D correction_;                 // of the odometry's frame (Result::pose_correction)
  HeadingFilter heading_;             // the share of each match (alignment.heading_drift_dps)
  bool map_has_scans_ = false;        // a scan updated the map since it was last cleared
  mutable std::vector<LogOdds> map_mirror_;
  mutable std::vector<std::uint8_t> free_mirror_;
};

}  // namespace freespace
