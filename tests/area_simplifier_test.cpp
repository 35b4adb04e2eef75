// The conservative polygon's simplification by least area given up (core/area_simplifier.hpp):
// against a plain greedy that recomputes every vertex's drop at each step, on random rings
// around a centre; and the rules a planner relies on: at most N vertices, the centre left of
// every kept edge, a convex bump dropped before a notch, and -1 where no N vertices can keep
// the centre inside.
#include "core/area_simplifier.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/simplifier.hpp"

namespace freespace {
namespace {

constexpr double kWeight = 100.0;

double Cross(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

// The drop of kept[i]: its weighted area and weighted distance, infinite when not allowed.
void DropOf(const std::vector<Vec2>& ring, const std::vector<int>& kept, std::size_t i,
            const Vec2& centre, double* cost, double* distance) {
  const std::size_t m = kept.size();
  const Vec2& u = ring[std::size_t(kept[(i + m - 1) % m])];
  const Vec2& p = ring[std::size_t(kept[i])];
  const Vec2& w = ring[std::size_t(kept[(i + 1) % m])];
  *cost = *distance = std::numeric_limits<double>::infinity();
  const bool at_centre = (u - centre).squaredNorm() <= 1e-18 || (w - centre).squaredNorm() <= 1e-18;
  if (!at_centre && Cross(w - u, centre - u) <= 0.0) return;
  const double twice = Cross(w - u, p - u);
  const double weight = twice > 0.0 ? kWeight : 1.0;
  *cost = weight * 0.5 * std::abs(twice);
  *distance = weight * std::abs(twice) / (w - u).norm();
}

// The greedy the heap must reproduce: the cheapest drop (the lowest ring index of equal ones)
// while more than N are kept, then while it stays within epsilon.
std::vector<int> Greedy(const std::vector<Vec2>& ring, const Vec2& centre, int n_max, double eps) {
  std::vector<int> kept;
  for (int i = 0; i < int(ring.size()); ++i) kept.push_back(i);
  while (kept.size() > 3) {
    std::size_t best = kept.size();
    double best_cost = std::numeric_limits<double>::infinity(), best_distance = 0.0;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      double cost, distance;
      DropOf(ring, kept, i, centre, &cost, &distance);
      if (cost < best_cost) {
        best = i;
        best_cost = cost;
        best_distance = distance;
      }
    }
    if (best == kept.size()) break;
    if (int(kept.size()) <= n_max && best_distance > eps) break;
    kept.erase(kept.begin() + std::ptrdiff_t(best));
  }
  if (int(kept.size()) > n_max) kept.clear();
  return kept;
}

// A ring around `centre` with a radius that jumps about (bumps and notches).
std::vector<Vec2> RandomRing(std::mt19937* rng, int n, const Vec2& centre) {
  std::uniform_real_distribution<double> radius(5.0, 40.0), jitter(-0.3, 0.3);
  std::vector<Vec2> ring;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * (i + 0.5 + jitter(*rng)) / n;
    const double r = radius(*rng);
    ring.emplace_back(centre.x() + r * std::cos(a), centre.y() + r * std::sin(a));
  }
  return ring;
}

TEST(AreaSimplifier, KeepsWhatTheGreedyKeeps) {
  std::mt19937 rng(7);
  const Vec2 centre(50.0, 50.0);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 8 + trial * 5, n_max = 3 + trial % 40;
    const double eps = trial % 3 == 0 ? 0.0 : 0.6;
    const std::vector<Vec2> ring = RandomRing(&rng, n, centre);
    AreaSimplifier simplifier(n_max, eps, kWeight, n);
    std::vector<int> kept;
    const double error = simplifier.Simplify(ring, centre, &kept);
    const std::vector<int> expected = Greedy(ring, centre, n_max, eps);
    ASSERT_EQ(kept, expected) << "trial " << trial;
    if (kept.empty()) {
      EXPECT_EQ(error, -1.0);
      continue;
    }
    // At most N, the centre left of every kept edge, the error the farthest dropped vertex.
    ASSERT_LE(int(kept.size()), n_max);
    double farthest = 0.0;
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const int a = kept[k], b = kept[(k + 1) % kept.size()];
      EXPECT_GT(Cross(ring[std::size_t(b)] - ring[std::size_t(a)], centre - ring[std::size_t(a)]),
                0.0);
      for (int i = (a + 1) % n; i != b; i = (i + 1) % n) {
        farthest = std::max(farthest, DistanceToSegment(ring[std::size_t(i)],
                                                        ring[std::size_t(a)],
                                                        ring[std::size_t(b)]));
      }
    }
    EXPECT_DOUBLE_EQ(error, farthest);
  }
}

// A square with a small bump out of its bottom edge and a notch of the same size into its top
// edge: with one vertex to give up, the bump's tip goes (its edge cuts inside the ring), then
// its base, now on a straight line (nothing given up); the notch, which an edge across it would
// pass outside, stays.
TEST(AreaSimplifier, GivesUpABumpBeforeANotch) {
  const std::vector<Vec2> ring = {{0, 0},  {5, 0},  {6, -1}, {7, 0},  {12, 0},
                                  {12, 12}, {7, 12}, {6, 11}, {5, 12}, {0, 12}};
  const Vec2 centre(6, 6);
  AreaSimplifier simplifier(9, 0.0, kWeight, 16);
  std::vector<int> kept;
  EXPECT_GE(simplifier.Simplify(ring, centre, &kept), 0.0);
  EXPECT_EQ(kept, (std::vector<int>{0, 4, 5, 6, 7, 8, 9}));
}

// Four vertices around the centre at right angles: any three leave it on an edge, so no
// polygon of three keeps it inside.
TEST(AreaSimplifier, SaysSoWhenNoNVerticesKeepTheCentreInside) {
  const std::vector<Vec2> ring = {{10, 0}, {0, 10}, {-10, 0}, {0, -10}};
  AreaSimplifier simplifier(3, 0.0, kWeight, 8);
  std::vector<int> kept;
  EXPECT_EQ(simplifier.Simplify(ring, Vec2(0, 0), &kept), -1.0);
  EXPECT_TRUE(kept.empty());
  AreaSimplifier four(4, 0.0, kWeight, 8);
  EXPECT_EQ(four.Simplify(ring, Vec2(0, 0), &kept), 0.0);
  EXPECT_EQ(kept.size(), 4u);
}

// Vertices on a straight run within epsilon go even below N.
TEST(AreaSimplifier, DropsWhatLiesWithinEpsilon) {
  std::vector<Vec2> ring;
  for (int i = 0; i <= 10; ++i) ring.emplace_back(i, -0.01 * (i % 2));  // small bumps out
  ring.emplace_back(10, 10);
  ring.emplace_back(0, 10);
  AreaSimplifier simplifier(100, 0.1, kWeight, 16);
  std::vector<int> kept;
  const double error = simplifier.Simplify(ring, Vec2(5, 5), &kept);
  EXPECT_EQ(kept, (std::vector<int>{0, 10, 11, 12}));
  EXPECT_LE(error, 0.01 + 1e-12);
}

}  // namespace
}  // namespace freespace
