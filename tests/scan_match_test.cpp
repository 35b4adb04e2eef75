// Heading correction from the scans (core/scan_match.hpp): a scan taken from a known pose,
// matched from a heading that is off by a little, is turned back, by at most the bound; echoes
// in free space and young occupied evidence do not count.
#include "core/scan_match.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "eval/drive_eval.hpp"
#include "freespace/estimator.hpp"
#include "geometry/geometry.hpp"
#include "sim/odometry.hpp"
#include "sim/simulator.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

constexpr int kSide = 200;
constexpr double kRes = 0.2;
constexpr LogOdds kMax = 890;

// A map of walls: cells on the given world segments are occupied, everything else free.
struct WallMap {
  std::vector<LogOdds> cells = std::vector<LogOdds>(kSide * kSide, LogOdds(-kMax));
  void Wall(Vec2 a, Vec2 b) {
    const int steps = int((b - a).norm() / (kRes / 4)) + 1;
    for (int i = 0; i <= steps; ++i) {
      const Vec2 p = a + (b - a) * (double(i) / steps);
      cells[int(p.y() / kRes) * kSide + int(p.x() / kRes)] = kMax;
    }
  }
  MapView View() const {
    MapView m;
    m.log_odds = cells.data();
    m.width = m.height = kSide;
    m.resolution_m = kRes;
    return m;
  }
};

// Points on the walls' cell centres' lines, in the frame of `sensor`.
std::vector<EchoPoint> Seen(const std::vector<Vec2>& world, const Pose2D& sensor) {
  std::vector<EchoPoint> out;
  const double c = std::cos(sensor.yaw), s = std::sin(sensor.yaw);
  for (const Vec2& w : world) {
    const double dx = w.x() - sensor.x, dy = w.y() - sensor.y;
    out.push_back({float(c * dx + s * dy), float(-s * dx + c * dy)});
  }
  return out;
}

// A room: walls along x = 5.1 and 34.9 m, y = 5.1 and 34.9 m (cell centres), and points on them.
std::vector<Vec2> Room(WallMap* map) {
  const double lo = 5.1, hi = 34.9;
  map->Wall({lo, lo}, {hi, lo});
  map->Wall({lo, hi}, {hi, hi});
  map->Wall({lo, lo}, {lo, hi});
  map->Wall({hi, lo}, {hi, hi});
  std::vector<Vec2> points;
  for (double t = lo + 1; t < hi - 1; t += 0.5) {
    points.push_back({t, lo});
    points.push_back({t, hi});
    points.push_back({lo, t});
    points.push_back({hi, t});
  }
  return points;
}

TEST(ScanMatch, TurnsAnOffsetHeadingBackOntoTheWalls) {
  WallMap map;
  const std::vector<Vec2> walls = Room(&map);
  const Pose2D truth{20.0, 18.0, 0.3};
  const std::vector<EchoPoint> points = Seen(walls, truth);
  const ScanMatcher matcher(0.2 * M_PI / 180, kMax);
  for (const double off : {0.002, -0.002}) {
    const Pose2D at{truth.x, truth.y, truth.yaw + off};
    const MatchResult m = matcher.Match(map.View(), points, at);
    ASSERT_TRUE(m.applied) << off;
    EXPECT_GT(m.points, ScanMatcher::kMinPoints);
    EXPECT_LT(m.cost_after, m.cost_before);
    EXPECT_NEAR(at.yaw + m.dyaw, truth.yaw, 0.0003) << off;
  }
}

// The match's standard error (what the heading filter weighs it by) grows with the echoes'
// misfit and with fewer echoes, and is never 0.
TEST(ScanMatch, TheStandardErrorGrowsWithMisfitAndFewerEchoes) {
  WallMap map;
  const std::vector<Vec2> walls = Room(&map);
  const Pose2D truth{20.0, 18.0, 0.0};
  const ScanMatcher matcher(0.2 * M_PI / 180, kMax);
  const auto std_of = [&](const std::vector<Vec2>& points) {
    const MatchResult m = matcher.Match(map.View(), Seen(points, truth), {20.0, 18.0, 0.002});
    EXPECT_TRUE(m.applied);
    return m.std_rad;
  };
  // Echoes 0, 1 or 2 times `step` in front of the wall.
  const auto in_front = [&](double step) {
    std::vector<Vec2> out = walls;
    for (std::size_t i = 0; i < out.size(); ++i) {
      out[i] += (Vec2(truth.x, truth.y) - out[i]).normalized() * double(i % 3) * step;
    }
    return out;
  };
  const std::vector<Vec2> base = in_front(0.03);
  std::vector<Vec2> sparse;
  for (std::size_t i = 0; i < base.size(); i += 4) sparse.push_back(base[i]);
  EXPECT_GT(std_of(walls), 0.0);  // on the cells' centres: no misfit, still not exact
  const double std_base = std_of(base);
  EXPECT_GT(std_base, 0.0);
  EXPECT_GT(std_of(in_front(0.06)), 1.5 * std_base);
  EXPECT_GT(std_of(sparse), 1.5 * std_base);
}

TEST(ScanMatch, ARotationIsBoundedPerScan) {
  WallMap map;
  const std::vector<Vec2> walls = Room(&map);
  const Pose2D truth{20.0, 18.0, 0.0};
  const ScanMatcher matcher(0.001, kMax);
  const Pose2D at{truth.x, truth.y, truth.yaw - 0.004};
  const MatchResult m = matcher.Match(map.View(), Seen(walls, truth), at);
  ASSERT_TRUE(m.applied);
  EXPECT_NEAR(m.dyaw, 0.001, 1e-12);  // toward the truth, no further than the bound
}

