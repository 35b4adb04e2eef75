// Capped Douglas-Peucker (paper IV.B, Fig. 7): N and epsilon each bind, the most deviating
// vertices are kept first, the result stays within its reported error, and it keeps the
// vehicle inside. The conservative polygon (polygon.shape inside) on random free masks: it
// covers free cells only, is star-shaped around the sensor, has at most N vertices, and on an
// open map is the whole rectangle its border rays reach. Its safety margin on hand-made maps:
// exactly the cells within k of an occupied cell in the cone, never the sensor's own.
#include <random>

#include "core/inside_polygon.hpp"
#include "core/margin.hpp"
#include "core/simplifier.hpp"
#include "geometry/geometry.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

// A wavy closed outline, counter-clockwise, like a free-space border in a cluttered street.
std::vector<Vec2> Wavy(int n, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-amplitude, amplitude);
  std::vector<Vec2> ring;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    const double r = 40 + 10 * std::sin(3 * a) + 4 * std::sin(11 * a) + noise(rng);
    ring.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return ring;
}

std::vector<Vec2> Pick(const std::vector<Vec2>& ring, const std::vector<int>& kept) {
  std::vector<Vec2> out;
  for (const int i : kept) out.push_back(ring[i]);
  return out;
}

double MaxDeviation(const std::vector<Vec2>& ring, const std::vector<int>& kept) {
  double worst = 0;
  const int n = int(ring.size());
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const int a = kept[k], b = kept[(k + 1) % kept.size()];
    for (int i = (a + 1) % n; i != b; i = (i + 1) % n) {
      worst = std::max(worst, DistanceToSegment(ring[i], ring[a], ring[b]));
    }
  }
  return worst;
}

TEST(Polygon, EpsilonBindsWhenNIsLarge) {
  const auto ring = Wavy(400, 0.5, 1);
  std::vector<int> a, b;
  PolygonSimplifier loose(1000, 2.0), looser_cap(4000, 2.0);
  loose.Simplify(ring, Vec2(0, 0), &a);
  looser_cap.Simplify(ring, Vec2(0, 0), &b);
  EXPECT_EQ(a, b);  // raising N changes nothing: epsilon stopped it (Fig. 7 D)
  EXPECT_LT(int(a.size()), 1000);
  EXPECT_LE(MaxDeviation(ring, a), 2.0);
}

TEST(Polygon, NBindsWhenEpsilonIsSmall) {
  const auto ring = Wavy(400, 0.5, 2);
  std::vector<int> a, b;
  PolygonSimplifier fine(16, 0.01), finer(16, 0.0);
  const double error = fine.Simplify(ring, Vec2(0, 0), &a);
  finer.Simplify(ring, Vec2(0, 0), &b);
  EXPECT_EQ(a.size(), 16u);
  EXPECT_EQ(a, b);  // lowering epsilon changes nothing: N stopped it (Fig. 7 A)
  EXPECT_GT(error, 0.01);
  EXPECT_NEAR(error, MaxDeviation(ring, a), 1e-12);  // the reported error is the true one
}

TEST(Polygon, CappedResultKeepsTheMostImportantVertex) {
  // A 20 x 20 square, slightly noisy, with one spike 10 out: with N = 5 the spike survives.
  std::vector<Vec2> ring;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  for (int i = 0; i < 20; ++i) ring.emplace_back(i, noise(rng));
  for (int i = 0; i < 20; ++i) ring.emplace_back(20, i + noise(rng));
  for (int i = 0; i < 10; ++i) ring.emplace_back(20 - i, 20 + noise(rng));
  ring.emplace_back(10, 30);  // the spike
  for (int i = 10; i < 20; ++i) ring.emplace_back(20 - i, 20 + noise(rng));
  for (int i = 0; i < 20; ++i) ring.emplace_back(noise(rng), 20 - i);
  const int spike = 50;
  std::vector<int> kept;
  PolygonSimplifier s(5, 0.1);
  s.Simplify(ring, Vec2(10, 10), &kept);
  EXPECT_EQ(kept.size(), 5u);
  EXPECT_NE(std::find(kept.begin(), kept.end(), spike), kept.end());
}

