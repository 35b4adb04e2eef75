// The scenario simulator: exact ray geometry (a wall at a known range, low obstacles seen only
// by the low layers), determinism (the same seed writes the same bytes, a log read back gives
// the same scans), trajectories that reverse when asked, odometry noise, and clutter and
// dropouts at their configured rates.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "geometry/geometry.hpp"
#include "sim/rig.hpp"
#include "sim/scanner.hpp"
#include "sim/scenarios.hpp"
#include "sim/simulator.hpp"
#include "sim/truth.hpp"
#include "test_util.hpp"

namespace freespace::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A scanner without noise, pitch, clutter, dropouts or sweep, mounted at the vehicle's
// reference point.
ScannerConfig IdealScanner() {
  ScannerConfig c;
  c.detection_range_m = 1e6;
  c.range_sigma_m = 0.0;
  c.range_resolution_m = 0.0;
  c.sweep_s = 0.0;
  c.mount_x_m = 0.0;
  c.pitch_per_accel_deg = 0.0;
  c.pitch_sigma_deg = 0.0;
  c.ground_echo_probability = 0.0;
  c.rain_probability = 0.0;
  return c;
}

Obstacle Wall(const Polygon& shape, double z_max = 3.0, double reflectivity = 1.0) {
  Obstacle o;
  o.shape = shape;
  o.z_max_m = z_max;
  o.reflectivity = reflectivity;
  return o;
}

// The vehicle standing at `pose` for `seconds`.
Trajectory Standing(const Pose2D& pose, double seconds = 100.0) {
  Trajectory t(pose);
  t.Wait(seconds);
  return t;
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(Geometry, RaySegmentAndClippedAreasAreExact) {
  EXPECT_DOUBLE_EQ(RaySegment({0, 0}, {1, 0}, {5, -1}, {5, 1}), 5.0);
  EXPECT_LT(RaySegment({0, 0}, {1, 0}, {5, 1}, {5, 2}), 0.0);    // passes beside
  EXPECT_LT(RaySegment({0, 0}, {-1, 0}, {5, -1}, {5, 1}), 0.0);  // behind the ray
  EXPECT_LT(RaySegment({0, 0}, {1, 0}, {1, 0}, {2, 0}), 0.0);    // parallel
  // An L-shaped (concave) polygon of area 3 clipped by boxes.
  const Polygon l = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  EXPECT_DOUBLE_EQ(SignedArea(l), 3.0);
  EXPECT_DOUBLE_EQ(AreaInBox(l, 0, 0, 2, 2), 3.0);
  EXPECT_DOUBLE_EQ(AreaInBox(l, 1, 1, 2, 2), 0.0);  // the notch
  EXPECT_DOUBLE_EQ(AreaInBox(l, 0.5, 0.5, 1.5, 1.5), 0.75);
  EXPECT_NEAR(SignedArea(ClipToConvex(l, Rectangle({1, 1}, 2, 2, 0.0))), 3.0, 1e-12);
  // Poses: compose with the inverse is the identity.
  const Pose2D a{3.0, -2.0, 0.7};
  const Pose2D id = Compose(a, Inverse(a));
  EXPECT_NEAR(id.x, 0.0, 1e-12);
  EXPECT_NEAR(id.y, 0.0, 1e-12);
  EXPECT_NEAR(id.yaw, 0.0, 1e-12);
}

TEST(Scanner, EveryLayerHitsAKnownWallAtTheKnownRange) {
  // 6 m ahead: even at the aperture's edge (19.95 m) the lowest layer meets the wall before
  // its footprint reaches the road (21.5 m).
  World world;
  world.obstacles.push_back(Wall(Box(6.0, -50.0, 7.0, 50.0)));
  const ScannerConfig config = IdealScanner();
  ScanSimulator scanner(config, world, 1);
  Scan scan;
  std::vector<EchoSource> sources;
  scanner.Simulate(0.0, Standing({0, 0, 0}), &scan, &sources);
  ASSERT_EQ(scan.points.size(), std::size_t(config.beams() * config.layers));
  EXPECT_EQ(config.beams(), 581);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const ScanPoint& p = scan.points[i];
    const double a = double(p.angle_rad);
    ASSERT_TRUE(p.echo) << "beam " << i;
    EXPECT_EQ(sources[i], EchoSource::kObstacle);
    // The wall's face is x = 6 m: range 6 / cos(angle).
    EXPECT_NEAR(p.range_m, 6.0 / std::cos(a), 2e-5 * 6.0 / std::cos(a)) << a / kDeg;
  }
  EXPECT_EQ(scan.points[4 * 290].angle_rad, 0.0f);  // the middle beam looks straight ahead
  EXPECT_FLOAT_EQ(scan.points[4 * 290].range_m, 6.0f);

  // Moved to (-4, -20) and turned to face north, the wall is 10 m to the right: the upper
  // layers (whose footprints never reach the road) meet it where the geometry says.
  Scan turned;
  scanner.Simulate(0.0, Standing({-4.0, -20.0, M_PI / 2}), &turned);
  int checked = 0;
  for (const ScanPoint& p : turned.points) {
    if (p.layer < 2) continue;
    const double a = M_PI / 2 + double(p.angle_rad);  // world angle of the beam
    if (std::cos(a) <= 0.0) {
      EXPECT_FALSE(p.echo);  // looking away from the wall: nothing within 150 m
    } else if (10.0 / std::cos(a) < 149.0 && std::abs(-20.0 + 10.0 * std::tan(a)) < 49.0) {
      ASSERT_TRUE(p.echo);
      EXPECT_NEAR(p.range_m, 10.0 / std::cos(a), 1e-4);
      ++checked;
    }
  }
  EXPECT_GT(checked, 400);
}

