// sensor.sweep_s: the constant twist between two poses, a point moved by it, a scan of a
// straight wall taken by a moving, turning sensor that lies straight again once each point is
// placed from where the sensor was, and when the estimator says it did so.
#include "core/sweep.hpp"

#include <cmath>

#include "core/preprocess.hpp"
#include "freespace/estimator.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

// The pose after `t` seconds of the constant twist (vx, 0, w) from the origin.
Pose2D Twist(double vx, double w, double t) {
  Pose2D p;
  p.yaw = w * t;
  p.x = vx * std::sin(w * t) / w;
  p.y = vx * (1.0 - std::cos(w * t)) / w;
  return p;
}

TEST(Sweep, TrackerGivesTheTwistBetweenTwoPoses) {
  SweepTracker tracker;
  SweepMotion m;
  const Pose2D start{3.0, -2.0, 0.7};
  EXPECT_FALSE(tracker.Motion(start, 0.0, 70.0, &m));  // nothing remembered yet
  tracker.Remember(start, 10.0);
  // 12 m/s forward while turning at 0.4 rad/s, for 40 ms, seen from a turned start pose.
  const Pose2D step = Twist(12.0, 0.4, 0.04);
  const double c = std::cos(start.yaw), s = std::sin(start.yaw);
  const Pose2D now{start.x + c * step.x - s * step.y, start.y + s * step.x + c * step.y,
                   start.yaw + step.yaw};
  ASSERT_TRUE(tracker.Motion(now, 10.04, 70.0, &m));
  EXPECT_NEAR(m.vx, 12.0, 1e-3);
  EXPECT_NEAR(m.vy, 0.0, 1e-9);
  EXPECT_NEAR(m.yaw_rate, 0.4, 1e-9);

  EXPECT_FALSE(tracker.Motion(now, 10.0, 70.0, &m));                         // not after it
  EXPECT_FALSE(tracker.Motion(now, 10.0 + kMaxSweepGapS + 1e-3, 70.0, &m));  // too long ago
  EXPECT_FALSE(tracker.Motion(now, 10.04, 10.0, &m));  // 12 m/s above a 10 m/s limit
  tracker.Forget();
  EXPECT_FALSE(tracker.Motion(now, 10.04, 70.0, &m));
}

TEST(Sweep, PointTakenLaterIsPlacedInTheFrameAtTheTimestamp) {
  // The sensor is at the origin at tau = 0 and moves by the twist; a world point seen at tau
  // from there comes back to its world position.
  const SweepMotion m{15.0, 0.0, 0.5};
  const double tau = 0.008;
  const Pose2D p = Twist(15.0, 0.5, tau);
  const double wx = 9.0, wy = 4.0;
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  float x = float(c * (wx - p.x) + s * (wy - p.y));
  float y = float(-s * (wx - p.x) + c * (wy - p.y));
  EXPECT_GT(std::hypot(x - wx, y - wy), 0.1);  // as the paper places it: off by 12 cm
  SweepPoint(m, tau, &x, &y);
  EXPECT_NEAR(x, wx, 1e-5);
  EXPECT_NEAR(y, wy, 1e-5);
}

// A scan of the wall x = 10 m (world) by a sensor that is at the origin, heading along +x, at
// the scan's timestamp and moves at `vx` m/s turning at `w` rad/s; its beam crosses -40 .. 40
// deg in `sweep_s`.
Scan WallScan(double vx, double w, double sweep_s) {
  Scan scan;
  for (int i = 0; i <= 80; ++i) {
    const double deg = -40.0 + i;
    const double tau = sweep_s * (i / 80.0 - 0.5);
    const Pose2D p = Twist(vx, w, tau);
    const double a = p.yaw + deg * M_PI / 180.0;
    ScanPoint point;
    point.angle_rad = float(deg * M_PI / 180.0);
    point.range_m = float((10.0 - p.x) / std::cos(a));
    scan.points.push_back(point);
  }
  return scan;
}

Config WallSensor(double sweep_s) {
  Config c;
  c.sensor.layers = 1;
  c.sensor.min_angle_deg = -40;
  c.sensor.max_angle_deg = 40;
  c.sensor.angular_resolution_deg = 1;
  c.sensor.max_range_m = 50;
  c.sensor.sweep_s = sweep_s;
  c.clutter.enabled = false;
  return c;
}

double WorstOffWall(const Preprocessor& pre) {
  double worst = 0.0;
  for (const EchoPoint& e : pre.kept()) worst = std::max(worst, std::abs(e.x - 10.0));
  for (const Beam& b : pre.beams()) worst = std::max(worst, std::abs(b.x - 10.0));
  return worst;
}

TEST(Sweep, AWallScannedWhileMovingLiesStraightOnceDeskewed) {
  const Scan scan = WallScan(25.0, 0.3, 0.016);
  ScanStats stats;
  Preprocessor as_paper(WallSensor(0.016));
  ASSERT_TRUE(as_paper.Run(scan, &stats));
  ASSERT_EQ(stats.kept, 81);
  EXPECT_GT(WorstOffWall(as_paper), 0.15);  // 25 m/s x 8 ms at the aperture's edges

  Preprocessor deskewed(WallSensor(0.016));
  ASSERT_TRUE(deskewed.Run(scan, &stats));
  deskewed.Deskew(SweepMotion{25.0, 0.0, 0.3});
  EXPECT_LT(WorstOffWall(deskewed), 1e-4);

  // sweep_s 0: Deskew leaves the scan as the paper places it.
  Preprocessor off(WallSensor(0.0));
  ASSERT_TRUE(off.Run(scan, &stats));
  off.Deskew(SweepMotion{25.0, 0.0, 0.3});
  EXPECT_EQ(WorstOffWall(off), WorstOffWall(as_paper));
}

TEST(Sweep, EstimatorSaysWhichScansItPlacedFromTheSweep) {
  const Scan wall = WallScan(0.0, 1.0, 0.0);  // a static sensor's scan, for a valid input
  const auto run = [&](double sweep_s) {
    Config c = WallSensor(sweep_s);
    c.backend.kind = BackendKind::kTbb;
    c.backend.threads = 1;
    Estimator estimator(c);
    std::vector<bool> corrected;
    for (const double t : {0.0, 0.04, 0.08, 0.7, 0.74}) {
      Scan scan = wall;
      scan.timestamp_s = t;
      scan.pose = {5.0 * t, 0.0, 0.0};
      const Result& r = estimator.Process(scan);
      EXPECT_EQ(r.status, ScanStatus::kOk) << r.message;
      corrected.push_back(r.sweep_corrected);
    }
    return corrected;
  };
  // The first scan has no motion yet, and 0.62 s after the last one is too long a gap.
  EXPECT_EQ(run(0.016), (std::vector<bool>{false, true, true, false, true}));
  EXPECT_EQ(run(0.0), (std::vector<bool>{false, false, false, false, false}));
}

}  // namespace
}  // namespace freespace
