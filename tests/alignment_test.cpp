// Vehicle on a circle (paper III): static world points keep their world position while the map
// shifts, the vehicle never leaves the map, reversing puts more map behind, yaw wraps, and bad
// timestamps and pose jumps are rejected without changing anything.
#include "core/alignment.hpp"

#include <random>

#include "baselines/map_warper.hpp"
#include "core/inside_polygon.hpp"
#include "core/simplifier.hpp"
#include "eval/reference_map.hpp"
#include "host/host_backend.hpp"
#include "sim/simulator.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

Config CircleConfig() {
  Config c;
  c.map.width_cells = 300;
  c.map.height_cells = 200;
  c.alignment.speed_window = 5;
  c.alignment.gain_s = 0.6;
  c.alignment.margin_m = 2.0;
  return c;
}

TEST(Alignment, FirstScanPutsTheVehicleAtTheCentre) {
  CircleAligner a(CircleConfig());
  const AlignStep s = a.Align(0.0, {1e5 + 0.37, -2e4 + 0.11, 3.0});
  ASSERT_TRUE(s.accepted);
  EXPECT_TRUE(s.reset);
  EXPECT_DOUBLE_EQ(s.local.x(), 150.0);
  EXPECT_DOUBLE_EQ(s.local.y(), 100.0);
  // The vehicle's world position is the origin plus its local position.
  const Vec2 world = a.origin_world() + s.local * 0.2;
  EXPECT_NEAR(world.x(), 1e5 + 0.37, 1e-9);
  EXPECT_NEAR(world.y(), -2e4 + 0.11, 1e-9);
}

TEST(Alignment, StaticWorldPointKeepsItsWorldPositionWhileTheMapShifts) {
  const Config config = CircleConfig();
  CircleAligner a(config);
  KernelParams params = MakeKernelParams(config);
  HostBackend map(params, 1);
  std::vector<LogOdds> cells(300 * 200, 0);
  std::mt19937 rng(31);
  Pose2D pose{100000.3, 2000.7, 0.4};  // far from the world origin
  double t = 0.0;
  a.Align(t, pose);
  // Mark the cell holding a static world point 5 m ahead of the start.
  const Vec2 point(pose.x + 5.0 * std::cos(pose.yaw), pose.y + 5.0 * std::sin(pose.yaw));
  auto cell_of = [&](const Vec2& w) {
    const Vec2 c = (w - a.origin_world()) / 0.2;
    return std::pair<int, int>{int(std::floor(c.y())), int(std::floor(c.x()))};
  };
  auto [row, col] = cell_of(point);
  cells[row * 300 + col] = 77;
  map.WriteLogOdds(cells.data());
  const Vec2 frac0 = (point - a.origin_world()) / 0.2;
  for (int k = 0; k < 120; ++k) {
    t += 0.04;
    const double speed = 3.0 + 2.0 * std::sin(k * 0.1);
    pose.yaw += 0.01;
    pose.x += speed * 0.04 * std::cos(pose.yaw);
    pose.y += speed * 0.04 * std::sin(pose.yaw);
    const AlignStep s = a.Align(t, pose);
    ASSERT_TRUE(s.accepted);
    map.Shift(s.shift_x, s.shift_y);
    // The point's position in cells changes by whole cells only.
    const Vec2 frac = (point - a.origin_world()) / 0.2;
    EXPECT_NEAR(frac.x() - std::floor(frac.x()), frac0.x() - std::floor(frac0.x()), 1e-6);
    EXPECT_NEAR(frac.y() - std::floor(frac.y()), frac0.y() - std::floor(frac0.y()), 1e-6);
    std::tie(row, col) = cell_of(point);
    if (row >= 0 && row < 200 && col >= 0 && col < 300) {
      map.ReadLogOdds(cells.data());
      ASSERT_EQ(cells[row * 300 + col], 77) << "scan " << k;
    }
  }
}