TEST(Scanner, RangesAreQuantisedToTheResolution) {
  World world;
  world.obstacles.push_back(Wall(Box(6.03, -50.0, 7.0, 50.0)));
  ScannerConfig config = IdealScanner();
  config.range_resolution_m = 0.1;
  ScanSimulator scanner(config, world, 1);
  Scan scan;
  scanner.Simulate(0.0, Standing({0, 0, 0}), &scan);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const double a = config.beam_angle_deg(int(i / 4)) * kDeg;
    const double expected = std::round(6.03 / std::cos(a) / 0.1) * 0.1;
    ASSERT_TRUE(scan.points[i].echo);
    EXPECT_EQ(scan.points[i].range_m, float(expected)) << i;
  }
}

TEST(Scanner, LowObstaclesAreSeenOnlyByTheLayersReachingDownToThem) {
  // A 0.25 m kerb-like block at 5 m before a wall at 10 m. From 0.3 m the layers' footprints
  // at 5 m span about [0.16, 0.23], [0.23, 0.30], [0.30, 0.37] and [0.37, 0.44] m: layers 0
  // and 1 meet the block, layers 2 and 3 pass over it to the wall.
  World world;
  world.obstacles.push_back(Wall(Box(5.0, -1.0, 5.5, 1.0), 0.25));
  world.obstacles.push_back(Wall(Box(10.0, -50.0, 11.0, 50.0)));
  const ScannerConfig config = IdealScanner();
  ScanSimulator scanner(config, world, 1);
  Scan scan;
  scanner.Simulate(0.0, Standing({0, 0, 0}), &scan);
  const std::size_t ahead = 4 * 290;
  EXPECT_NEAR(scan.points[ahead + 0].range_m, 5.0, 1e-5);
  EXPECT_NEAR(scan.points[ahead + 1].range_m, 5.0, 1e-5);
  EXPECT_NEAR(scan.points[ahead + 2].range_m, 10.0, 1e-5);
  EXPECT_NEAR(scan.points[ahead + 3].range_m, 10.0, 1e-5);
}