TEST(Polygon, KeepsTheVehicleInside) {
  // A long thin room with a bump; the vehicle sits in the bump. Plain Douglas-Peucker with
  // epsilon 1.5 would drop the bump's tip and leave the vehicle outside.
  const std::vector<Vec2> ring = {{-10, -1}, {10, -1}, {10, 1}, {1, 1}, {0, 2}, {-1, 1}, {-10, 1}};
  const Vec2 vehicle(0, 1.5);
  std::vector<int> kept;
  PolygonSimplifier s(10, 1.5);
  s.Simplify(ring, vehicle, &kept);
  EXPECT_TRUE(PointInPolygon(Pick(ring, kept), vehicle));
  EXPECT_NE(std::find(kept.begin(), kept.end(), 4), kept.end());
}

TEST(Polygon, AtLeastThreeVerticesAndSmallRingsUnchanged) {
  std::vector<int> kept;
  PolygonSimplifier s(32, 100.0);
  const std::vector<Vec2> square = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  s.Simplify(square, Vec2(0.5, 0.5), &kept);
  EXPECT_GE(kept.size(), 3u);
  s.Simplify({{0, 0}, {1, 1}}, Vec2(0, 0), &kept);
  EXPECT_EQ(kept.size(), 2u);
}

// A free mask (1 = free) of random rectangles and single cells that are not free, on an open
// map; border cells stay free or not at random too.
std::vector<std::uint8_t> RandomMask(int width, int height, std::mt19937* rng) {
  std::vector<std::uint8_t> free(std::size_t(width) * height, 1);
  std::uniform_int_distribution<int> col(0, width - 1), row(0, height - 1), size(1, 4),
      count(0, 12);
  for (int k = count(*rng); k > 0; --k) {
    const int c = col(*rng), r = row(*rng), w = size(*rng), h = size(*rng);
    for (int y = r; y < std::min(height, r + h); ++y) {
      for (int x = c; x < std::min(width, c + w); ++x) free[std::size_t(y) * width + x] = 0;
    }
  }
  for (int k = count(*rng) * 3; k > 0; --k) free[std::size_t(row(*rng)) * width + col(*rng)] = 0;
  return free;
}

// Area of `polygon` on cells that are not free (cells^2).
double AreaOnNotFree(const std::vector<Vec2>& polygon, const std::vector<std::uint8_t>& free,
                     int width, int height) {
  double area = 0.0;
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      if (!free[std::size_t(r) * width + c])
        area += geometry::AreaInBox(polygon, c, r, c + 1, r + 1);
    }
  }
  return area;
}

// Consecutive vertices never turn clockwise around `sensor` and go round it at most once.
void ExpectStarShaped(const std::vector<Vec2>& polygon, const Vec2& sensor) {
  double turned = 0.0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Vec2 u = polygon[k] - sensor, v = polygon[(k + 1) % polygon.size()] - sensor;
    if (u.norm() < 1e-12 || v.norm() < 1e-12) continue;
    const double cross = u.x() * v.y() - u.y() * v.x();
    EXPECT_GE(cross, -1e-9 * u.norm() * v.norm()) << "edge " << k << " turns clockwise";
    turned += std::atan2(cross, u.dot(v));
  }
  EXPECT_LE(turned, 2 * M_PI + 1e-9);
}

