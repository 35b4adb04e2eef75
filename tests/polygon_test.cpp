// Capped Douglas-Peucker (paper IV.B, Fig. 7): N and epsilon each bind, the most deviating
// vertices are kept first, the result stays within its reported error, and it keeps the
// vehicle inside. The conservative polygon (polygon.shape inside) from exact rays on random
// masks: it covers mask cells only (and so does the ring it is simplified from), is star-shaped
// around the sensor, has at most N distinct vertices, is empty when nothing around the sensor is
// in the mask, and on an open map is the whole rectangle its border rays reach.
#include <random>

#include "core/inside_polygon.hpp"
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

TEST(Polygon, InwardWeightSplitsAtVerticesAnEdgeWouldCutOff) {
  // A 20 x 20 square around the vehicle with a dent 0.5 in and a bump 0.5 out on its bottom
  // side, epsilon 1: the paper's simplification drops both; with the inward weight the dent
  // counts 50 and is kept, the bump (0.5 out) is still dropped.
  const std::vector<Vec2> ring = {{0, 0},     {5, 0},  {6, 0.5}, {7, 0},   {13, 0},
                                  {14, -0.5}, {15, 0}, {20, 0},  {20, 20}, {0, 20}};
  const int dent = 2, bump = 5;
  const Vec2 vehicle(10, 10);
  for (const double weight : {1.0, 100.0}) {
    PolygonSimplifier s(32, 1.0);
    s.set_inward_weight(weight);
    std::vector<int> kept;
    const double error = s.Simplify(ring, vehicle, &kept);
    const bool has_dent = std::find(kept.begin(), kept.end(), dent) != kept.end();
    EXPECT_EQ(has_dent, weight > 1.0) << "weight " << weight;
    EXPECT_EQ(std::find(kept.begin(), kept.end(), bump), kept.end()) << "weight " << weight;
    EXPECT_NEAR(error, MaxDeviation(ring, kept), 1e-12);  // the true distance, not weighted
    EXPECT_LE(error, 1.0);
  }
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

// A mask (1 = allowed) of random rectangles and single cells that are not, on an open map;
// border cells stay allowed or not at random too.
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

// Area of `polygon` on cells that are not allowed (cells^2).
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

// The conservative polygon on a byte mask: the mask as bitset rows (the sensor's own cell
// allowed, as stage 3b makes it), the exact rays, the builder.
struct Inside {
  int width, height;
  std::vector<std::uint64_t> bits;
  SensorCell sensor;
  std::vector<RayStop> stops;
  InsidePolygonBuilder builder;
  std::vector<Vec2> polygon;
  bool built = false;

  Inside(const std::vector<std::uint8_t>& mask, int w, int h, const Vec2& at, int n, double eps,
         int parts = 1)
      : width(w),
        height(h),
        bits(std::size_t((w + 63) / 64) * h, 0),
        sensor(MakeSensorCell(at, w, h)),
        builder(w, h, n, eps, parts) {
    const int words = (w + 63) / 64;
    for (int r = 0; r < h; ++r) {
      for (int c = 0; c < w; ++c) {
        const bool own = r == sensor.cell.row && c == sensor.cell.col;
        if (mask[std::size_t(r) * w + c] || own) {
          bits[std::size_t(r) * words + c / 64] |= std::uint64_t{1} << (c % 64);
        }
      }
    }
    for (int l = 0; l < BorderLabelCount(h, w); ++l) {
      const CellIndex t = BorderCell(l, h, w);
      stops.push_back(TraceExactRayRows(bits.data(), words, w, sensor, t.col, t.row));
    }
    double error = 0.0;
    built = builder.Build({w, h, words, bits.data()}, sensor, stops, &polygon, &error);
  }
  Vec2 at() const { return Vec2(double(sensor.x) / kFixedOne, double(sensor.y) / kFixedOne); }
};

TEST(InsidePolygon, CoversMaskCellsOnlyOnRandomMasks) {
  std::mt19937 rng(7);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int width = 12 + int(rng() % 40), height = 12 + int(rng() % 40);
    std::vector<std::uint8_t> mask = RandomMask(width, height, &rng);
    // The sensor anywhere in the map; every fourth time on a cell corner or edge exactly.
    std::uniform_real_distribution<double> x(1.0, width - 1.0), y(1.0, height - 1.0);
    Vec2 at(x(rng), y(rng));
    if (trial % 4 == 0) at = Vec2(std::round(at.x()), std::round(at.y()));
    if (trial % 4 == 1) at.x() = std::round(at.x());
    const int n = std::vector<int>{3, 5, 8, 32, 4096}[trial % 5];
    const double epsilon = trial % 3 == 0 ? 0.0 : 1.0;
    const Inside in(mask, width, height, at, n, epsilon);
    mask[std::size_t(in.sensor.cell.row) * width + in.sensor.cell.col] = 1;
    const std::string where = "trial " + std::to_string(trial);
    // The ring, whose fan triangles the simplified polygon keeps inside, covers mask cells only.
    if (in.built) {
      EXPECT_LE(AreaOnNotFree(in.builder.ring(), mask, width, height), 1e-6) << where;
    }
    if (!in.built) {
      EXPECT_TRUE(in.polygon.empty()) << where;
      // Collapsed: the mask held space around the sensor (a ring), but no N-gon in it.
      if (in.builder.collapsed()) {
        EXPECT_GE(in.builder.ring().size(), 3u) << where;
      }
      continue;
    }
    ASSERT_GE(in.polygon.size(), 3u) << where;
    ASSERT_LE(int(in.polygon.size()), n) << where;
    for (std::size_t k = 0; k < in.polygon.size(); ++k) {
      EXPECT_GT((in.polygon[k] - in.polygon[(k + 1) % in.polygon.size()]).norm(), 0.0) << where;
    }
    EXPECT_LE(AreaOnNotFree(in.polygon, mask, width, height), 1e-6) << where;
    ExpectStarShaped(in.polygon, in.at());
    ++checked;
  }
  EXPECT_GT(checked, 200);
}

