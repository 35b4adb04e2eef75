// Vehicle on a circle for grid maps (paper III, eqs. 1-7): keeps the map axis-aligned with
// the world, moves it by whole cells only, and places the vehicle (the sensor origin) on a
// circle around the map centre whose radius grows with the filtered speed, behind the centre
// when driving forward and in front of it when reversing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "freespace/config.hpp"
#include "freespace/result.hpp"
#include "freespace/types.hpp"

namespace freespace {

// The outcome of aligning one scan.
struct AlignStep {
  bool accepted = false;
  RejectReason reason = RejectReason::kNone;
  bool reset = false;  // the map starts (again) at this scan: clear it
  int shift_x = 0;     // eqs. (4), (5): new(r, c) = old(r + shift_y, c + shift_x)
  int shift_y = 0;
  Vec2 local;                       // eqs. (6), (7): sensor position in the map, cells
  double yaw = 0.0;                 // eq. (2)
  double speed_mps = 0.0;           // S_t, negative when reversing
  double filtered_speed_mps = 0.0;  // eq. (1)
  double radius_m = 0.0;
  Vec2 circle_centre;             // cells
  Vec2 circle_point;              // P_c, cells
  bool timestamp_jitter = false;  // the timestamp was not after the previous one, but within
                                  // alignment.time_jitter_s: used without a speed sample
  bool clock_stalled = false;     // the clock has stalled (kStalledClockScans scans in a row
                                  // with one timestamp): no jump test, no speed sample
  bool stall_detected = false;    // this scan is the one that found the stall
  bool clock_restart = false;     // the map restarts here: the clock stayed behind the latest
                                  // accepted time for reset_after_jumps scans in a row, and
                                  // would take longer to catch up than it has been behind
};

// Scans in a row stamped with the same time after which the clock counts as stalled (logs whose
// timestamps never advance, such as some corrected CARMEN logs).
inline constexpr int kStalledClockScans = 3;

class CircleAligner {
 public:
  explicit CircleAligner(const Config& config);

  // Forgets everything; the next scan starts a new map.
  void Reset();

  // Aligns the map to the sensor's world pose at time t. A rejected step changes nothing;
  // an accepted one commits the new origin and local position.
  AlignStep Align(double t, const Pose2D& sensor);

  // World position (m) of the corner of cell (0, 0), and that origin in whole cells.
  Vec2 origin_world() const;
  std::int64_t origin_x() const { return origin_x_; }
  std::int64_t origin_y() const { return origin_y_; }
  double resolution() const { return resolution_; }
  int consecutive_jumps() const { return jumps_; }
  // Scans in a row rejected as before the latest accepted time, each later than the one before.
  int consecutive_behind() const { return behind_; }
  double last_timestamp() const { return last_t_; }  // the latest accepted scan's
  bool started() const { return started_; }          // a scan has been accepted

 private:
  void Start(double t, const Pose2D& sensor, AlignStep* step);

  AlignmentConfig config_;
  double resolution_;
  Vec2 centre_;  // map centre, cells
  double max_radius_cells_;

  bool started_ = false;
  double last_t_ = 0.0;
  Pose2D last_;
  Vec2 anchor_;  // world position of the origin when origin_x_ = origin_y_ = 0
  std::int64_t origin_x_ = 0;
  std::int64_t origin_y_ = 0;
  std::vector<double> distances_;  // ring buffers of eq. (1): signed displacement and dt
  std::vector<double> intervals_;
  int speed_count_ = 0;
  int speed_next_ = 0;
  int jumps_ = 0;
  int repeats_ = 0;  // scans in a row (accepted or not) stamped last_t_ after the one that was
  int behind_ = 0;   // consecutive_behind(), the first and the last of those scans' times
  double behind_since_ = 0.0, behind_t_ = 0.0;
};

// Angle wrapped to (-pi, pi].
double WrapAngle(double a);

}  // namespace freespace