TEST(InsidePolygon, CoversFreeCellsOnlyOnRandomMasks) {
  std::mt19937 rng(7);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int width = 12 + int(rng() % 40), height = 12 + int(rng() % 40);
    const std::vector<std::uint8_t> free = RandomMask(width, height, &rng);
    // The sensor anywhere in the map; every fourth time on a cell corner or edge exactly.
    std::uniform_real_distribution<double> x(1.0, width - 1.0), y(1.0, height - 1.0);
    Vec2 sensor(x(rng), y(rng));
    if (trial % 4 == 0) sensor = Vec2(std::round(sensor.x()), std::round(sensor.y()));
    if (trial % 4 == 1) sensor.x() = std::round(sensor.x());
    const int n = std::vector<int>{3, 5, 8, 32, 4096}[trial % 5];
    const double epsilon = trial % 3 == 0 ? 0.0 : 1.0;
    InsidePolygonBuilder builder(width, height, n, epsilon);
    std::vector<Vec2> polygon;
    builder.Build(free.data(), sensor, &polygon);
    const std::string where = "trial " + std::to_string(trial);
    ASSERT_GE(polygon.size(), 3u) << where;
    ASSERT_LE(int(polygon.size()), n) << where;
    EXPECT_LE(AreaOnNotFree(polygon, free, width, height), 1e-6) << where;
    ExpectStarShaped(polygon, sensor);
    // The traced rays of the unsimplified ring never pass through a not-free cell's inside.
    for (const Vec2& v : builder.ring()) {
      for (int k = 1; k < 200; ++k) {
        const Vec2 q = sensor + (k / 200.0) * (v - sensor);
        const double fx = q.x() - std::floor(q.x()), fy = q.y() - std::floor(q.y());
        if (fx < 1e-9 || fx > 1 - 1e-9 || fy < 1e-9 || fy > 1 - 1e-9) continue;
        ASSERT_TRUE(free[std::size_t(std::floor(q.y())) * width + int(std::floor(q.x()))])
            << where << ": ray to " << v.transpose() << " passes " << q.transpose();
      }
    }
    const int sc = int(std::floor(sensor.x())), sr = int(std::floor(sensor.y()));
    if (!free[std::size_t(sr) * width + sc]) {
      // No free cell holds the sensor: the polygon is the sensor point.
      for (const Vec2& v : polygon) EXPECT_EQ(v, sensor) << where;
    } else {
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
}

TEST(InsidePolygon, OpenMapGivesTheBorderCentresRectangle) {
  // Everything free: each border ray reaches its cell's centre, Douglas-Peucker keeps the four
  // corners, nothing is pulled in: the rectangle of the border cells' centres.
  const int width = 30, height = 20;
  const std::vector<std::uint8_t> free(std::size_t(width) * height, 1);
  for (const Vec2& sensor : {Vec2(7.3, 11.9), Vec2(15, 10), Vec2(1.2, 18.7)}) {
    InsidePolygonBuilder builder(width, height, 32, 0.0);
    std::vector<Vec2> polygon;
    EXPECT_EQ(builder.Build(free.data(), sensor, &polygon), 0.0);
    EXPECT_NEAR(std::abs(geometry::SignedArea(polygon)), (width - 1.0) * (height - 1.0), 1e-9);
    EXPECT_TRUE(PointInPolygon(polygon, sensor));
  }
}

TEST(InsidePolygon, PullsACappedEdgeInFrontOfTheObstacleItCuts) {
  // One not-free cell (10, 10) in an open 21 x 21 map, the sensor at (10.5, 5.5) south of it.
  // The rays north stop at the cell's south face y = 10; with N = 4 the simplified polygon
  // cannot follow the notch, and the edge across it is pulled in to y <= 10 there.
  const int size = 21;
  std::vector<std::uint8_t> free(std::size_t(size) * size, 1);
  free[10 * size + 10] = 0;
  const Vec2 sensor(10.5, 5.5);
  for (const int n : {4, 8, 4096}) {
    InsidePolygonBuilder builder(size, size, n, 0.0);
    std::vector<Vec2> polygon;
    builder.Build(free.data(), sensor, &polygon);
    EXPECT_LE(AreaOnNotFree(polygon, free, size, size), 1e-9) << "N " << n;
    EXPECT_TRUE(PointInPolygon(polygon, sensor));
    EXPECT_LE(int(polygon.size()), n);
    // The straight line north from the sensor ends on the cell's face.
    double north = 0.0;
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      const Vec2& a = polygon[k];
      const Vec2& b = polygon[(k + 1) % polygon.size()];
      if ((a.x() - sensor.x()) * (b.x() - sensor.x()) <= 0 && a.x() != b.x()) {
        const double y = a.y() + (b.y() - a.y()) * (sensor.x() - a.x()) / (b.x() - a.x());
        if (y > sensor.y()) north = std::max(north, y);
      }
    }
    EXPECT_LE(north, 10.0 + 1e-9) << "N " << n;
    EXPECT_GT(north, 5.5) << "N " << n;
  }
}