// The one cell the mask keeps whatever it holds is the cell the sensor is in: a sensor a hair
// below a cell edge (closer to the next cell than 1/512 of a cell) does not lend its place to
// that next cell, which here holds an obstacle.
TEST(InsidePolygon, TheSensorsOwnCellIsTheOneItIsIn) {
  const int width = 20, height = 20;
  for (const double below : {1e-3, 1e-4, 1e-9}) {
    const Vec2 at(10.0 - below, 7.5);
    std::vector<std::uint8_t> mask(std::size_t(width) * height, 1);
    mask[std::size_t(7) * width + 10] = 0;  // the cell right of the sensor's
    const Inside in(mask, width, height, at, 32, 0.0);
    EXPECT_EQ(in.sensor.cell.col, 9) << below;
    EXPECT_EQ(in.sensor.cell.row, 7) << below;
    EXPECT_LE(in.at().x(), at.x()) << below;
    ASSERT_TRUE(in.built) << below;
    EXPECT_LE(AreaOnNotFree(in.polygon, mask, width, height), 1e-6) << below;
  }
}

TEST(InsidePolygon, PartsInParallelGiveTheSamePolygon) {
  // The rays worked in several parts (some empty: more parts than rays) build the ring and the
  // polygon of one part, to the bit.
  std::mt19937 rng(11);
  int built = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const int width = 12 + int(rng() % 40), height = 12 + int(rng() % 40);
    const std::vector<std::uint8_t> mask = RandomMask(width, height, &rng);
    std::uniform_real_distribution<double> x(1.0, width - 1.0), y(1.0, height - 1.0);
    const Vec2 at(x(rng), y(rng));
    const Inside one(mask, width, height, at, 32, 0.5, 1);
    for (const int parts : {2, 3, 8, 400}) {
      const Inside many(mask, width, height, at, 32, 0.5, parts);
      const std::string where =
          "trial " + std::to_string(trial) + ", " + std::to_string(parts) + " parts";
      ASSERT_EQ(many.built, one.built) << where;
      EXPECT_EQ(many.builder.ring(), one.builder.ring()) << where;
      EXPECT_EQ(many.polygon, one.polygon) << where;
    }
    built += one.built;
  }
  EXPECT_GT(built, 60);
}

