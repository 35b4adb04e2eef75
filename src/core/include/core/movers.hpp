// The mover layer of the conservative polygon (polygon.mover_memory_s): the vehicles the scans
// saw moving, followed while they are out of sight, so that the polygon does not hold the place a
// vehicle the scanners no longer see has driven into (docs/design.md). Host work on each scan's
// outline (Preprocessor::beams()), in the world frame; its cells join the face layer's near ones.
//
// Detection: each scan is compared with the same sensor's outline (full-scan polygon) lag_s
// earlier. An echo lying well inside the earlier outline came nearer (the place was seen free); an
// earlier echo now lying well inside this outline went away, and the beams beside it, which now
// see past, count as moving too. Consecutive real beams joined as the clutter filter joins
// neighbours (doubled) form runs (surfaces); a run with kMinMovingBeams moving beams is an
// observation, and it can start a track when at least kMinMovingShare of its beams move.
//
// Tracking: an observation joins the track whose last observation, moved on by the track's
// velocity, lies within a gate of it. The velocity is measured between the new observation and
// the oldest of the last kVelocityWindowS: from the motion of the run's ends that are ends of the
// object in both (the beam beyond sees farther or nothing, not the aperture's edge or a nearer
// surface: the part in sight may grow or shrink), refined by registering the two point sets; where
// no motion fits clearly better than none (a wall matches itself along its length) the shift
// registered from none is taken (about zero), and without a shared end nothing is measured. The
// velocity is measured between one sensor's observations. A track observed in kMinHits cycles and
// at least min_speed_mps fast is a mover.
//
// Hazard: every mover until memory_s after its last observation: the points of its observations
// within kKeepS of its newest, each moved on by the velocity to now and widened by dilation_m plus
// speed_sigma_mps per second since it was taken, as map cells, less the cells the cycle's scans
// see free now (inside their outlines): those hold no vehicle, or its echoes would show.
#pragma once

#include <cmath>
#include <cstdint>
#include <deque>
#include <vector>

#include "freespace/config.hpp"
#include "freespace/types.hpp"

namespace freespace {

struct Beam;

struct MoverRule {
  double memory_s = 0.0;  // polygon.mover_memory_s; 0: no mover layer
  double lag_s = 0.2;     // a scan is compared with the same sensor's outline this much older
  // An echo is moving when it lies this far inside the older outline (plus two beam spacings at
  // its range).
  double tolerance_m = 0.3;
  // Beams join into one surface within join_m + join_per_m * range: the clutter filter's
  // neighbourhood (clutter.eps_m, eps_per_m), doubled.
  double join_m = 0.4;
  double join_per_m = 0.02;
  double max_extent_m = 25.0;    // a longer run is no vehicle
  double dilation_m = 0.8;       // how far around a predicted point the hazard reaches
  double speed_sigma_mps = 1.0;  // and how much farther each second since it was seen
  double min_speed_mps = 1.0;    // slower tracks are no movers
  double bin_width_rad = 0.0;    // the sensors' angular resolution (the coarsest of a rig)
  bool parallel = false;         // detection's two passes at once (backend.threads 0: all cores)

  // The rule `config` sets: memory 0 unless polygon.shape is inside.
  static MoverRule Of(const Config& config);
};

inline constexpr int kSpread = 2;  // InsideOutline()'s spread in detection
inline constexpr int kMinMovingBeams = 5;
inline constexpr double kMinMovingShare = 0.3;
inline constexpr int kMinHits = 6;
inline constexpr double kMinMatchedShare = 0.5;  // of an observation's echoes, to join a track
inline constexpr double kVelocityWindowS = 0.5;
inline constexpr double kKeepS = 1.5;
inline constexpr double kStoreS = 0.1;

// Where the map lies in the world: cell (col, row) covers origin + R(yaw) [col, col + 1) x
// [row, row + 1) * resolution.
struct MapFrame {
  Vec2 origin = Vec2::Zero();
  double yaw = 0.0;
  double resolution_m = 0.2;
  int width = 0;
  int height = 0;
};

// Points in an outline's sensor frame: (x, y) and their angle FastAtan2(float(y), float(x)), as
// InsideOutline() takes them (ToOutlineFrame()), for many points in one pass.
struct OutlineFrame {
  std::vector<double> x, y;
  std::vector<float> angle;
};

class MoverTracker {
 public:
  explicit MoverTracker(const MoverRule& rule) : rule_(rule) {}

  bool enabled() const { return rule_.memory_s > 0.0; }

  // Starts a cycle at time t: forgets tracks unseen for longer than memory_s and the outlines
  // of the last cycle's view.
  void BeginCycle(double t);
  // One scan of sensor `sensor` (0 .. kMaxSensors - 1) taken from world pose `pose` at time t,
  // its beams in the sensor frame (Preprocessor::beams(), deskewed): its outline and what moved
  // since the sensor's outline lag_s earlier. Scans of different sensors may be detected at
  // once (each touches only its sensor's state); Commit() then takes them in.
  void Detect(int sensor, const Pose2D& pose, double t, const std::vector<Beam>& beams);
  // The scans detected since the last Commit(), in sensor order: their observations join the
  // tracks, their outlines the history and this cycle's view.
  void Commit();
  // Detect() and Commit() of one scan.
  void Observe(int sensor, const Pose2D& pose, double t, const std::vector<Beam>& beams) {
    Detect(sensor, pose, t, beams);
    Commit();
  }
  // Appends the hazard cells at time t (row * width + col, inside the map, no repeats).
  void Hazard(double t, const MapFrame& frame, std::vector<std::int32_t>* cells);
  void Clear();