TEST(Alignment, TheVehicleNeverLeavesTheMap) {
  const Config config = CircleConfig();
  CircleAligner a(config);
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Pose2D pose{0, 0, 0};
  double t = 0, speed = 0;
  const double margin_cells = config.alignment.margin_m / config.map.resolution_m;
  for (int k = 0; k < 5000; ++k) {
    t += 0.04;
    speed = std::clamp(speed + 3.0 * unit(rng), -15.0, 60.0);  // hard braking, reversing
    pose.yaw += 0.2 * unit(rng);
    pose.x += speed * 0.04 * std::cos(pose.yaw);
    pose.y += speed * 0.04 * std::sin(pose.yaw);
    const AlignStep s = a.Align(t, pose);
    ASSERT_TRUE(s.accepted);
    ASSERT_GE(s.local.x(), margin_cells);
    ASSERT_LE(s.local.x(), 300 - margin_cells);
    ASSERT_GE(s.local.y(), margin_cells);
    ASSERT_LE(s.local.y(), 200 - margin_cells);
  }
}

TEST(Alignment, RadiusFollowsSpeedAndReversingPutsMoreMapBehind) {
  for (const double speed : {8.0, -8.0}) {
    CircleAligner a(CircleConfig());
    Pose2D pose{10, 20, 0.7};
    AlignStep s;
    for (int k = 0; k < 20; ++k) {
      pose.x += speed * 0.04 * std::cos(pose.yaw);
      pose.y += speed * 0.04 * std::sin(pose.yaw);
      s = a.Align(0.04 * k, pose);
      ASSERT_TRUE(s.accepted);
    }
    EXPECT_NEAR(s.filtered_speed_mps, speed, 1e-9);
    EXPECT_NEAR(s.radius_m, 0.6 * std::abs(speed), 1e-9);  // radius proportional to speed
    // Offset of the vehicle from the circle's centre along its heading: negative when driving
    // forward (more map ahead), positive when reversing (more map behind).
    const Vec2 heading(std::cos(pose.yaw), std::sin(pose.yaw));
    const double along = (s.circle_point - s.circle_centre).dot(heading) * 0.2;
    EXPECT_NEAR(along, speed > 0 ? -4.8 : 4.8, 1e-9);
    const double map_ahead = speed > 0 ? 1 : -1;
    EXPECT_LT(map_ahead * (s.local - s.circle_centre).dot(heading), 0.0);
  }
}

TEST(Alignment, FilteredSpeedSurvivesAJitteryClock) {
  // True speed 5 m/s at 25 Hz, but the clock stamps scans alternately 1 ms and 79 ms apart.
  Config config = CircleConfig();
  config.alignment.speed_window = 10;
  CircleAligner a(config);
  double t = 0.0, x = 0.0;
  a.Align(t, {x, 0, 0});
  AlignStep s;
  for (int k = 1; k <= 40; ++k) {
    t += (k % 2) ? 0.001 : 0.079;
    x += 5.0 * 0.04;
    s = a.Align(t, {x, 0, 0});
  }
  EXPECT_NEAR(s.filtered_speed_mps, 5.0, 1e-9);
}

TEST(Alignment, YawWrapsPastPiWithoutAJump) {
  CircleAligner a(CircleConfig());
  Pose2D pose{0, 0, 3.0};
  for (int k = 0; k < 100; ++k) {
    pose.yaw += 0.01;  // crosses +pi; odometry may report it unwrapped or wrapped
    const double reported = (k % 2) ? pose.yaw : pose.yaw - 2 * M_PI;
    pose.x += 0.4 * std::cos(pose.yaw);
    pose.y += 0.4 * std::sin(pose.yaw);
    const AlignStep s = a.Align(0.04 * (k + 1), {pose.x, pose.y, reported});
    ASSERT_TRUE(s.accepted);
    if (k == 0) continue;              // the first scan has no speed yet
    EXPECT_GT(s.speed_mps, 9.9) << k;  // forward all along: no spurious reversing
    EXPECT_GT(s.yaw, -M_PI);
    EXPECT_LE(s.yaw, M_PI);
  }
}

