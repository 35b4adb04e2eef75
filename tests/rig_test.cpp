// A rig of several sensors (Config::sensors, Estimator::ProcessCycle): the config's list and its
// errors, the fusion rule of a cycle (each scan fused once from its own pose, in the rig's
// order), a one-sensor rig matching the single sensor bit for bit, bad cycles and the
// simulator's surround rig (a rig in files: rig_log_test.cpp).
#include "sim/rig.hpp"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/simplifier.hpp"
#include "sim/simulator.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

constexpr const char* kTwoSensors = R"(
sensors:
  - name: front
    mount_x_m: 3.7
  - name: rear
    mount_x_m: -1.0
    mount_yaw_deg: 180
    max_range_m: 80
rig:
  reference_x_m: 1.35
  footprint_length_m: 4.7
  footprint_width_m: 1.8
)";

std::string ConfigError(const std::string& yaml) {
  try {
    Config::FromYaml(yaml, "rig.yaml").Validate();
  } catch (const freespace::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(RigConfig, ReadsTheSensorsList) {
  const Config c = Config::FromYaml(kTwoSensors, "rig.yaml");
  c.Validate();
  ASSERT_TRUE(c.is_rig());
  ASSERT_EQ(c.sensor_count(), 2);
  EXPECT_EQ(c.sensor_at(0).name, "front");
  EXPECT_EQ(c.sensor_at(1).name, "rear");
  EXPECT_DOUBLE_EQ(c.sensor_at(1).mount_yaw_deg, 180.0);
  EXPECT_DOUBLE_EQ(c.sensor_at(1).max_range_m, 80.0);
  EXPECT_DOUBLE_EQ(c.sensor_at(1).angular_resolution_deg, 0.25);  // the default
  EXPECT_DOUBLE_EQ(c.rig.reference_x_m, 1.35);
  EXPECT_DOUBLE_EQ(c.rig.footprint_width_m, 1.8);

  const Config again = Config::FromYaml(c.ToYaml(), "written");
  ASSERT_EQ(again.sensors.size(), 2u);
  EXPECT_EQ(again.sensors[1].name, "rear");
  EXPECT_DOUBLE_EQ(again.sensors[1].max_range_m, 80.0);
  EXPECT_DOUBLE_EQ(again.rig.footprint_length_m, 4.7);
  EXPECT_EQ(again.ToYaml(), c.ToYaml());
}

TEST(RigConfig, ASingleSensorConfigIsNoRig) {
  const Config c = Config::FromYaml("sensor:\n  mount_x_m: 3.7\n", "one.yaml");
  EXPECT_FALSE(c.is_rig());
  EXPECT_EQ(c.sensor_count(), 1);
  EXPECT_DOUBLE_EQ(c.sensor_at(0).mount_x_m, 3.7);
  EXPECT_EQ(Config::FromYaml(c.ToYaml()).sensors.size(), 0u);
}

TEST(RigConfig, ErrorsNameTheSensorAndTheField) {
  // The heading correction matches one scanner's scans: a rig's cycle is refused, not ignored.
  const std::string matched =
      ConfigError("alignment:\n  scan_match: true\nsensors:\n  - name: a\n  - name: b\n");
  EXPECT_NE(matched.find("alignment.scan_match"), std::string::npos) << matched;
  EXPECT_NE(matched.find("one sensor"), std::string::npos) << matched;
  EXPECT_EQ(Config::FromYaml("alignment:\n  scan_match: true\n").alignment.scan_match, true);
  EXPECT_NE(ConfigError("sensor:\n  layers: 2\nsensors:\n  - name: a\n").find("not both"),
            std::string::npos);
  EXPECT_NE(ConfigError("sensors:\n  - name: a\n  - name: a\n").find("sensors[a].name"),
            std::string::npos);
  EXPECT_NE(ConfigError("sensors:\n  - name: a\n  - name: b\n    max_range_m: 0.05\n")
                .find("sensors[b].max_range_m = 0.05: must be > sensors[b].min_range_m"),
            std::string::npos);
  EXPECT_NE(ConfigError("sensors:\n  - name: a\n  - name: b\n    colour: red\n")
                .find("rig.yaml:4: unknown field 'sensors[1].colour'"),
            std::string::npos);
  EXPECT_NE(ConfigError("sensors: []\n").find("a list of 1 to 16"), std::string::npos);
  EXPECT_NE(ConfigError("sensors:\n  - name: two words\n").find("one word"), std::string::npos);
  EXPECT_NE(ConfigError("rig:\n  footprint_length_m: 60\n").find("rig.footprint_length_m"),
            std::string::npos);
}

using test::TwoAlike;
using test::Wall;

// Two sensors at one mount seeing the same scene: each scan is fused once, so every cell the
// cycle updates holds twice what one scan gives it on a fresh map (the paper's rule per scan).
TEST(RigEstimator, EachScanOfACycleUpdatesACellOnce) {
  Estimator one(Config{});
  Estimator rig(TwoAlike());
  const Scan a = Wall(0.0, {0, 0, 0}, 0, 12.0);
  Scan b = a;
  b.sensor = 1;
  ASSERT_EQ(one.Process(a).status, ScanStatus::kOk);
  const Result& r = rig.ProcessCycle(std::vector<Scan>{b, a});
  ASSERT_EQ(r.status, ScanStatus::kOk) << r.message;
  EXPECT_EQ(r.cycle_sensors, (std::vector<int>{0, 1}));  // fused in the rig's order
  const MapView m1 = one.map(), m2 = rig.map();
  ASSERT_EQ(m1.origin, m2.origin);
  long updated = 0;
  for (int i = 0; i < m1.width * m1.height; ++i) {
    ASSERT_EQ(int(m2.log_odds[i]), 2 * int(m1.log_odds[i])) << "cell " << i;
    updated += m1.log_odds[i] != 0;
  }
  EXPECT_GT(updated, 1000);
}

// Each scan of a cycle is placed at its own pose: the second sensor's scan, taken 2 m further
// on, puts its wall 2 m further than the first's.
TEST(RigEstimator, ScansOfACycleAreFusedAtTheirOwnPoses) {
  Estimator rig(TwoAlike());
  const std::vector<Scan> cycle = {Wall(0.00, {0, 0, 0}, 0, 10.1),
                                   Wall(0.08, {2.0, 0, 0}, 1, 10.1)};
  const Result& r = rig.ProcessCycle(cycle);
  ASSERT_EQ(r.status, ScanStatus::kOk) << r.message;
  EXPECT_DOUBLE_EQ(r.timestamp_s, 0.08);  // the newest scan's
  const MapView m = rig.map();
  const auto at = [&](double x, double y) {
    const int col = int(std::floor((x - m.origin.x()) / m.resolution_m));
    const int row = int(std::floor((y - m.origin.y()) / m.resolution_m));
    return m.log_odds[std::size_t(row) * m.width + col];
  };
  EXPECT_GT(at(10.1, 0.1), 0);  // sensor a's wall
  EXPECT_GT(at(12.1, 0.1), 0);  // sensor b's wall, 2 m on
  EXPECT_LT(at(11.1, 0.1), 0);  // free in b's view
}

TEST(RigEstimator, BadCyclesAreRejectedAndChangeNothing) {
  Estimator rig(TwoAlike());
  const Scan a = Wall(0.0, {0, 0, 0}, 0, 12.0);
  Scan far = a;
  far.sensor = 2;
  EXPECT_EQ(rig.ProcessCycle(nullptr, 0).reject_reason, RejectReason::kBadCycle);
  EXPECT_EQ(rig.ProcessCycle(std::vector<Scan>{a, a}).reject_reason, RejectReason::kBadCycle);
  const Result& r = rig.ProcessCycle(std::vector<Scan>{far});
  EXPECT_EQ(r.reject_reason, RejectReason::kBadCycle);
  EXPECT_NE(r.message.find("sensor 2"), std::string::npos) << r.message;
  const MapView m = rig.map();
  for (int i = 0; i < m.width * m.height; ++i) ASSERT_EQ(m.log_odds[i], 0);

  // Scans of one cycle farther apart than the vehicle can travel between them (or than the map
  // reaches): rejected, not placed far outside the map. The newest scan is the reference.
  Scan away = Wall(0.04, {1e6, 0, 0}, 1, 12.0);
  const Result& spread = rig.ProcessCycle(std::vector<Scan>{a, away});
  EXPECT_EQ(spread.reject_reason, RejectReason::kPoseJump);
  EXPECT_NE(spread.message.find("sensor 0 (a)"), std::string::npos) << spread.message;
  away.pose.x = 20.0;  // 20 m in 0.04 s
  EXPECT_EQ(rig.ProcessCycle(std::vector<Scan>{a, away}).reject_reason, RejectReason::kPoseJump);
  const MapView after = rig.map();
  for (int i = 0; i < after.width * after.height; ++i) ASSERT_EQ(after.log_odds[i], 0);
  away.pose.x = 1.0;  // 25 m/s: plausible
  EXPECT_EQ(rig.ProcessCycle(std::vector<Scan>{a, away}).status, ScanStatus::kOk);

  Estimator single(Config{});
  Scan b = a;
  b.sensor = 1;
  EXPECT_EQ(single.Process(b).reject_reason, RejectReason::kBadCycle);
  EXPECT_EQ(single.ProcessCycle(std::vector<Scan>{a, a}).reject_reason, RejectReason::kBadCycle);
  EXPECT_EQ(single.ProcessCycle(std::vector<Scan>{a}).status, ScanStatus::kOk);
}

// A scan of a cycle that Process() would reject for its time is rejected with its cycle, though
// the alignment only sees the cycle's newest scan: a stale frame of one sensor, 50 s (or 2 s)
// before the latest accepted scan, changes nothing. Within alignment.time_jitter_s it is taken.
TEST(RigEstimator, AScanOlderThanTheLastCycleRejectsItsCycle) {
  Estimator rig(TwoAlike());
  ASSERT_EQ(rig.ProcessCycle(std::vector<Scan>{Wall(10.0, {0, 0, 0}, 0, 12.0),
                                               Wall(10.01, {0, 0, 0}, 1, 12.0)})
                .status,
            ScanStatus::kOk);
  const MapView before = rig.map();
  const std::vector<LogOdds> kept(before.log_odds, before.log_odds + before.width * before.height);
  for (const double stale : {-40.0, 8.0}) {
    const Result& r = rig.ProcessCycle(
        std::vector<Scan>{Wall(stale, {0.5, 0, 0}, 0, 11.0), Wall(10.1, {0.5, 0, 0}, 1, 11.0)});
    EXPECT_EQ(r.reject_reason, RejectReason::kTimestampNotIncreasing) << stale;
    EXPECT_NE(r.message.find("sensor 0 (a)"), std::string::npos) << r.message;
    const MapView after = rig.map();
    for (int i = 0; i < after.width * after.height; ++i) ASSERT_EQ(after.log_odds[i], kept[i]);
  }
  // 0.5 s back: within the default 1 s of clock jitter, as Process() takes it.
  EXPECT_EQ(rig.ProcessCycle(std::vector<Scan>{Wall(9.51, {0.5, 0, 0}, 0, 11.0),
                                               Wall(10.1, {0.5, 0, 0}, 1, 11.0)})
                .status,
            ScanStatus::kOk);
}

// A rig of one sensor whose reference point is that sensor is the single sensor, bit for bit.
TEST(RigEstimator, OneSensorRigAtItsReferenceIsTheSingleSensor) {
  sim::SimulationOptions options;
  options.scenario = "urban";
  options.seed = 4;
  sim::Simulation simulation(options);
  Config single = test::LoadProjectConfig("scala.yaml");
  single.sensor = simulation.truth().scanner.EngineSensor();
  Config rig = single;
  rig.sensors = {single.sensor};
  rig.rig.reference_x_m = single.sensor.mount_x_m;
  rig.rig.reference_y_m = single.sensor.mount_y_m;
  Estimator a(single), b(rig);
  Scan scan;
  for (int k = 0; k < 150 && simulation.Next(&scan); ++k) {
    const Result& ra = a.Process(scan);
    const Result& rb = b.ProcessCycle(&scan, 1);
    ASSERT_EQ(ra.status, rb.status) << "scan " << k;
    ASSERT_EQ(ra.polygon, rb.polygon) << "scan " << k;
    const MapView ma = a.map(), mb = b.map();
    ASSERT_EQ(std::memcmp(ma.log_odds, mb.log_odds, sizeof(LogOdds) * ma.width * ma.height), 0)
        << "scan " << k;
  }
}

TEST(RigSimulation, SurroundGivesFourSynchronisedScansAllAround) {
  sim::SimulationOptions options;
  options.scenario = "parking";
  options.seed = 2;
  options.rig = "surround";
  sim::Simulation simulation(options);
  ASSERT_EQ(simulation.rig().scanners.size(), 4u);
  std::vector<Scan> cycle;
  ASSERT_TRUE(simulation.NextCycle(&cycle));
  ASSERT_EQ(cycle.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(cycle[k].sensor, k);
    EXPECT_EQ(cycle[k].timestamp_s, cycle[0].timestamp_s);
    EXPECT_EQ(cycle[k].pose.x, cycle[0].pose.x);
    int echoes = 0;
    for (const ScanPoint& p : cycle[k].points) echoes += p.echo;
    EXPECT_GT(echoes, 50) << "scanner " << k;  // parked cars on every side
  }
  // The truth's sensor pose is the rig's reference point, between the axles.
  const sim::TruthScan& t = simulation.last();
  EXPECT_NEAR(std::hypot(t.sensor.x - t.pose.x, t.sensor.y - t.pose.y), 1.35, 1e-9);

  // The engine's view of the rig: four sensors, the footprint, a valid config.
  const Config c = sim::WithRig(Config(), simulation.rig());
  c.Validate();
  EXPECT_EQ(c.sensor_count(), 4);
  EXPECT_EQ(c.sensor_at(2).name, "rear_left");
  EXPECT_GT(c.rig.footprint_length_m, 4.0);

  // The front rig is the single scanner: the same scans as Next() gives.
  options.rig = "front";
  sim::Simulation a(options), b(options);
  Scan scan;
  ASSERT_TRUE(a.Next(&scan));
  ASSERT_TRUE(b.NextCycle(&cycle));
  ASSERT_EQ(cycle.size(), 1u);
  EXPECT_EQ(cycle[0].points.size(), scan.points.size());
  EXPECT_EQ(cycle[0].points[100].range_m, scan.points[100].range_m);
}

// The surround rig's cycle: polygon all around the vehicle (it contains points ahead, behind
// and to both sides of the reference point), the footprint free. Beside the car's middle the
// corner scanners are blind (a wedge out to about 5 m); 4 s into the drive the front scanners
// have seen that ground on the way.
TEST(RigEstimator, SurroundPolygonReachesAllAround) {
  sim::SimulationOptions options;
  options.scenario = "urban";
  options.seed = 1;
  options.rig = "surround";
  sim::Simulation simulation(options);
  Config config = sim::WithRig(test::LoadProjectConfig("scala.yaml"), simulation.rig());
  Estimator estimator(config);
  std::vector<Scan> cycle;
  const Result* r = nullptr;
  for (int k = 0; k < 100 && simulation.NextCycle(&cycle); ++k) r = &estimator.ProcessCycle(cycle);
  ASSERT_NE(r, nullptr);
  ASSERT_EQ(r->polygon_status, PolygonStatus::kOk) << r->message;
  EXPECT_TRUE(r->polygon_contains_vehicle);
  ASSERT_EQ(r->cycle_sensor_poses.size(), 4u);
  const Pose2D& c = r->sensor_pose;
  int quadrants = 0;
  for (int q = 0; q < 4; ++q) {
    // A point beyond the car's body ahead, behind (4 m) and to either side (1.5 m) lies in the
    // polygon: beyond the footprint, so the scanners saw it free.
    const double a = c.yaw + q * M_PI / 2, d = q % 2 == 0 ? 4.0 : 1.5;
    const Vec2 p(c.x + d * std::cos(a), c.y + d * std::sin(a));
    EXPECT_TRUE(PointInPolygon(r->polygon, p)) << "direction " << q;
    quadrants += PointInPolygon(r->polygon, p);
  }
  EXPECT_EQ(quadrants, 4);
}

// The sensors' parallel work (preprocessing, deskew and projection) held to one thread
// (backend.threads 1) gives the cycles' maps and polygons of the default, bit for bit, with
// every scan placed from its sensor's sweep (sensor.sweep_s).
TEST(RigEstimator, OneThreadGivesTheSameCycles) {
  sim::SimulationOptions options;
  options.scenario = "urban";
  options.seed = 3;
  options.rig = "surround";
  sim::Simulation simulation(options);
  Config all = sim::WithRig(test::LoadProjectConfig("scala.yaml"), simulation.rig());
  Config one = all;
  one.backend.threads = 1;
  ASSERT_GT(all.sensors.front().sweep_s, 0.0);
  Estimator a(all), b(one);
  std::vector<Scan> cycle;
  int swept = 0;
  for (int k = 0; k < 60 && simulation.NextCycle(&cycle); ++k) {
    const Result& ra = a.ProcessCycle(cycle);
    const Result& rb = b.ProcessCycle(cycle);
    ASSERT_EQ(ra.status, rb.status) << "cycle " << k;
    ASSERT_EQ(ra.sweep_corrected, rb.sweep_corrected) << "cycle " << k;
    ASSERT_EQ(ra.polygon, rb.polygon) << "cycle " << k;
    const MapView ma = a.map(), mb = b.map();
    ASSERT_EQ(std::memcmp(ma.log_odds, mb.log_odds, sizeof(LogOdds) * ma.width * ma.height), 0)
        << "cycle " << k;
    swept += ra.sweep_corrected ? 1 : 0;
  }
  EXPECT_GT(swept, 50);  // every cycle but the first few placed from the sweep
}

}  // namespace
}  // namespace freespace
