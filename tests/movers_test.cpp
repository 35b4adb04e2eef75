// The mover layer (polygon.mover_memory_s): scans ray-cast in a small world of boxes, a box that
// moves out of sight behind another, and a static world passed at speed.
#include "core/movers.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/preprocess.hpp"
#include "eval/scorer.hpp"
#include "freespace/estimator.hpp"
#include "sim/simulator.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

struct Box {
  double x0, y0, x1, y1;
};

// Distance along the ray from (ox, oy) in direction (dx, dy) to `box`, +inf when it misses.
double Hit(const Box& box, double ox, double oy, double dx, double dy) {
  double lo = 0.0, hi = 1e9;
  const double o[2] = {ox, oy}, d[2] = {dx, dy}, b0[2] = {box.x0, box.y0}, b1[2] = {box.x1, box.y1};
  for (int k = 0; k < 2; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (o[k] < b0[k] || o[k] > b1[k]) return INFINITY;
      continue;
    }
    double t0 = (b0[k] - o[k]) / d[k], t1 = (b1[k] - o[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
  }
  return lo <= hi ? lo : INFINITY;
}

// A ScaLa-like scan (145 deg at 0.25 deg; or `count` beams from `first_deg`) of `boxes` from
// `pose`: the nearest hit of each beam.
std::vector<Beam> ScanOf(const std::vector<Box>& boxes, const Pose2D& pose,
                         double first_deg = -72.5, int count = 581) {
  std::vector<Beam> beams;
  for (int i = 0; i < count; ++i) {
    const double a = (first_deg + 0.25 * i) * M_PI / 180.0;
    const double dx = std::cos(pose.yaw + a), dy = std::sin(pose.yaw + a);
    double r = INFINITY;
    for (const Box& box : boxes) r = std::min(r, Hit(box, pose.x, pose.y, dx, dy));
    Beam b;
    b.angle = float(a);
    b.range = float(std::isfinite(r) ? r : 100.0);
    b.is_virtual = !std::isfinite(r);
    b.x = float(b.range * std::cos(a));
    b.y = float(b.range * std::sin(a));
    beams.push_back(b);
  }
  return beams;
}

MoverRule Rule() {
  MoverRule rule;
  rule.memory_s = 3.0;
  rule.bin_width_rad = 0.25 * M_PI / 180.0;
  return rule;
}

MapFrame Frame() {
  MapFrame f;
  f.origin = Vec2(-10.0, -30.0);
  f.resolution_m = 0.2;
  f.width = f.height = 300;
  return f;
}

// The cells whose centre lies inside `box`.
std::set<std::int32_t> CellsOf(const Box& box, const MapFrame& f) {
  std::set<std::int32_t> cells;
  for (int r = 0; r < f.height; ++r) {
    for (int c = 0; c < f.width; ++c) {
      const double x = f.origin.x() + (c + 0.5) * f.resolution_m;
      const double y = f.origin.y() + (r + 0.5) * f.resolution_m;
      if (x > box.x0 && x < box.x1 && y > box.y0 && y < box.y1) cells.insert(r * f.width + c);
    }
  }
  return cells;
}

TEST(MoverLayer, InsideOutline) {
  MoverTracker::Outline outline;
  outline.pose = {1.0, 2.0, M_PI / 2};  // looking along +y
  outline.cos_yaw = 0.0;
  outline.sin_yaw = 1.0;
  for (int i = -4; i <= 4; ++i) {
    outline.angle.push_back(float(0.01 * i));
    outline.range.push_back(10.0f);
  }
  const double bin = 0.01;
  EXPECT_TRUE(InsideOutline(outline, Vec2(1.0, 7.0), bin, 0.5));
  EXPECT_FALSE(InsideOutline(outline, Vec2(1.0, 11.8), bin, 0.5));  // 9.8 m: within the margin
  EXPECT_FALSE(InsideOutline(outline, Vec2(1.0, 13.0), bin, 0.0));  // beyond the outline
  EXPECT_FALSE(InsideOutline(outline, Vec2(4.0, 7.0), bin, 0.0));   // outside the aperture
  EXPECT_FALSE(InsideOutline(outline, Vec2(1.0, -3.0), bin, 0.0));  // behind the sensor
  // A pole two beams to the side: the point is inside unless the spread reaches the pole.
  outline.range[2] = 3.0f;                                                      // at -0.02 rad
  const Vec2 beside(1.0 + 5.0 * std::sin(0.005), 2.0 + 5.0 * std::cos(0.005));  // at -0.005 rad
  EXPECT_TRUE(InsideOutline(outline, beside, bin, 0.5));
  std::size_t at = 0;
  EXPECT_FALSE(InsideOutline(outline, beside, bin, 0.5, 2, &at));
  EXPECT_EQ(at, 4u);
}

TEST(MoverLayer, FastAtan2) {
  for (int i = -720; i <= 720; ++i) {
    const double a = i * M_PI / 720.0 * 0.999;
    for (const double r : {0.05, 1.0, 150.0}) {
      EXPECT_NEAR(FastAtan2(float(r * std::sin(a)), float(r * std::cos(a))), a, 2e-5) << a;
    }
  }
}

TEST(MoverLayer, FastAtan2AtTheOriginAndOnTheAxes) {
  EXPECT_EQ(FastAtan2(0.0f, 0.0f), 0.0f);
  EXPECT_EQ(FastAtan2(-0.0f, -0.0f), 0.0f);
  EXPECT_NEAR(FastAtan2(0.0f, 2.0f), 0.0, 1e-7);
  EXPECT_NEAR(FastAtan2(2.0f, 0.0f), M_PI / 2, 1e-6);
  EXPECT_NEAR(FastAtan2(-2.0f, 0.0f), -M_PI / 2, 1e-6);
  EXPECT_NEAR(FastAtan2(0.0f, -2.0f), M_PI, 1e-6);
  EXPECT_NEAR(FastAtan2(1.0f, 1.0f), M_PI / 4, 2e-5);
  EXPECT_NEAR(FastAtan2(-1.0f, -1.0f), -3 * M_PI / 4, 2e-5);
}

// The pass over many points (ToOutlineFrame) answers as the test of one point does, hint and all.
TEST(MoverLayer, OutlineFrameAgreesWithOnePoint) {
  MoverTracker::Outline outline;
  outline.pose = Pose2D{3.0, -1.0, 0.7};
  outline.cos_yaw = std::cos(0.7);
  outline.sin_yaw = std::sin(0.7);
  const double bin = 0.25 * M_PI / 180.0;
  for (int i = 0; i < 400; ++i) {
    outline.angle.push_back(float(-0.8 + i * bin));
    outline.range.push_back(float(6.0 + 3.0 * std::sin(i * 0.05)));
  }
  std::vector<Vec2> points;
  for (int i = 0; i < 1000; ++i) {
    const double a = 0.7 - 1.0 + i * 0.0021, r = 2.0 + 0.011 * i;
    points.push_back(Vec2(3.0 + r * std::cos(a), -1.0 + r * std::sin(a)));
  }
  points.push_back(Vec2(3.0, -1.0));  // the sensor itself
  OutlineFrame frame;
  ToOutlineFrame(outline, points, &frame);
  ASSERT_EQ(frame.angle.size(), points.size());
  std::size_t hint_one = 0, hint_many = 0;
  int inside = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    // The pass's angle, to the bit, is the one-point function's of the pass's coordinates.
    EXPECT_EQ(frame.angle[k], FastAtan2(float(frame.y[k]), float(frame.x[k]))) << k;
    const bool one = InsideOutline(outline, points[k], bin, 0.3, kSpread, &hint_one);
    const bool many = InsideOutlineAt(outline, frame, k, bin, 0.3, kSpread, &hint_many);
    EXPECT_EQ(one, many) << k;
    EXPECT_EQ(hint_one, hint_many) << k;
    inside += many;
  }
  EXPECT_GT(inside, 50);
  EXPECT_LT(inside, 950);
}