TEST(Alignment, RejectsBackwardsTimeAndPoseJumpsThenRestarts) {
  Config config = CircleConfig();
  config.alignment.reset_after_jumps = 3;
  config.alignment.time_jitter_s = 0.1;
  CircleAligner a(config);
  ASSERT_TRUE(a.Align(1.0, {0, 0, 0}).accepted);
  ASSERT_TRUE(a.Align(1.04, {0.4, 0, 0}).accepted);
  const Vec2 origin = a.origin_world();
  EXPECT_EQ(a.Align(0.5, {0.8, 0, 0}).reason, RejectReason::kTimestampNotIncreasing);
  EXPECT_EQ(a.Align(0.9, {0.8, 0, 0}).reason, RejectReason::kTimestampNotIncreasing);
  EXPECT_EQ(a.Align(1.08, {300.0, 0, 0}).reason, RejectReason::kPoseJump);
  EXPECT_EQ(a.origin_world(), origin);
  // Back on track: accepted, and the jump counter clears.
  EXPECT_TRUE(a.Align(1.12, {0.8, 0, 0}).accepted);
  // Clock jitter: a timestamp slightly before the last is used, without a speed sample.
  const AlignStep jitter = a.Align(1.10, {0.84, 0, 0});
  EXPECT_TRUE(jitter.accepted);
  EXPECT_TRUE(jitter.timestamp_jitter);
  EXPECT_DOUBLE_EQ(jitter.speed_mps, 0.0);
  EXPECT_EQ(a.last_timestamp(), 1.12);
  EXPECT_EQ(a.Align(1.12, {0.86, 0, 0}).timestamp_jitter, true);  // equal times: jitter too
  EXPECT_EQ(a.Align(1.16, {500.0, 0, 0}).reason, RejectReason::kPoseJump);
  EXPECT_EQ(a.Align(1.20, {500.4, 0, 0}).reason, RejectReason::kPoseJump);
  const AlignStep restart = a.Align(1.24, {500.8, 0, 0});  // third jump in a row: restart
  EXPECT_TRUE(restart.accepted);
  EXPECT_TRUE(restart.reset);
  EXPECT_TRUE(a.Align(1.28, {501.2, 0, 0}).accepted);
}

}  // namespace
}  // namespace freespace

namespace freespace {
namespace {

// The baseline alignment: a vehicle-centred map resampled by the vehicle's motion.
TEST(MapWarper, WholeCellMotionIsAnExactShiftAndTurnsMoveTheWorld) {
  Config c;
  c.map.width_cells = 101;
  c.map.height_cells = 81;
  MapWarper warper(c);
  std::vector<LogOdds> map(101 * 81, 0);
  // A mark 5 m (25 cells) ahead of the vehicle at the centre (50.5, 40.5).
  const int row = 40, col = 75;
  map[row * 101 + col] = 500;
  // Driving 1 m forward along +x: the mark comes 5 cells closer, exactly.
  std::vector<LogOdds> moved = map;
  warper.Warp({10, 20, 0}, {11, 20, 0}, moved.data());
  EXPECT_EQ(moved[row * 101 + col - 5], 500);
  EXPECT_EQ(std::count(moved.begin(), moved.end(), 0), long(moved.size()) - 1);
  // Turning left by 90 degrees on the spot: the mark ends up to the vehicle's right.
  std::vector<LogOdds> turned = map;
  warper.Warp({10, 20, 0}, {10, 20, M_PI / 2}, turned.data());
  EXPECT_NEAR(turned[(row - 25) * 101 + 50], 500, 1);
  // A turn by a fraction of a degree blurs the mark over several cells (the paper's point).
  std::vector<LogOdds> blurred = map;
  warper.Warp({10, 20, 0}, {10.03, 20.02, 0.013}, blurred.data());
  EXPECT_GT(std::count_if(blurred.begin(), blurred.end(), [](LogOdds l) { return l != 0; }), 1);
  EXPECT_LT(*std::max_element(blurred.begin(), blurred.end()), 500);
}

TEST(Alignment, RotateBaselineKeepsPolygonsAroundTheVehicleInWorldCoordinates) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  auto reader = OpenLog(path);
  Config c = test::LoadProjectConfig("indoor.yaml");
  c.sensor = reader->sensor();
  c.alignment.kind = AlignmentKind::kRotate;
  Estimator estimator(c);
  Scan scan;
  int checked = 0;
  while (reader->Next(&scan) && checked < 300) {
    const Result& r = estimator.Process(scan);
    if (r.status == ScanStatus::kRejected) continue;
    ++checked;
    EXPECT_EQ(r.vehicle_cells, Vec2(150, 150));
    EXPECT_DOUBLE_EQ(r.map_yaw, r.sensor_pose.yaw);
    ASSERT_GE(r.polygon.size(), 3u);
    EXPECT_TRUE(PointInPolygon(r.polygon, Vec2(r.sensor_pose.x, r.sensor_pose.y)))
        << "scan " << r.scan_index;
  }
  EXPECT_EQ(checked, 300);
}

}  // namespace
}  // namespace freespace

