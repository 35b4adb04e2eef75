// Capped Douglas-Peucker (paper IV.B, Fig. 7): N and epsilon each bind, the most deviating
// vertices are kept first, the result stays within its reported error, and it keeps the
// vehicle inside.
#include "polygon.hpp"

#include <random>

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

}  // namespace
}  // namespace freespace