TEST(MoverLayer, OffWithoutMemory) {
  Config c;
  c.polygon.shape = PolygonShape::kInside;
  EXPECT_FALSE(MoverTracker(MoverRule::Of(c)).enabled());
  c.polygon.mover_memory_s = 2.0;
  EXPECT_TRUE(MoverTracker(MoverRule::Of(c)).enabled());
  c.polygon.shape = PolygonShape::kPaper;
  EXPECT_FALSE(MoverTracker(MoverRule::Of(c)).enabled());
}

// A car-sized box crosses the view at 10 m/s and drives behind a wall: while out of sight, the
// hazard holds where it is now, not where it was last seen, and never a cell the scan sees.
TEST(MoverLayer, FollowsACarOutOfSight) {
  const Box back{40.0, -60.0, 41.0, 60.0}, wall{7.0, 2.0, 8.0, 30.0};
  MoverTracker movers(Rule());
  const MapFrame frame = Frame();
  const Pose2D sensor{0.0, 0.0, 0.0};
  const double speed = 10.0;
  double last_seen_y = -1e9;
  int checked = 0;
  for (int k = 0; k <= 75; ++k) {
    const double t = 0.04 * k;
    const double y = -10.0 + speed * t;  // the car's rear
    const Box car{14.0, y, 16.0, y + 4.5};
    const std::vector<Beam> beams = ScanOf({back, wall, car}, sensor);
    const bool visible = std::any_of(beams.begin(), beams.end(), [&](const Beam& b) {
      const double bx = b.x, by = b.y;
      return bx >= 13.99 && bx <= 16.01 && by >= y - 0.01 && by <= y + 4.51;
    });
    if (visible) last_seen_y = y;
    movers.BeginCycle(t);
    movers.Observe(0, sensor, t, beams);
    std::vector<std::int32_t> hazard;
    movers.Hazard(t, frame, &hazard);
    // No repeats, all inside the map.
    std::set<std::int32_t> unique(hazard.begin(), hazard.end());
    ASSERT_EQ(unique.size(), hazard.size());
    for (std::int32_t cell : hazard) ASSERT_TRUE(cell >= 0 && cell < 300 * 300);
    if (visible || t - 0.04 > 1.0 + (last_seen_y + 10.0) / speed) continue;
    // Out of sight for up to a second: the car's cells now are held.
    ++checked;
    const std::set<std::int32_t> now = CellsOf(car, frame);
    int held = 0;
    for (std::int32_t cell : now) held += unique.count(cell);
    EXPECT_GE(held, int(0.95 * double(now.size()))) << "t " << t;
    // Where its rear was last seen, 8 m and more behind it now, is not held.
    const std::set<std::int32_t> then =
        CellsOf({14.0, last_seen_y - 0.5, 16.0, last_seen_y + 0.5}, frame);
    if (y - last_seen_y > 8.0) {
      for (std::int32_t cell : then) EXPECT_EQ(unique.count(cell), 0u) << "t " << t;
    }
  }
  EXPECT_GT(checked, 10);
  EXPECT_EQ(movers.movers(), 1);
}