TEST(Scanner, MovingMirrorSmearsPointsAtSpeed) {
  // Driving at 20 m/s towards a wall 30 m ahead of the sensor: the beams at the start of the
  // sweep (right edge) are taken 8 ms before the scan's time, 0.16 m farther back.
  World world;
  world.obstacles.push_back(Wall(Box(30.0, -100.0, 31.0, 100.0)));
  ScannerConfig config = IdealScanner();
  config.sweep_s = 0.016;
  Trajectory drive(Pose2D{0, 0, 0}, 20.0);
  drive.Drive({{200.0, 0.0}}, {{0.0, 20.0}, {200.0, 20.0}});
  ScanSimulator scanner(config, world, 1);
  Scan scan;
  scanner.Simulate(0.5, drive, &scan);  // the sensor is at x = 10 m at t = 0.5 s
  // Layer 2 (the lower layers reach the road before the wall at the aperture's edges).
  const ScanPoint& first = scan.points[2];
  const ScanPoint& middle = scan.points[4 * 290 + 2];
  const ScanPoint& last = scan.points[scan.points.size() - 2];
  EXPECT_NEAR(middle.range_m, 20.0, 1e-4);
  EXPECT_NEAR(first.range_m * std::cos(double(first.angle_rad)), 20.16, 1e-4);
  EXPECT_NEAR(last.range_m * std::cos(double(last.angle_rad)), 19.84, 1e-4);
}

TEST(Scanner, OpenSpaceBeyondRangeGivesNoEcho) {
  World world;
  world.obstacles.push_back(Wall(Box(200.0, -1.0, 201.0, 1.0)));  // beyond 150 m
  ScanSimulator scanner(IdealScanner(), world, 1);
  Scan scan;
  std::vector<EchoSource> sources;
  scanner.Simulate(0.0, Standing({0, 0, 0}), &scan, &sources);
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    EXPECT_FALSE(scan.points[i].echo);
    EXPECT_EQ(sources[i], EchoSource::kNoEchoRange);
  }
}

// Counts points of `source` (and of `layer` when >= 0) over `scans` scans.
long Count(const World& world, const ScannerConfig& config, int scans, EchoSource source, int layer,
           long* beams) {
  ScanSimulator scanner(config, world, 42);
  const Trajectory standing = Standing({0, 0, 0});
  Scan scan;
  std::vector<EchoSource> sources;
  long n = 0;
  *beams = 0;
  for (int k = 0; k < scans; ++k) {
    scanner.Simulate(0.04 * k, standing, &scan, &sources);
    for (std::size_t i = 0; i < sources.size(); ++i) {
      if (layer >= 0 && scan.points[i].layer != layer) continue;
      ++*beams;
      n += sources[i] == source ? 1 : 0;
    }
  }
  return n;
}

// |observed - expected| within 5 binomial standard deviations.
void ExpectRate(long n, long trials, double p) {
  const double sigma = std::sqrt(trials * p * (1.0 - p));
  EXPECT_NEAR(double(n), trials * p, 5.0 * sigma + 1.0) << n << " of " << trials << " at " << p;
}

TEST(Scanner, RainAndDustAppearAtTheConfiguredRate) {
  // In the top layer, whose beam never meets the road, every rain range (1 .. 40 m) counts.
  ScannerConfig config = IdealScanner();
  config.rain_probability = 0.05;
  long beams = 0;
  const long rain = Count(World{}, config, 20, EchoSource::kRain, 3, &beams);
  ExpectRate(rain, beams, 0.05);
}