TEST(ScanMatch, EchoesInFreeSpaceAreNotMatched) {
  WallMap map;
  Room(&map);
  std::vector<Vec2> inside;  // a vehicle in the room's free middle
  for (double t = 15; t < 25; t += 0.2) inside.push_back({t, 25.0});
  const Pose2D sensor{20.0, 18.0, 0.0};
  const ScanMatcher matcher(0.2 * M_PI / 180, kMax);
  const MatchResult m = matcher.Match(map.View(), Seen(inside, sensor), {20.0, 18.0, 0.002});
  EXPECT_FALSE(m.applied);
  EXPECT_EQ(m.points, 0);
  EXPECT_EQ(m.dyaw, 0.0);
}

// Cells one or two scans saw occupied (a vehicle's trail) are not matched: only settled ones.
TEST(ScanMatch, YoungOccupiedEvidenceIsNotMatched) {
  WallMap map;
  const std::vector<Vec2> walls = Room(&map);
  for (LogOdds& l : map.cells) {
    if (l > 0) l = LogOdds(kMax * 4 / 10);
  }
  const Pose2D truth{20.0, 18.0, 0.0};
  const ScanMatcher matcher(0.2 * M_PI / 180, kMax);
  const MatchResult m =
      matcher.Match(map.View(), Seen(walls, truth), {truth.x, truth.y, truth.yaw + 0.002});
  EXPECT_FALSE(m.applied);
  EXPECT_EQ(m.points, 0);
}

}  // namespace
}  // namespace freespace

namespace freespace {
namespace {

struct DriveScore {
  double intrusion_m2 = 0.0;  // mean over the scans
  double coverage = 0.0;
};

// A simulated drive with a production car's odometry (0.5 % distance scale, 0.1 deg/s
// yaw-rate bias), the road setup with or without the heading correction, scored per scan.
DriveScore Drive(const std::string& scenario, bool scan_match) {
  sim::SimulationOptions options;
  options.scenario = scenario;
  options.seed = 11;
  options.duration_s = 20.0;
  options.odometry = sim::OdometryNoise::Preset("typical");
  Config config = test::LoadProjectConfig("scala.yaml");
  config.alignment.scan_match = scan_match;
  const DriveEvaluation drive = EvaluateDrive(options, config);
  DriveScore score;
  for (const ScanMetrics& m : drive.metrics.scans()) {
    score.intrusion_m2 += m.intrusion_m2 / double(drive.metrics.size());
    score.coverage += m.coverage / double(drive.metrics.size());
  }
  EXPECT_EQ(drive.rejected, 0);
  EXPECT_GT(drive.metrics.size(), 400u);
  return score;
}

// The car park, where the drift does most harm: with the heading corrected from the scans the
// polygon's intrusion falls to under half, its coverage within 0.03 of the uncorrected.
TEST(HeadingCorrection, KeepsTheRememberedFreeSpaceOffWhatTheCarPassed) {
  const DriveScore raw = Drive("parking", false);
  const DriveScore matched = Drive("parking", true);
  EXPECT_GT(raw.intrusion_m2, 0.1);
  EXPECT_LT(matched.intrusion_m2, 0.5 * raw.intrusion_m2);
  EXPECT_GT(matched.coverage, raw.coverage - 0.03);
}

// The result is in the input poses' frame, the map kept in the corrected one: the sensor pose is
// the input pose with the mount, the map's view places the sensor's cells there, and the polygon
// lies around it, however far the correction has turned the map.
TEST(HeadingCorrection, TheResultStaysInTheInputPosesFrame) {
  sim::SimulationOptions options;
  options.scenario = "urban";
  options.seed = 12;
  options.duration_s = 10.0;
  options.odometry.yaw_rate_bias_dps = 0.5;
  sim::Simulation simulation(options);
  Config config = test::LoadProjectConfig("scala.yaml");
  config.sensor = simulation.truth().scanner.EngineSensor();
  config.alignment.scan_match = true;
  Estimator estimator(config);
  Scan scan;
  double turned = 0.0;
  while (simulation.Next(&scan)) {
    const Result& r = estimator.Process(scan);
    ASSERT_EQ(r.status, ScanStatus::kOk) << r.message;
    const double c = std::cos(scan.pose.yaw), s = std::sin(scan.pose.yaw);
    const Vec2 sensor(scan.pose.x + c * config.sensor.mount_x_m,
                      scan.pose.y + s * config.sensor.mount_x_m);
    EXPECT_NEAR(r.sensor_pose.x, sensor.x(), 1e-9);
    EXPECT_NEAR(r.sensor_pose.y, sensor.y(), 1e-9);
    EXPECT_NEAR(std::remainder(r.sensor_pose.yaw - scan.pose.yaw, 2 * M_PI), 0.0, 1e-12);
    EXPECT_NEAR(std::remainder(r.map_yaw + r.pose_correction.yaw, 2 * M_PI), 0.0, 1e-12);
    const MapView map = estimator.map();
    const double mc = std::cos(map.map_yaw), ms = std::sin(map.map_yaw);
    const Vec2 v = r.vehicle_cells * map.resolution_m;
    EXPECT_NEAR(map.origin.x() + mc * v.x() - ms * v.y(), sensor.x(), 1e-6);
    EXPECT_NEAR(map.origin.y() + ms * v.x() + mc * v.y(), sensor.y(), 1e-6);
    if (r.polygon_status == PolygonStatus::kOk) {
      EXPECT_TRUE(geometry::InsidePolygon(r.polygon, sensor)) << "scan " << r.scan_index;
    }
    turned = std::max(turned, std::abs(r.pose_correction.yaw));
  }
  EXPECT_GT(turned, 0.5 * M_PI / 180);  // the frames differ by more than half a degree
}

}  // namespace
}  // namespace freespace