  int tracks() const { return int(tracks_.size()); }
  // The tracks that count as movers (kMinHits observations, speed >= min_speed_mps), and their
  // velocities (world, m/s).
  int movers() const;
  std::vector<Vec2> mover_velocities() const;

  // A scan's outline in the world frame, for the inside test.
  struct Outline {
    Pose2D pose;
    double cos_yaw = 1.0, sin_yaw = 0.0;
    double t = 0.0;
    std::vector<float> angle;  // sensor frame, ascending (FastAtan2)
    std::vector<float> range;
    std::vector<Vec2> world;          // the beam's point in the world
    std::vector<std::uint32_t> beam;  // index into the scan's beams
    std::vector<std::uint8_t> real;   // a real beam's (not virtual)
  };

  // One run of beams taken for a mover.
  struct Observation {
    double t = 0.0;
    int sensor = 0;
    std::vector<Vec2> points;  // world
    Vec2 centroid = Vec2::Zero();
    Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();  // bounding box
    // The run's first and last point, and whether each is an end of the object's outline (the
    // beam beyond it sees farther or nothing) rather than where the aperture or a nearer
    // surface cuts it off.
    Vec2 ends[2] = {Vec2::Zero(), Vec2::Zero()};
    bool true_end[2] = {false, false};
    // Enough of its echoes move (kMinMovingShare) to start a track; a run with fewer only joins
    // one.
    bool strong = false;
  };

 private:
  struct Track {
    // Oldest first, one each kStoreS of each sensor, within kKeepS of the newest.
    std::deque<Observation> seen;
    Vec2 velocity = Vec2::Zero();
    bool measured = false;  // the velocity has been measured once
    int hits = 0;           // cycles with an observation
    std::uint64_t last_cycle = 0;
  };
  // A track is a hazard when it was observed this often and moves this fast.
  bool Moving(const Track& track) const;

  // A sensor's scan between Detect() and Commit().
  struct Pending {
    bool ready = false;
    Outline outline;
    std::vector<Observation> found;
    std::vector<Vec2> points;         // the scan's beams in the world
    std::vector<float> angle, range;  // the beams' FastAtan2 angles and ranges, sensor frame
    OutlineFrame near, away;          // this scan's points in the reference's frame and the reverse
  };
  // The runs of this scan (`pending`'s outline and points, `beams`) with moving echoes: echoes
  // inside the reference outline (the object came nearer), and echoes where the reference's echo
  // now lies inside this outline (the object went away).
  void FindMoving(const Outline& reference, const std::vector<Beam>& beams, Pending* pending) const;
  void Associate(std::vector<Observation>* found);
  void Join(Track* track, Observation o);
  bool InView(const Vec2& p) const;

  MoverRule rule_;
  std::deque<Outline> history_[kMaxSensors];  // per sensor, oldest first
  std::vector<int> view_;  // the sensors of this cycle's outlines (each its history's newest)
  std::vector<Track> tracks_;
  Pending pending_[kMaxSensors];
  std::uint64_t cycle_ = 0;           // Commit()s so far
  std::vector<std::uint64_t> marks_;  // Hazard(): cells already listed, a bit each
};

// atan2 to within 1e-5 rad, at a fraction of its cost: the outlines' angles and their look-ups.
inline float FastAtan2(float y, float x) {
  // atan on [-1, 1] by an odd polynomial (error below 1e-5), then the octant; selects rather
  // than branches, so that a loop over many points can run several at once (the mover layer's
  // passes over a scan, movers.cpp and mover_outline.cpp).
  const float ax = std::abs(x), ay = std::abs(y);
  const bool steep = ay > ax, origin = (ax == 0.0f) & (ay == 0.0f);
  const float z = (steep ? ax : ay) / (steep ? ay : (origin ? 1.0f : ax)), z2 = z * z;
  float a = z * (0.9998660f +
                 z2 * (-0.3302995f + z2 * (0.1801410f + z2 * (-0.0851330f + z2 * 0.0208351f))));
  a = steep ? 1.57079633f - a : a;
  a = x < 0.0f ? 3.14159265f - a : a;
  a = y < 0.0f ? -a : a;
  return origin ? 0.0f : a;
}

// Whether world point p lies inside `outline` by more than `margin` metres along its beam: nearer
// than the two beams on either side of its angle and `spread` more on each side (so that a
// point at an object's silhouette, which the next beam passes, is not inside). `*at`, when given,
// is where the search for p's angle starts (the last call's answer for the previous point of a
// scan), and is set to the index of the outline's first beam after p's angle when p lies within
// the outline's angles.
bool InsideOutline(const MoverTracker::Outline& outline, const Vec2& p, double bin_width_rad,
                   double margin, int spread = 0, std::size_t* at = nullptr);

// `points` (world) in the sensor frame of `outline`, into `frame` (one entry per point).
void ToOutlineFrame(const MoverTracker::Outline& outline, const std::vector<Vec2>& points,
                    OutlineFrame* frame);
// InsideOutline() of point k of `frame`.
bool InsideOutlineAt(const MoverTracker::Outline& outline, const OutlineFrame& frame, std::size_t k,
                     double bin_width_rad, double margin, int spread, std::size_t* at);

}  // namespace freespace