TEST(Scanner, GroundEchoesComeFromTheLowLayersAtTheConfiguredRate) {
  // At pitch 0 layer 0's footprint (-1.6 .. -0.8 deg) lies wholly below the horizon: each of
  // its beams reaches the road between 10.7 and 21.5 m. Layers 2 and 3 never do.
  ScannerConfig config = IdealScanner();
  config.ground_echo_probability = 0.2;
  long beams = 0;
  const long ground = Count(World{}, config, 20, EchoSource::kGround, 0, &beams);
  ExpectRate(ground, beams, 0.2);
  EXPECT_EQ(Count(World{}, config, 5, EchoSource::kGround, 2, &beams), 0);
  EXPECT_EQ(Count(World{}, config, 5, EchoSource::kGround, 3, &beams), 0);
  // And layer 0 then sees nothing beyond 21.5 m: the road swallows the beam.
  World world;
  world.obstacles.push_back(Wall(Box(30.0, -200.0, 31.0, 200.0)));
  EXPECT_EQ(Count(world, config, 5, EchoSource::kObstacle, 0, &beams), 0);
  ScanSimulator scanner(config, world, 3);
  Scan scan;
  std::vector<EchoSource> sources;
  scanner.Simulate(0.0, Standing({0, 0, 0}), &scan, &sources);
  // Layer 0 echoes from the road between 10.7 and 21.5 m, layer 1 (-0.8 .. 0 deg) beyond.
  int seen[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    if (sources[i] != EchoSource::kGround) continue;
    const ScanPoint& p = scan.points[i];
    ++seen[p.layer];
    EXPECT_GE(p.range_m, p.layer == 0 ? 10.7f : 21.4f);
    EXPECT_LE(p.range_m, p.layer == 0 ? 21.5 : 30.0 / std::cos(double(p.angle_rad)));
  }
  EXPECT_GT(seen[0], 0);
  EXPECT_GT(seen[1], 0);
  EXPECT_EQ(seen[2] + seen[3], 0);
}

TEST(Scanner, WeakAndAbsorbedEchoesDropAtTheConfiguredRates) {
  ScannerConfig config = IdealScanner();
  config.detection_range_m = 80.0;
  // The detection model: a 0.1 reflectivity target head-on at detection_range_m is seen half
  // the time; weaker returns (darker, farther, more glancing) less often.
  EXPECT_DOUBLE_EQ(config.DetectionProbability(0.1, 1.0, config.detection_range_m), 0.5);
  EXPECT_GT(config.DetectionProbability(0.5, 1.0, 20.0), 0.999);
  EXPECT_LT(config.DetectionProbability(0.5, std::cos(88 * kDeg), 60.0),
            config.DetectionProbability(0.5, std::cos(60 * kDeg), 60.0));
  EXPECT_LT(config.DetectionProbability(0.05, 1.0, 60.0),
            config.DetectionProbability(0.5, 1.0, 60.0));

  // Glass (no_echo_probability 0.3) on a bright wall 10 m ahead.
  World glass;
  glass.obstacles.push_back(Wall(Box(10.0, -50.0, 11.0, 50.0)));
  glass.obstacles.back().no_echo_probability = 0.3;
  long beams = 0;
  const long absorbed = Count(glass, config, 10, EchoSource::kNoEchoAbsorbed, 3, &beams);
  ExpectRate(absorbed, beams, 0.3);

  // A dark wall (reflectivity 0.1) head-on at the detection range: about half the beams near
  // the middle of the aperture (within 2 deg, where the range and incidence barely change) of
  // the layers that do not meet the road first.
  World dark;
  dark.obstacles.push_back(Wall(Box(80.0, -50.0, 81.0, 50.0), 3.0, 0.1));
  ScanSimulator scanner(config, dark, 9);
  Scan scan;
  std::vector<EchoSource> sources;
  long weak = 0, middle = 0;
  double expected = 0.0;
  for (int k = 0; k < 40; ++k) {
    scanner.Simulate(0.04 * k, Standing({0, 0, 0}), &scan, &sources);
    for (std::size_t i = 0; i < sources.size(); ++i) {
      const double a = double(scan.points[i].angle_rad);
      if (std::abs(a) > 2.0 * kDeg || scan.points[i].layer < 2) continue;
      ++middle;
      weak += sources[i] == EchoSource::kNoEchoWeak ? 1 : 0;
      expected += 1.0 - config.DetectionProbability(0.1, std::cos(a), 80.0 / std::cos(a));
    }
  }
  ExpectRate(weak, middle, expected / middle);
  EXPECT_NEAR(expected / middle, 0.5, 0.01);
}

