// What the estimator returns for one scan (Result: status, poses, map placement, the
// free-space polygon, stage times) and the read-only view of its map (MapView).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "freespace/types.hpp"

namespace freespace {

enum class ScanStatus {
  kOk,              // the map was updated and the polygon extracted
  kNoSensorUpdate,  // no usable return (empty scan, every beam without echo): the map was
                    // aligned and the polygon extracted, but no cell was updated
  kRejected,        // the scan was not used at all (see RejectReason); nothing changed
};

enum class RejectReason {
  kNone,
  kTimestampNotFinite,
  kTimestampNotIncreasing,  // before the latest accepted timestamp by more than time_jitter_s
  kPoseNotFinite,
  kTimestampOutOfRange,  // |t| > kMaxTimestampS (freespace/scan.hpp)
  kPoseOutOfRange,       // |x| or |y| > kMaxCoordinateM, or a map shift no integer can hold
  kPoseJump,             // moved farther than max_speed_mps * dt + jump_slack_m since the last scan
  kBadCycle,             // a rig's cycle with no scan, a sensor index not in the rig, or one
                         // sensor twice (Estimator::ProcessCycle)
};

// What became of the free-space polygon of a scan.
enum class PolygonStatus {
  kOk,           // the polygon holds the free space around the sensor
  kNoFreeSpace,  // nothing around the sensor is free (yet): the polygon is empty
  kNone,         // the scan was rejected: no polygon
};

// What preprocessing saw and did, in points (beams) of this scan.
struct ScanStats {
  int points = 0;           // beams in the scan
  int echoes = 0;           // valid echoes before the clutter filter
  int no_echo = 0;          // beams without echo (flagged, or range >= max - margin, or +inf)
  int invalid_range = 0;    // NaN, negative, -inf or below min_range: treated as no echo
  int out_of_aperture = 0;  // angle outside the sensor aperture (or not finite): dropped
  int bad_layer = 0;        // layer >= sensor.layers: dropped
  int clutter = 0;          // echoes removed by DBSCAN
  int kept = 0;             // echoes marked occupied
  int beams = 0;            // angular bins of the full-scan polygon
  int virtual_points = 0;   // bins closed by a virtual point
};

// Microseconds spent per stage for this scan (wall clock on the host; OpenCL event times for
// the kernel stages on the OpenCL backend, which folds the map shift and the fusion into the
// row pass of stage 1: see docs/opencl.md).
struct StageTimes {
  double preprocess_us = 0;  // validation, DBSCAN, virtual points, the sweep, projection
  double align_us = 0;       // vehicle on a circle, including the map shift (host backend)
  double rasterize_us = 0;   // kernel stage 1
  double fuse_us = 0;        // kernel stage 2 (OpenCL: with stage 1's row pass and the shift)
  double classify_us = 0;    // kernel stage 3: hysteresis + opening
  double mask_us = 0;        // kernel stage 3b (polygon.shape inside): the polygon mask
  double insight_us = 0;     // kernel stage 4: border rays, C_Edge
  double polygon_us = 0;     // capped Douglas-Peucker, world coordinates
  double total_us = 0;
};

// One Process() or ProcessCycle() call's result. A rejected call (status kRejected) changes
// nothing; of its result, scan_index, timestamp_s, status, reject_reason, message, pose, stats
// (what the preprocessing counted, zero when the input check rejected it) and the empty polygons
// (polygon_status kNone) are the call's own; sensor_pose and the cycle's sensor poses are the
// call's only as far as it got before the rejection (read them as undefined); the map's fields
// (vehicle_cells, yaw, map_yaw, vehicle_cell, origin, the speed and the circle) are the last
// accepted call's.
struct Result {
  std::uint64_t scan_index = 0;  // 0-based count of Process() calls
  double timestamp_s = 0.0;
  ScanStatus status = ScanStatus::kOk;
  RejectReason reject_reason = RejectReason::kNone;
  std::string message;            // why a scan was rejected or not used, and what was odd about
                                  // it (clock jitter, a stall), joined by "; "; else empty
  bool map_reset = false;         // the map was (re)started at this scan (first scan, pose
                                  // jumps, or a clock that stayed behind: docs/behaviour.md)
  bool timestamp_jitter = false;  // timestamp not after the latest accepted one, but within
                                  // alignment.time_jitter_s: used (the newest scan of the call
                                  // without a speed sample); `message` names it
  bool clock_stalled = false;     // the timestamps have stopped advancing (3 scans or more with
                                  // one time): used without a jump test or a speed sample
  bool stall_detected = false;    // this scan found the stall; `message` says so
  bool sweep_corrected = false;   // sensor.sweep_s set and every scan of this call with a usable
                                  // echo (one at least) placed from the sensor's motion during
                                  // its sweep (not the first scan of a map, nor one more than
                                  // 0.5 s after its sensor's last)