// A hand-made map as rows of text, the top line the northern row: '.' free, '#' occupied
// (log-odds above 0, not free), 'o' the sensor's cell (free), 'x' free but expected to be kept
// out by the margin. Fills the free mask (with 'x' free), the log-odds and the expected mask.
struct TextMap {
  int width = 0, height = 0;
  std::vector<std::uint8_t> free, expected;
  std::vector<LogOdds> log_odds;
  Vec2 sensor;
  explicit TextMap(const std::vector<std::string>& rows) {
    height = int(rows.size());
    width = int(rows[0].size());
    free.assign(std::size_t(width) * height, 1);
    expected = free;
    log_odds.assign(free.size(), LogOdds{-100});
    for (int r = 0; r < height; ++r) {
      for (int c = 0; c < width; ++c) {
        const char t = rows[height - 1 - r][c];
        const std::size_t i = std::size_t(r) * width + c;
        if (t == '#') free[i] = expected[i] = 0, log_odds[i] = 100;
        if (t == 'x') expected[i] = 0;
        if (t == 'o') sensor = Vec2(c + 0.5, r + 0.5);
      }
    }
  }
};

TEST(PolygonMargin, KeepsOutTheCellsInFrontOfAWallAsTheSensorSeesIt) {
  // A wall three rows north of the sensor: with a 60 deg cone the cells in front of it go;
  // those beside its ends (which see it at 90 deg or more) and those behind it stay.
  TextMap cone({
      ".........",
      "..#####..",
      "..xxxxx..",
      ".........",
      ".........",
      "....o....",
  });
  std::vector<std::uint8_t> free = cone.free;
  PolygonMargin(cone.width, cone.height, 1, 60.0)
      .Apply(cone.log_odds.data(), cone.sensor, free.data());
  EXPECT_EQ(free, cone.expected);
  // All around (180 deg): every free cell within one cell of the wall.
  TextMap all({
      ".xxxxxxx.",
      ".x#####x.",
      ".xxxxxxx.",
      ".........",
      ".........",
      "....o....",
  });
  free = all.free;
  PolygonMargin(all.width, all.height, 1, 180.0)
      .Apply(all.log_odds.data(), all.sensor, free.data());
  EXPECT_EQ(free, all.expected);
  // Two cells, 60 deg: the second row in front too; the cells diagonally beyond the wall's
  // ends still see it at more than 60 deg.
  TextMap two({
      ".........",
      "..#####..",
      "..xxxxx..",
      "..xxxxx..",
      ".........",
      "....o....",
  });
  free = two.free;
  PolygonMargin(two.width, two.height, 2, 60.0).Apply(two.log_odds.data(), two.sensor, free.data());
  EXPECT_EQ(free, two.expected);
}

TEST(PolygonMargin, TheSensorsOwnCellStaysAndThePolygonHoldsTheVehicle) {
  // An occupied cell right next to the sensor: its own cell stays free, the polygon is not
  // empty and contains the sensor.
  TextMap map({
      "..........",
      "..........",
      ".....#....",
      "....o.....",
      "..........",
  });
  for (const double cone : {60.0, 180.0}) {
    std::vector<std::uint8_t> free = map.free;
    PolygonMargin(map.width, map.height, 1, cone)
        .Apply(map.log_odds.data(), map.sensor, free.data());
    const std::size_t own = std::size_t(std::floor(map.sensor.y())) * map.width +
                            std::size_t(std::floor(map.sensor.x()));
    EXPECT_TRUE(free[own]) << "cone " << cone;
    InsidePolygonBuilder builder(map.width, map.height, 32, 0.0);
    std::vector<Vec2> polygon;
    builder.Build(free.data(), map.sensor, &polygon);
    EXPECT_TRUE(PointInPolygon(polygon, map.sensor)) << "cone " << cone;
    EXPECT_GT(std::abs(geometry::SignedArea(polygon)), 1.0) << "cone " << cone;
    EXPECT_LE(AreaOnNotFree(polygon, free, map.width, map.height), 1e-9) << "cone " << cone;
  }
}