TEST(Trajectory, ReversesWhenAskedAndStaysContinuous) {
  Trajectory t(Pose2D{0, 0, 0});
  t.Drive({{10.0, 0.0}}, {{0.0, 0.0}, {5.0, 2.0}, {10.0, 0.0}});
  t.Wait(1.0);
  // Reversing: travel west along a right arc (towards the north), heading the other way.
  t.Drive({{M_PI * 2.5, -1.0 / 5.0}}, {{0.0, 0.0}, {M_PI * 1.25, 1.0}, {M_PI * 2.5, 0.0}}, true);
  const double stop = 10.0;  // 2 * 5 m / 2 m/s + 2 * 5 m / 2 m/s
  EXPECT_NEAR(t.At(stop).pose.x, 10.0, 1e-9);
  EXPECT_DOUBLE_EQ(t.At(stop).speed, 0.0);
  EXPECT_GT(t.At(2.0).speed, 0.0);
  EXPECT_GT(t.At(2.0).acceleration, 0.0);
  EXPECT_LT(t.At(7.0).acceleration, 0.0);  // braking
  // While reversing the speed is negative, the vehicle moves against its heading, and the
  // heading turns as the arc does (a quarter turn in all).
  const MotionState r0 = t.At(stop + 2.0), r1 = t.At(stop + 2.1);
  EXPECT_LT(r0.speed, 0.0);
  const Vec2 d(r1.pose.x - r0.pose.x, r1.pose.y - r0.pose.y);
  EXPECT_LT(d.dot(Vec2(std::cos(r0.pose.yaw), std::sin(r0.pose.yaw))), 0.0);
  const MotionState end = t.At(t.duration());
  EXPECT_NEAR(end.pose.x, 5.0, 1e-9);
  EXPECT_NEAR(end.pose.y, 5.0, 1e-9);
  EXPECT_NEAR(end.pose.yaw, -M_PI / 2, 1e-9);  // travelled north, so heading south
  // No jump anywhere: at most the top speed times the step.
  MotionState last = t.At(0.0);
  for (double s = 0.01; s <= t.duration(); s += 0.01) {
    const MotionState m = t.At(s);
    EXPECT_LE(std::hypot(m.pose.x - last.pose.x, m.pose.y - last.pose.y), 2.0 * 0.01 + 1e-9);
    last = m;
  }
  // A change of direction while moving is refused.
  Trajectory moving(Pose2D{0, 0, 0});
  moving.Drive({{10.0, 0.0}}, {{0.0, 0.0}, {10.0, 3.0}});
  EXPECT_THROW(moving.Drive({{5.0, 0.0}}, {{0.0, 3.0}, {5.0, 0.0}}, true), std::invalid_argument);
}

TEST(Trajectory, ScenariosDriveTheirProfiles) {
  // Highway: from standstill to 130 km/h. Parking: reverses into the bay, heading north.
  const Scenario highway = BuildScenario("highway", 1);
  EXPECT_DOUBLE_EQ(highway.trajectory.At(0.0).speed, 0.0);
  EXPECT_NEAR(highway.trajectory.At(30.0).speed, 130.0 / 3.6, 1e-9);
  const Scenario parking = BuildScenario("parking", 1);
  double slowest = 0.0, reversing_from = -1.0;
  for (double t = 0.0; t < parking.duration_s; t += 0.04) {
    const MotionState m = parking.trajectory.At(t);
    if (m.speed < slowest) slowest = m.speed;
    if (m.speed < 0.0 && reversing_from < 0.0) reversing_from = t;
  }
  EXPECT_NEAR(slowest, -1.2, 1e-9);
  EXPECT_GT(reversing_from, 5.0);
  const Scenario urban = BuildScenario("urban", 1);
  EXPECT_NEAR(urban.trajectory.At(urban.duration_s).pose.yaw, -M_PI / 2, 1e-9);  // turned right
  EXPECT_THROW(BuildScenario("moon", 1), std::invalid_argument);
}

