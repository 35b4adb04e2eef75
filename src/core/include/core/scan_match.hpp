// Heading correction from the scans (not in the paper): the small rotation of the odometry's
// sensor pose about the sensor that lays this scan's echoes onto the occupied cells the map
// already holds, so that a drifting heading (a gyro's yaw-rate bias, which does most of an
// odometry's harm to the map) does not smear the map and move its remembered free space onto
// what the car passed. Gauss-Newton on the map's settled occupied evidence, bilinearly
// interpolated. Runs on the host on the map both backends hold bit-identical, so the correction
// and everything after it stay identical too. The position is left to the odometry: matched on
// these one-cell-thick occupied faces it wanders more than a 0.5 % distance error does.
#pragma once

#include <cstddef>
#include <vector>

#include "core/dbscan.hpp"
#include "freespace/result.hpp"
#include "freespace/types.hpp"

namespace freespace {

struct MatchResult {
  bool applied = false;      // false: too few echoes near settled occupied cells, or no better fit
  int points = 0;            // echoes that took part at the given pose
  double dyaw = 0.0;         // the rotation of the sensor pose about its position, radians
  double cost_before = 0.0;  // mean squared misfit (0: every echo on a certain-occupied cell)
  double cost_after = 0.0;
  double std_rad = 0.0;  // the rotation's standard error (misfit over the curvature)
};

class ScanMatcher {
 public:
  // A correction is bounded by max_step_rad; `l_max` is the map's upper clamp (a cell there is
  // certainly occupied).
  ScanMatcher(double max_step_rad, LogOdds l_max);

  // The rotation of `sensor` (world) that best lays `echoes` (sensor frame; every k-th when
  // there are more than kMaxPoints) onto the occupied cells of `map` (its log-odds, in the
  // frame of its origin and map_yaw).
  MatchResult Match(const MapView& map, const std::vector<EchoPoint>& echoes,
                    const Pose2D& sensor) const;

  // Fewest echoes near settled occupied cells a correction is taken from.
  static constexpr int kMinPoints = 30;
  static constexpr int kIterations = 2;
  static constexpr std::size_t kMaxPoints = 512;

 private:
  struct Sums {
    double h = 0.0;  // sum of J^2
    double g = 0.0;  // sum of J * residual
    int points = 0;
  };
  // Mean misfit of the echoes at the sensor pose `at`, and (with sums) the normal equation.
  double Evaluate(const MapView& map, const std::vector<EchoPoint>& echoes, const Pose2D& at,
                  Sums* sums) const;

  double max_step_rad_;
  LogOdds l_max_;
};

// How much of each match a scan takes (alignment.heading_drift_dps): a scalar Kalman filter on
// the heading's error. Its variance after the last applied match grows by the square of the
// drift the odometry may have made since then (a yaw-rate bias turns the heading in proportion
// to the time, however many scans or failed matches lie between); a match whose own variance
// is (kMisfitCorrelation x its standard error)^2 takes the share variance / (variance + its
// own), and the variance shrinks by that share.
class HeadingFilter {
 public:
  // The misfits of neighbouring echoes are not independent (one face, one quantization): a
  // match's rotation errs about 3 times its standard error from the misfit and the curvature
  // (with exact odometry on a simulated car-park drive the matched rotations spread 3.4 times
  // their median standard error).
  static constexpr double kMisfitCorrelation = 3.0;

  explicit HeadingFilter(double drift_rad_per_s) : drift_rad_per_s_(drift_rad_per_s) {}

  // A heading exact by definition at time t (a cleared map, the first scan).
  void Reset(double t) {
    variance_ = 0.0;
    t_ = t;
  }
  // The share of a match with standard error `match_std_rad` at time t that the heading
  // takes, in [0, 1]; the filter then counts the match as applied. A time before the last one
  // adds no drift and does not move the filter's time back. A match of no error at all, on a
  // heading of no error, is not taken (0).
  double Share(double match_std_rad, double t);

  double variance() const { return variance_; }  // rad^2, after the last applied match
  double time() const { return t_; }             // of the last applied match or reset

 private:
  double drift_rad_per_s_;
  double variance_ = 0.0;
  double t_ = 0.0;
};

}  // namespace freespace