TEST(PolygonMargin, PolygonCoversNoFreeCellWithinTheMarginOfAnOccupiedCell) {
  // Random maps, every not-free cell occupied: with the margin all around, the polygon has no
  // area on any cell within k cells of an occupied one (but the sensor's own); the cells the
  // margin keeps out are exactly those.
  std::mt19937 rng(11);
  int checked = 0;
  for (int trial = 0; trial < 120; ++trial) {
    const int width = 16 + int(rng() % 30), height = 16 + int(rng() % 30);
    const std::vector<std::uint8_t> mask = RandomMask(width, height, &rng);
    std::vector<LogOdds> log_odds(mask.size());
    for (std::size_t i = 0; i < mask.size(); ++i) log_odds[i] = mask[i] ? -50 : 50;
    std::uniform_real_distribution<double> x(1.0, width - 1.0), y(1.0, height - 1.0);
    const Vec2 sensor(x(rng), y(rng));
    const int sc = int(std::floor(sensor.x())), sr = int(std::floor(sensor.y()));
    const int k = 1 + trial % 3;
    std::vector<std::uint8_t> free = mask;
    PolygonMargin(width, height, k, 180.0).Apply(log_odds.data(), sensor, free.data());
    std::vector<std::uint8_t> near(mask.size(), 0);  // within k of an occupied cell
    for (int r = 0; r < height; ++r) {
      for (int c = 0; c < width; ++c) {
        for (int dr = -k; dr <= k; ++dr) {
          for (int dc = -k; dc <= k; ++dc) {
            const int rr = r + dr, cc = c + dc;
            if (rr >= 0 && cc >= 0 && rr < height && cc < width &&
                log_odds[std::size_t(rr) * width + cc] > 0) {
              near[std::size_t(r) * width + c] = 1;
            }
          }
        }
      }
    }
    const std::string where = "trial " + std::to_string(trial);
    for (int r = 0; r < height; ++r) {
      for (int c = 0; c < width; ++c) {
        const std::size_t i = std::size_t(r) * width + c;
        const bool own = r == sr && c == sc;
        ASSERT_EQ(free[i], mask[i] && (!near[i] || own)) << where << " cell " << r << "," << c;
      }
    }
    if (!free[std::size_t(sr) * width + sc]) continue;
    InsidePolygonBuilder builder(width, height, std::vector<int>{8, 32, 4096}[trial % 3], 0.5);
    std::vector<Vec2> polygon;
    builder.Build(free.data(), sensor, &polygon);
    std::vector<std::uint8_t> allowed(mask.size());
    for (std::size_t i = 0; i < mask.size(); ++i) allowed[i] = mask[i] && !near[i];
    allowed[std::size_t(sr) * width + sc] = 1;
    EXPECT_LE(AreaOnNotFree(polygon, allowed, width, height), 1e-6) << where;
    EXPECT_TRUE(PointInPolygon(polygon, sensor)) << where;
    ++checked;
  }
  EXPECT_GT(checked, 60);
}

TEST(PolygonMargin, NothingOccupiedNothingKeptOut) {
  // Not-free cells that the map does not hold occupied (unknown, or free evidence the
  // hysteresis or the opening left out) give no margin.
  std::mt19937 rng(5);
  const int width = 40, height = 30;
  const std::vector<std::uint8_t> mask = RandomMask(width, height, &rng);
  std::vector<LogOdds> log_odds(mask.size());
  for (std::size_t i = 0; i < mask.size(); ++i) log_odds[i] = mask[i] ? -50 : (i % 2 ? 0 : -5);
  std::vector<std::uint8_t> free = mask;
  PolygonMargin(width, height, 3, 180.0).Apply(log_odds.data(), Vec2(20.5, 15.5), free.data());
  EXPECT_EQ(free, mask);
}

}  // namespace
}  // namespace freespace