  // alignment.scan_match: the map is kept in the input poses' frame corrected by this pose (a
  // point p of the input frame lies at pose_correction composed with p in the map's frame), as
  // of the end of this scan; identity when off. The world positions below (sensor_pose, origin,
  // map_yaw) and the polygon are in the input poses' frame either way, so map_yaw is the
  // correction's rotation, not 0, when it is on.
  Pose2D pose_correction;
  bool pose_matched = false;  // this scan's echoes corrected the heading (alignment.scan_match)

  Pose2D pose;           // the vehicle pose given with the scan (a rig: the newest scan's)
  Pose2D sensor_pose;    // the sensor's world pose (pose composed with the mount); with a rig,
                         // the reference point's (rig.reference_*), which stands for the sensor
                         // in the fields below
  Vec2 vehicle_cells;    // sensor position in the map, cells, fractional (eqs. 6, 7)
  double yaw = 0.0;      // sensor yaw in the map (eq. 2), radians
  double map_yaw = 0.0;  // rotation of the map's axes from the world's: 0 with the circle
                         // alignment (the correction's with alignment.scan_match), the
                         // sensor's yaw with alignment.kind rotate
  CellIndex vehicle_cell;
  Vec2 origin;                     // world position (m) of the corner of cell (0, 0)
  std::int64_t origin_cell_x = 0;  // origin in whole cells from the map's anchor
  std::int64_t origin_cell_y = 0;
  double filtered_speed_mps = 0.0;  // eq. (1); negative when reversing
  double circle_radius_m = 0.0;
  Vec2 circle_centre_cells;  // centre of the vehicle position circle, cells

  // The free-space polygon, counter-clockwise, at least three and at most
  // polygon.max_vertices distinct vertices, in world metres and in map cells (continuous: cell
  // (r, c) spans [c, c+1) x [r, r+1)); empty unless polygon_status is kOk.
  PolygonStatus polygon_status = PolygonStatus::kNone;
  std::vector<Vec2> polygon;
  std::vector<Vec2> polygon_cells;
  // C_Edge: the in-sight edge cells in label order (with polygon.shape paper, the unsimplified
  // polygon's vertices; with inside, the cells where the exact rays stopped).
  std::vector<CellIndex> edge_cells;
  double simplification_error_m = 0.0;  // largest distance of a dropped ring vertex
  bool polygon_contains_vehicle = false;

  ScanStats stats;   // a rig's cycle: summed over its scans
  StageTimes times;  // a rig's cycle: rasterize and fuse summed over its scans (wall clock)
  // A rig's cycle (Estimator::ProcessCycle): its scans' sensor indices and world sensor poses,
  // in the order fused (the rig's order). One entry for a single sensor.
  std::vector<int> cycle_sensors;
  std::vector<Pose2D> cycle_sensor_poses;
  // A rig's accepted cycle (a `sensors` list, one entry too): the rig's sensors that added
  // nothing to the map, in the rig's order: no scan of theirs in the cycle, or a scan without a
  // usable echo (empty, or every beam without echo); `message` names them. Empty for a single
  // `sensor`, whose status says so.
  std::vector<int> cycle_silent_sensors;
};

// A read-only view of the map as of the last Process(). Pointers stay valid until the next
// call to Process(), Reset() or map(); row-major, row 0 southern, index = row * width + col.
struct MapView {
  int width = 0;
  int height = 0;
  double resolution_m = 0.0;
  Vec2 origin;           // world position of the corner of cell (0, 0)
  double map_yaw = 0.0;  // rotation of the map's axes (Result::map_yaw: 0 but for alignment rotate
                         // and alignment.scan_match)
  const LogOdds* log_odds = nullptr;   // fused log-odds (kLogOddsScale units)
  const std::uint8_t* free = nullptr;  // 1 where classified free after opening, else 0

  double Probability(int row, int col) const;
};

const char* ToString(ScanStatus status);
const char* ToString(RejectReason reason);
const char* ToString(PolygonStatus status);

}  // namespace freespace