TEST(InsidePolygon, OpenMapGivesTheBorderCentresRectangle) {
  // Everything allowed: each border ray reaches its cell's centre, Douglas-Peucker keeps the
  // four corners, nothing is pulled in: the rectangle of the border cells' centres.
  const int width = 30, height = 20;
  const std::vector<std::uint8_t> free(std::size_t(width) * height, 1);
  for (const Vec2& sensor : {Vec2(7.3, 11.9), Vec2(15, 10), Vec2(1.2, 18.7)}) {
    const Inside in(free, width, height, sensor, 32, 0.0);
    ASSERT_TRUE(in.built);
    EXPECT_NEAR(std::abs(geometry::SignedArea(in.polygon)), (width - 1.0) * (height - 1.0), 1e-9);
    EXPECT_TRUE(PointInPolygon(in.polygon, in.at()));
  }
}

TEST(InsidePolygon, PullsACappedEdgeInFrontOfTheObstacleItCuts) {
  // One blocked cell (10, 10) in an open 21 x 21 map, the sensor at (10.5, 5.5) south of it.
  // The rays north stop at the cell's south face y = 10; with N = 4 the simplified polygon
  // cannot follow the notch, and the edge across it is pulled in to y <= 10 there.
  const int size = 21;
  std::vector<std::uint8_t> free(std::size_t(size) * size, 1);
  free[10 * size + 10] = 0;
  const Vec2 sensor(10.5, 5.5);
  for (const int n : {4, 8, 4096}) {
    const Inside in(free, size, size, sensor, n, 0.0);
    ASSERT_TRUE(in.built);
    const std::vector<Vec2>& polygon = in.polygon;
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

// Whether the segment from p to q meets the open square of cell (col, row) (Liang-Barsky).
bool SegmentMeetsCell(const Vec2& p, const Vec2& q, int col, int row) {
  double t0 = 0.0, t1 = 1.0;
  const Vec2 d = q - p;
  const double lo[2] = {double(col), double(row)}, hi[2] = {col + 1.0, row + 1.0};
  for (int axis = 0; axis < 2; ++axis) {
    if (d[axis] == 0.0) {
      if (p[axis] <= lo[axis] || p[axis] >= hi[axis]) return false;
      continue;
    }
    double a = (lo[axis] - p[axis]) / d[axis], b = (hi[axis] - p[axis]) / d[axis];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  return t0 < t1;
}

// Area of the border centres' square that the sensor sees past every blocked cell but
// `polygon` leaves out (cells^2, points every 0.1 cell off any line through a cell corner).
double SeenButLeftOut(const std::vector<Vec2>& polygon, const std::vector<std::uint8_t>& free,
                      int size, const Vec2& sensor) {
  std::vector<CellIndex> blocked;
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      if (!free[std::size_t(r) * size + c]) blocked.push_back(CellIndex{r, c});
    }
  }
  double lost = 0.0;
  for (double y = 0.5537; y < size - 0.5; y += 0.1) {
    for (double x = 0.5519; x < size - 0.5; x += 0.1) {
      const Vec2 p(x, y);
      if (PointInPolygon(polygon, p)) continue;
      bool seen = true;
      for (const CellIndex& b : blocked) seen = seen && !SegmentMeetsCell(sensor, p, b.col, b.row);
      if (seen) lost += 0.01;
    }
  }
  return lost;
}

TEST(InsidePolygon, KeepsWhatTheSensorSeesPastObstacles) {
  // Blocked cells near the sensor in an open map: a pole, and a wall of cells running at 45
  // deg. The polygon keeps what the sensor sees but for slivers along the shadows' sides (the
  // rays are a border cell apart): the ring goes round the corners that poke between two rays
  // instead of pulling their ends in.
  const int size = 41;
  std::vector<std::uint8_t> free(std::size_t(size) * size, 1);
  free[std::size_t(22) * size + 23] = 0;
  for (int i = 0; i < 6; ++i) free[std::size_t(12 + i) * size + 14 + i] = 0;
  for (const Vec2& sensor : {Vec2(20.3, 19.6), Vec2(20.5, 20.5), Vec2(18.2, 21.7)}) {
    const Inside in(free, size, size, sensor, 4096, 0.0);
    ASSERT_TRUE(in.built);
    EXPECT_LE(AreaOnNotFree(in.polygon, free, size, size), 1e-9);
    ExpectStarShaped(in.polygon, in.at());
    // The ring passes through the pole's two silhouette corners.
    const std::vector<Vec2> corners = {Vec2(23, 22), Vec2(24, 22), Vec2(24, 23), Vec2(23, 23)};
    const auto angle = [&](const Vec2& c) {
      return std::atan2(c.y() - sensor.y(), c.x() - sensor.x());
    };
    const auto by_angle = [&](const Vec2& p, const Vec2& q) { return angle(p) < angle(q); };
    for (const Vec2& silhouette : {*std::min_element(corners.begin(), corners.end(), by_angle),
                                   *std::max_element(corners.begin(), corners.end(), by_angle)}) {
      const std::vector<Vec2>& ring = in.builder.ring();
      EXPECT_TRUE(std::any_of(ring.begin(), ring.end(),
                              [&](const Vec2& v) { return (v - silhouette).norm() < 1e-9; }))
          << "sensor " << sensor.transpose() << " corner " << silhouette.transpose();
    }
    // Slivers only: at most a cell wide at the border along each of the four shadow sides.
    EXPECT_LT(SeenButLeftOut(in.polygon, free, size, sensor), 30.0)
        << "sensor " << sensor.transpose();
  }
}

TEST(InsidePolygon, NothingAroundTheSensorGivesNoPolygon) {
  // The sensor's cell boxed in by blocked cells: every ray ends on its own cell's edge, and
  // the polygon is empty, not a ring of repeated points. One free neighbour is enough.
  const int size = 9;
  std::vector<std::uint8_t> mask(std::size_t(size) * size, 1);
  for (int r = 3; r <= 5; ++r) {
    for (int c = 3; c <= 5; ++c) mask[std::size_t(r) * size + c] = 0;
  }
  for (const Vec2& at : {Vec2(4.5, 4.5), Vec2(4.0, 4.0), Vec2(4.9, 4.1)}) {
    const Inside boxed(mask, size, size, at, 32, 0.0);
    EXPECT_FALSE(boxed.built);
    EXPECT_TRUE(boxed.polygon.empty());
  }
  std::vector<std::uint8_t> open = mask;
  open[4 * size + 5] = 1;
  open[4 * size + 4] = 1;  // the sensor's own cell is in the mask
  const Inside one(open, size, size, Vec2(4.5, 4.5), 32, 0.0);
  EXPECT_TRUE(one.built);
  EXPECT_GT(std::abs(geometry::SignedArea(one.polygon)), 1.0);
  EXPECT_LE(AreaOnNotFree(one.polygon, open, size, size), 1e-9);
}

TEST(InsidePolygon, NoRayThroughCellsThatMeetAtACorner) {
  // Two blocked cells meeting at a corner, the sensor on their diagonal: the rays through the
  // corner stop there, and no part of the polygon lies beyond the pair.
  const int size = 15;
  std::vector<std::uint8_t> mask(std::size_t(size) * size, 1);
  mask[std::size_t(8) * size + 7] = 0;
  mask[std::size_t(7) * size + 8] = 0;
  const Inside in(mask, size, size, Vec2(4.5, 4.5), 4096, 0.0);
  ASSERT_TRUE(in.built);
  EXPECT_LE(AreaOnNotFree(in.polygon, mask, size, size), 1e-9);
  EXPECT_FALSE(PointInPolygon(in.polygon, Vec2(8.5, 8.5)));
  EXPECT_FALSE(PointInPolygon(in.polygon, Vec2(10.2, 10.4)));
}

}  // namespace
}  // namespace freespace