TEST(Trajectory, TheCarNeverTouchesAStaticObstacle) {
  // The car's body along every drive of seeds 1-40, every 0.05 s: no static obstacle overlaps
  // it (a parked van too long for its bay, reaching into the aisle, is not parked there).
  const geometry::Polygon body = VehicleBody();
  for (const std::string& name : ScenarioNames()) {
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
      const Scenario sc = BuildScenario(name, seed);
      for (double t = 0.0; t <= sc.duration_s; t += 0.05) {
        const geometry::Polygon car = geometry::Transform(sc.trajectory.At(t).pose, body);
        for (const Obstacle& o : sc.world.obstacles) {
          if (o.mover >= 0) continue;
          ASSERT_EQ(geometry::SignedArea(geometry::ClipToConvex(o.shape, car)), 0.0)
              << name << " seed " << seed << " at " << t << " s";
        }
      }
    }
  }
}

TEST(Odometry, IsTheTruthWithoutNoiseAndDriftsWithIt) {
  const Scenario urban = BuildScenario("urban", 1);
  Odometry exact(OdometryNoise::Preset("none"), 1);
  Odometry poor(OdometryNoise::Preset("poor"), 1);
  double drift = 0.0;
  for (int k = 0; k <= 500; ++k) {
    const double t = 0.04 * k;
    const Pose2D truth = urban.trajectory.At(t).pose;
    const Pose2D a = exact.Update(t, truth);
    EXPECT_EQ(a.x, truth.x);
    EXPECT_EQ(a.y, truth.y);
    EXPECT_EQ(a.yaw, truth.yaw);
    const Pose2D b = poor.Update(t, truth);
    if (k == 0) {
      EXPECT_EQ(b.x, truth.x);
    }
    drift = std::hypot(b.x - truth.x, b.y - truth.y);
  }
  EXPECT_GT(drift, 0.1);  // 2 % of about 100 m plus the yaw bias
  EXPECT_LT(drift, 10.0);
  EXPECT_THROW(OdometryNoise::Preset("bad"), std::invalid_argument);
}

// Simulates `seconds` of `scenario` into `dir`; returns the scans.
std::vector<Scan> SimulateInto(const std::string& dir, const std::string& scenario,
                               std::uint64_t seed, double seconds, const std::string& noise) {
  std::filesystem::create_directories(dir);
  SimulationOptions options;
  options.scenario = scenario;
  options.seed = seed;
  options.duration_s = seconds;
  options.odometry = OdometryNoise::Preset(noise);
  Simulation simulation(options);
  SimulationWriter writer(dir, simulation.truth());
  std::vector<Scan> scans;
  Scan scan;
  while (simulation.Next(&scan)) {
    writer.Write(scan, simulation.last());
    scans.push_back(scan);
  }
  writer.Close();
  return scans;
}