// Overtaking a truck at 36 against its 22 m/s: the part of it in sight shrinks to its front as
// the aperture passes it, and its speed is still its own; once it is behind the scanner, the
// hazard holds its near side.
TEST(MoverLayer, OvertakenTruck) {
  const Box left{-100.0, 12.0, 400.0, 13.0}, right{-100.0, -14.0, 400.0, -13.0};
  MoverTracker movers(Rule());
  MapFrame frame = Frame();
  int checked = 0;
  for (int k = 0; k <= 150; ++k) {
    const double t = 0.04 * k;
    const Pose2D sensor{36.0 * t, 0.0, 0.0};
    const double rear = 40.0 + 22.0 * t;
    const Box truck{rear, -8.3, rear + 16.5, -5.7};
    movers.BeginCycle(t);
    movers.Observe(0, sensor, t, ScanOf({left, right, truck}, sensor));
    if (rear + 16.5 > sensor.x + 1.0) continue;  // not yet wholly behind the scanner
    frame.origin = Vec2(sensor.x - 30.0, -30.0);
    std::vector<Vec2> v = movers.mover_velocities();
    ASSERT_EQ(v.size(), 1u) << "t " << t;
    EXPECT_NEAR(v[0].x(), 22.0, 1.5);
    EXPECT_NEAR(v[0].y(), 0.0, 1.0);
    std::vector<std::int32_t> hazard;
    movers.Hazard(t, frame, &hazard);
    const std::set<std::int32_t> held(hazard.begin(), hazard.end());
    const std::set<std::int32_t> near_side = CellsOf({rear, -6.5, rear + 16.5, -5.7}, frame);
    int in = 0;
    for (std::int32_t cell : near_side) in += held.count(cell);
    EXPECT_GE(in, int(0.95 * double(near_side.size()))) << "t " << t;
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

// A scanner all around, its beams from 90 to 450 deg (so they cross 180 deg), sees a car cross in
// front of it, in the part of the scan past 180 deg: the outline runs on, and the car is followed.
TEST(MoverLayer, ApertureAcross180Deg) {
  const std::vector<Box> walls = {{-21.0, -21.0, 21.0, -20.0},
                                  {-21.0, 20.0, 21.0, 21.0},
                                  {-21.0, -20.0, -20.0, 20.0},
                                  {20.0, -20.0, 21.0, 20.0}};
  MoverTracker movers(Rule());
  const Pose2D sensor{0.0, 0.0, 0.0};
  for (int k = 0; k <= 40; ++k) {
    const double t = 0.04 * k;
    const double y = -9.0 + 10.0 * t;
    std::vector<Box> world = walls;
    world.push_back({10.0, y, 12.0, y + 4.5});
    movers.BeginCycle(t);
    movers.Observe(0, sensor, t, ScanOf(world, sensor, 90.0, 1440));
  }
  const std::vector<Vec2> v = movers.mover_velocities();
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NEAR(v[0].x(), 0.0, 1.0);
  EXPECT_NEAR(v[0].y(), 10.0, 1.5);
}

TEST(MoverLayer, ForgetsAfterMemory) {
  const Box back{40.0, -60.0, 41.0, 60.0}, wall{7.0, 2.0, 8.0, 30.0};
  MoverRule rule = Rule();
  rule.memory_s = 0.5;
  MoverTracker movers(rule);
  const Pose2D sensor{0.0, 0.0, 0.0};
  double t = 0.0;
  for (int k = 0; k <= 150; ++k) {
    t = 0.04 * k;
    const double y = -10.0 + 10.0 * t;
    movers.BeginCycle(t);
    movers.Observe(0, sensor, t, ScanOf({back, wall, Box{14.0, y, 16.0, y + 4.5}}, sensor));
  }
  // Out of sight since about t = 1.5 s.
  EXPECT_EQ(movers.tracks(), 0);
  std::vector<std::int32_t> hazard;
  movers.Hazard(t, Frame(), &hazard);
  EXPECT_TRUE(hazard.empty());
}

// Driving at 30 m/s past parked cars, posts and a wall: nothing moves, nothing is held.
TEST(MoverLayer, StaticWorldFromAMovingSensor) {
  std::vector<Box> world = {{-50.0, 8.0, 400.0, 9.0}, {-50.0, -9.0, 400.0, -8.0}};
  for (int i = 0; i < 30; ++i) {
    const double x = 10.0 + 11.0 * i;
    world.push_back({x, -6.5, x + 4.5, -4.7});      // parked cars
    world.push_back({x + 6.0, 5.0, x + 6.3, 5.3});  // posts
  }
  MoverTracker movers(Rule());
  MapFrame frame = Frame();
  for (int k = 0; k < 200; ++k) {
    const double t = 0.04 * k;
    const Pose2D sensor{30.0 * t, 0.0, 0.01 * std::sin(t)};
    movers.BeginCycle(t);
    movers.Observe(0, sensor, t, ScanOf(world, sensor));
    frame.origin = Vec2(sensor.x - 10.0, -30.0);
    std::vector<std::int32_t> hazard;
    movers.Hazard(t, frame, &hazard);
    ASSERT_TRUE(hazard.empty()) << "t " << t;
  }
  EXPECT_EQ(movers.movers(), 0);
}

// The road setup on the simulated highway while the car overtakes a truck and passes traffic
// (seed 1, 20 .. 31 s): without the layer the polygon holds the overtaken vehicles behind the
// scanner; with it, their place is kept out.
TEST(MoverLayer, KeepsOvertakenTrafficOutOfThePolygon) {
  sim::SimulationOptions options;
  options.scenario = "highway";
  options.seed = 1;
  options.duration_s = 31.0;
  sim::Simulation simulation(options);
  Config config = test::LoadProjectConfig("scala.yaml");
  config.sensor = simulation.truth().scanner.EngineSensor();
  ASSERT_GT(config.polygon.mover_memory_s, 0.0);
  Estimator with(config);
  config.polygon.mover_memory_s = 0.0;
  Estimator without(config);
  sim::TruthScorer score_with(simulation.truth()), score_without(simulation.truth());
  double moving_with = 0.0, moving_without = 0.0, area_with = 0.0, area_without = 0.0;
  int scans = 0;
  Scan scan;
  while (simulation.Next(&scan)) {
    if (scan.timestamp_s < 20.0) continue;
    const Result& a = with.Process(scan);
    const ScanMetrics ma = score_with.Score(score_with.Find(a.timestamp_s), with.map(), a);
    const Result& b = without.Process(scan);
    const ScanMetrics mb = score_without.Score(score_without.Find(b.timestamp_s), without.map(), b);
    moving_with += ma.intrusion_moving_m2;
    moving_without += mb.intrusion_moving_m2;
    area_with += ma.polygon_area_m2;
    area_without += mb.polygon_area_m2;
    ++scans;
  }
  ASSERT_GT(scans, 250);
  EXPECT_GT(moving_without / scans, 1.0);
  EXPECT_LT(moving_with / scans, 0.05);
  // The polygon keeps most of its area: only the movers' places go.
  EXPECT_GT(area_with, 0.85 * area_without);
}

}  // namespace
}  // namespace freespace