namespace freespace {
namespace {

// The paper's claim for the circle: an exact local map, no resampling error. Against a
// world-fixed reference map on the same lattice, every cell of the local map is identical, on a
// real log; the rotate baseline is not.
TEST(Alignment, CircleMapEqualsTheWorldFixedReferenceAndRotateDoesNot) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  auto reader = OpenLog(path);
  Config circle = test::LoadProjectConfig("indoor.yaml");
  circle.sensor = reader->sensor();
  circle.alignment.gain_s = 20.0;  // a slow robot: a large circle, so the map moves a lot
  Config rotate = circle;
  rotate.alignment.kind = AlignmentKind::kRotate;
  Estimator a(circle), b(rotate);
  ReferenceMap reference(circle, 400);
  Scan scan;
  long compared = 0, rotated_mismatch = 0, rotated_compared = 0;
  int scans = 0;
  while (reader->Next(&scan) && scans < 400) {
    const Result& ra = a.Process(scan);
    reference.Update(scan, ra);
    if (ra.status == ScanStatus::kRejected) continue;
    ++scans;
    const MapDifference d = reference.CompareCircle(a.map(), ra);
    ASSERT_EQ(d.different, 0) << "scan " << ra.scan_index;
    compared += d.compared;
    const Result& rb = b.Process(scan);
    const MapDifference e = reference.CompareRotated(b.map(), rb);
    rotated_mismatch += e.class_mismatch;
    rotated_compared += e.compared;
  }
  EXPECT_GT(compared, 100000);
  EXPECT_GT(rotated_compared, 100000);
  EXPECT_GT(double(rotated_mismatch) / double(rotated_compared), 0.01);
}

// The same with the road setup, whose sensor model leaves the cells on the scan's outline
// unchanged (sensor_model.free_on_outline false): the reference follows the config, so the
// circle's local map still equals it cell for cell (bench's "cells differing from the
// reference" is 0), on a simulated drive through a turn.
TEST(Alignment, CircleMapEqualsTheReferenceWithoutFreeOutline) {
  sim::SimulationOptions options;
  options.scenario = "urban";
  options.seed = 2;
  options.duration_s = 12.0;
  sim::Simulation simulation(options);
  Config config = test::LoadProjectConfig("scala.yaml");
  config.sensor = simulation.truth().scanner.EngineSensor();
  config.sensor.sweep_s = 0.0;  // the reference places every point from the scan's one pose
  ASSERT_FALSE(config.sensor_model.free_on_outline);
  Estimator estimator(config);
  ReferenceMap reference(config, 400);
  Config filled = config;  // a reference that fills the outline free differs
  filled.sensor_model.free_on_outline = true;
  ReferenceMap other(filled, 400);
  Scan scan;
  long compared = 0, other_different = 0;
  while (simulation.Next(&scan)) {
    const Result& r = estimator.Process(scan);
    reference.Update(scan, r);
    other.Update(scan, r);
    if (r.status == ScanStatus::kRejected) continue;
    const MapDifference d = reference.CompareCircle(estimator.map(), r);
    ASSERT_EQ(d.different, 0) << "scan " << r.scan_index;
    compared += d.compared;
    other_different += other.CompareCircle(estimator.map(), r).different;
  }
  EXPECT_GT(compared, 100000);
  EXPECT_GT(other_different, 1000);
}

TEST(Alignment, RejectsAShiftNoIntegerHoldsAndChangesNothing) {
  Config config = CircleConfig();
  config.map.resolution_m = 1e-9;  // a pose 1e8 m away is 1e17 cells: more than 2^52
  CircleAligner a(config);
  ASSERT_TRUE(a.Align(1.0, {0, 0, 0}).accepted);
  ASSERT_TRUE(a.Align(1.04, {1e-8, 0, 0}).accepted);
  const Vec2 origin = a.origin_world();
  const std::int64_t origin_x = a.origin_x();
  for (const Pose2D far : {Pose2D{1e8, 0, 0}, Pose2D{0, -1e8, 0}, Pose2D{1e300, 1e300, 0}}) {
    const AlignStep s = a.Align(1e9, far);
    EXPECT_FALSE(s.accepted);
    EXPECT_EQ(s.reason, RejectReason::kPoseOutOfRange);
    EXPECT_EQ(a.origin_world(), origin);
    EXPECT_EQ(a.origin_x(), origin_x);
    EXPECT_EQ(a.consecutive_jumps(), 0);
  }
  // Near enough, the next scan is used as before.
  EXPECT_TRUE(a.Align(1.08, {2e-8, 0, 0}).accepted);
}

TEST(Alignment, AClockThatStopsIsDetectedOnceAndPosesAreUsedWithoutAJumpTest) {
  Config config = CircleConfig();
  config.alignment.jump_slack_m = 1.0;
  CircleAligner a(config);
  ASSERT_TRUE(a.Align(1.0, {0, 0, 0}).accepted);
  ASSERT_TRUE(a.Align(1.04, {0.4, 0, 0}).accepted);
  // Two scans with the time of the one before: jitter, then the stall.
  const AlignStep second = a.Align(1.04, {0.8, 0, 0});
  EXPECT_TRUE(second.accepted);
  EXPECT_TRUE(second.timestamp_jitter);
  EXPECT_FALSE(second.clock_stalled);
  const AlignStep third = a.Align(1.04, {1.2, 0, 0});
  EXPECT_TRUE(third.accepted);
  EXPECT_TRUE(third.clock_stalled);
  EXPECT_TRUE(third.stall_detected);
  EXPECT_FALSE(third.timestamp_jitter);
  // While stalled, a move far beyond jump_slack_m is used, said no more, and gives no speed.
  const AlignStep far = a.Align(1.04, {6.2, 0, 0});
  EXPECT_TRUE(far.accepted);
  EXPECT_TRUE(far.clock_stalled);
  EXPECT_FALSE(far.stall_detected);
  EXPECT_DOUBLE_EQ(far.speed_mps, 0.0);
  EXPECT_EQ(a.consecutive_jumps(), 0);
  // The clock advances: the stall ends, speeds and the jump test come back.
  const AlignStep moving = a.Align(1.08, {6.6, 0, 0});
  EXPECT_TRUE(moving.accepted);
  EXPECT_FALSE(moving.clock_stalled);
  EXPECT_NEAR(moving.speed_mps, 10.0, 1e-9);
  EXPECT_EQ(a.Align(1.12, {60.0, 0, 0}).reason, RejectReason::kPoseJump);
}

// Found by tests/fuzz/fuzz_estimator: an interval of 1e-321 s gave an infinite speed.
TEST(Alignment, TheFilteredSpeedStaysWithinMaxSpeed) {
  Config config = CircleConfig();
  config.alignment.max_speed_mps = 30.0;
  CircleAligner a(config);
  ASSERT_TRUE(a.Align(0.0, {0, 0, 0}).accepted);
  ASSERT_TRUE(a.Align(1e-321, {0, 0, 0}).accepted);
  const AlignStep s = a.Align(0.0, {5e-10, 0, 0});
  ASSERT_TRUE(s.accepted);
  EXPECT_TRUE(std::isfinite(s.filtered_speed_mps));
  EXPECT_LE(std::abs(s.filtered_speed_mps), 30.0);
  EXPECT_LE(s.radius_m, 0.5 * 200 * config.map.resolution_m);
}

}  // namespace
}  // namespace freespace