TEST(Simulation, SameSeedWritesTheSameBytesAndALogReadsBackAsSimulated) {
  const std::string base = ::testing::TempDir() + "/sim_determinism";
  const std::vector<Scan> a = SimulateInto(base + "/a", "urban", 7, 2.0, "typical");
  SimulateInto(base + "/b", "urban", 7, 2.0, "typical");
  SimulateInto(base + "/c", "urban", 8, 2.0, "typical");
  ASSERT_EQ(a.size(), 51u);
  for (const char* file : {"/sim.fslog", "/sim.clf", "/truth.json"}) {
    const std::string first = ReadAll(base + "/a" + file);
    EXPECT_GT(first.size(), 1000u) << file;
    EXPECT_EQ(first, ReadAll(base + "/b" + file)) << file;
    EXPECT_NE(first, ReadAll(base + "/c" + file)) << file;
  }
  // The log read back is the simulated scans, bit for bit.
  auto reader = OpenLog(base + "/a/sim.fslog");
  EXPECT_EQ(reader->sensor().layers, 4);
  EXPECT_DOUBLE_EQ(reader->sensor().mount_x_m, 3.7);
  Scan scan;
  for (const Scan& expected : a) {
    ASSERT_TRUE(reader->Next(&scan));
    EXPECT_EQ(scan.timestamp_s, expected.timestamp_s);
    EXPECT_EQ(scan.pose.x, expected.pose.x);
    EXPECT_EQ(scan.pose.y, expected.pose.y);
    EXPECT_EQ(scan.pose.yaw, expected.pose.yaw);
    ASSERT_EQ(scan.points.size(), expected.points.size());
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      const ScanPoint& p = scan.points[i];
      const ScanPoint& q = expected.points[i];
      ASSERT_EQ(p.layer, q.layer);
      ASSERT_EQ(p.echo, q.echo);
      ASSERT_EQ(p.angle_rad, q.angle_rad);
      if (p.echo) {
        ASSERT_EQ(p.range_m, q.range_m) << i;
      }
    }
  }
  EXPECT_FALSE(reader->Next(&scan));
  EXPECT_TRUE(reader->TakeIssues().empty());
  // The ROBOTLASER1 file holds one line per layer and reads as 4-layer scans.
  auto carmen = OpenLog(base + "/a/sim.clf");
  ASSERT_TRUE(carmen->Next(&scan));
  EXPECT_EQ(carmen->sensor().layers, 4);
}

TEST(Simulation, TruthRoundTripsExactly) {
  const std::string dir = ::testing::TempDir() + "/sim_truth";
  SimulateInto(dir, "highway", 3, 1.0, "none");
  const Truth truth = ReadTruth(dir + "/truth.json");
  const Scenario scenario = BuildScenario("highway", 3);
  EXPECT_EQ(truth.scenario, "highway");
  EXPECT_EQ(truth.seed, 3u);
  ASSERT_EQ(truth.world.obstacles.size(), scenario.world.obstacles.size());
  EXPECT_EQ(truth.world.movers, scenario.world.movers);
  for (std::size_t i = 0; i < truth.world.obstacles.size(); ++i) {
    ASSERT_EQ(truth.world.obstacles[i].shape, scenario.world.obstacles[i].shape);
    ASSERT_EQ(truth.world.obstacles[i].mover, scenario.world.obstacles[i].mover);
  }
  ASSERT_EQ(truth.scans.size(), 26u);
  const TruthScan& s = truth.scans[25];
  EXPECT_DOUBLE_EQ(s.t, 1.0);
  const Pose2D pose = scenario.trajectory.At(1.0).pose;
  EXPECT_EQ(s.pose.x, pose.x);
  EXPECT_EQ(s.pose.yaw, pose.yaw);
  EXPECT_EQ(s.movers.size(), std::size_t(scenario.world.movers));
  EXPECT_EQ(s.movers[0].x, scenario.world.MoverPoses(1.0)[0].x);
  EXPECT_THROW(ReadTruth(dir + "/sim.fslog"), InputError);
}

TEST(Simulation, TypicalScenesHaveAboutTwoThousandEchoesAScan) {
  for (const std::string name : {"urban", "parking"}) {
    SimulationOptions options;
    options.scenario = name;
    options.duration_s = 0.4;
    Simulation simulation(options);
    Scan scan;
    long echoes = 0, scans = 0;
    while (simulation.Next(&scan)) {
      ++scans;
      for (const ScanPoint& p : scan.points) echoes += p.echo ? 1 : 0;
    }
    EXPECT_EQ(scan.points.size(), 2324u);
    EXPECT_GT(echoes / scans, 1500) << name;
    EXPECT_LT(echoes / scans, 2324) << name;
  }
}

}  // namespace
}  // namespace freespace::sim
