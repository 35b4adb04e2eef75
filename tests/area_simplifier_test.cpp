// The conservative polygon's simplification by least area given up (core/area_simplifier.hpp):
// against a plain greedy that recomputes every vertex's drop at each step, on random rings
// around a centre; and the rules a planner relies on: at most N vertices, the centre left of
// every kept edge, a convex bump dropped before a notch, and -1 where no N vertices can keep
// the centre inside.
#include "core/area_simplifier.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "core/fan_pull.hpp"
#include "core/simplifier.hpp"

namespace freespace {
namespace {

constexpr double kWeight = 100.0;

using fan::Cross;

// The drop of kept[i] (dev[j]: the bound for the kept edge from kept[j]): its weighted area,
// its deviation bound and that bound weighted; infinite when not allowed.
void DropOf(const std::vector<Vec2>& ring, const std::vector<int>& kept,
            const std::vector<double>& dev, std::size_t i, const Vec2& centre, double* cost,
            double* deviation, double* distance) {
  const std::size_t m = kept.size(), before = (i + m - 1) % m;
  const Vec2& u = ring[std::size_t(kept[before])];
  const Vec2& p = ring[std::size_t(kept[i])];
  const Vec2& w = ring[std::size_t(kept[(i + 1) % m])];
  *cost = *deviation = *distance = std::numeric_limits<double>::infinity();
  const auto at_centre = [&](const Vec2& q) { return (q - centre).squaredNorm() <= 1e-18; };
  if (at_centre(p)) return;
  if (!at_centre(u) && !at_centre(w) && Cross(w - u, centre - u) <= fan::kAreaTolerance) return;
  const double twice = Cross(w - u, p - u);
  const double weight = twice > 0.0 ? kWeight : 1.0;
  *cost = weight * 0.5 * std::abs(twice);
  *deviation = std::max(dev[before], dev[i]) + DistanceToSegment(p, u, w);
  *distance = weight * *deviation;
}

// The greedy the heap must reproduce: the cheapest drop (the lowest ring index of equal ones)
// while more than N are kept, then while its weighted bound stays within epsilon.
std::vector<int> Greedy(const std::vector<Vec2>& ring, const Vec2& centre, int n_max, double eps) {
  std::vector<int> kept;
  for (int i = 0; i < int(ring.size()); ++i) kept.push_back(i);
  std::vector<double> dev(kept.size(), 0.0);
  while (kept.size() > 3) {
    std::size_t best = kept.size();
    double best_cost = std::numeric_limits<double>::infinity(), best_dev = 0.0, best_distance = 0.0;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      double cost, deviation, distance;
      DropOf(ring, kept, dev, i, centre, &cost, &deviation, &distance);
      if (cost < best_cost) {
        best = i;
        best_cost = cost;
        best_dev = deviation;
        best_distance = distance;
      }
    }
    if (best == kept.size()) break;
    if (int(kept.size()) <= n_max && best_distance > eps) break;
    dev[(best + kept.size() - 1) % kept.size()] = best_dev;
    kept.erase(kept.begin() + std::ptrdiff_t(best));
    dev.erase(dev.begin() + std::ptrdiff_t(best));
  }
  if (int(kept.size()) > n_max) kept.clear();
  return kept;
}

// A ring around `centre` with a radius that jumps about (bumps and notches). `grid`: vertices
// on whole numbers, so that drops tie; `blocked`: a run of rays blocked at once, ending at the
// centre.
std::vector<Vec2> RandomRing(std::mt19937* rng, int n, const Vec2& centre, bool grid,
                             bool blocked) {
  std::uniform_real_distribution<double> radius(5.0, 40.0), jitter(-0.3, 0.3);
  std::vector<Vec2> ring;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * (i + 0.5 + jitter(*rng)) / n;
    const double r = blocked && i < n / 6 ? 0.0 : radius(*rng);
    Vec2 p(centre.x() + r * std::cos(a), centre.y() + r * std::sin(a));
    if (grid && r > 0.0) p = Vec2(std::round(p.x()), std::round(p.y()));
    if (ring.empty() || (ring.back() - p).squaredNorm() > 0.0) ring.push_back(p);
  }
  return ring;
}

TEST(AreaSimplifier, KeepsWhatTheGreedyKeeps) {
  std::mt19937 rng(7);
  const Vec2 centre(50.0, 50.0);
  int simplified = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n_max = 3 + trial % 40;
    const double eps = trial % 3 == 0 ? 0.0 : 0.6;
    const std::vector<Vec2> ring =
        RandomRing(&rng, 8 + trial * 5, centre, trial % 2 == 1, trial % 4 == 3);
    const int n = int(ring.size());
    AreaSimplifier simplifier(n_max, eps, kWeight, n);
    std::vector<int> kept;
    const double error = simplifier.Simplify(ring, centre, &kept);
    const std::vector<int> expected = Greedy(ring, centre, n_max, eps);
    ASSERT_EQ(kept, expected) << "trial " << trial;
    if (kept.empty()) {
      EXPECT_EQ(error, -1.0);
      continue;
    }
    // At most N, the centre left of every kept edge or on its end, a vertex at the centre kept,
    // the error the farthest dropped vertex, within epsilon where N did not stop the drops.
    ASSERT_LE(int(kept.size()), n_max);
    ++simplified;
    double farthest = 0.0;
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const int a = kept[k], b = kept[(k + 1) % kept.size()];
      const Vec2 &pa = ring[std::size_t(a)], &pb = ring[std::size_t(b)];
      if (b != (a + 1) % n && pa != centre && pb != centre) {  // an edge of the simplifier's
        EXPECT_GT(Cross(pb - pa, centre - pa), 0.0);
      }
      for (int i = (a + 1) % n; i != b; i = (i + 1) % n) {
        EXPECT_NE(ring[std::size_t(i)], centre);
        farthest = std::max(farthest, DistanceToSegment(ring[std::size_t(i)], ring[std::size_t(a)],
                                                        ring[std::size_t(b)]));
      }
    }
    EXPECT_DOUBLE_EQ(error, farthest);
    if (int(kept.size()) < n_max) {
      EXPECT_LE(error, eps + 1e-12);
    }
  }
  EXPECT_GT(simplified, 40);
}

// A square with a small bump out of its bottom edge and a notch of the same size into its top
// edge: with one vertex to give up, the bump's tip goes (its edge cuts inside the ring); the
// notch, which an edge across it would pass outside, stays. The bump's base then lies on a
// straight line, but dropping it would leave the tip 1 cell off the new edge: beyond epsilon.
TEST(AreaSimplifier, GivesUpABumpBeforeANotch) {
  const std::vector<Vec2> ring = {{0, 0},   {5, 0},  {6, -1}, {7, 0},  {12, 0},
                                  {12, 12}, {7, 12}, {6, 11}, {5, 12}, {0, 12}};
  const Vec2 centre(6, 6);
  AreaSimplifier simplifier(9, 0.0, kWeight, 16);
  std::vector<int> kept;
  EXPECT_GE(simplifier.Simplify(ring, centre, &kept), 0.0);
  EXPECT_EQ(kept, (std::vector<int>{0, 1, 3, 4, 5, 6, 7, 8, 9}));
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

// Below N the drops stop before the vertices a new edge replaces could lie beyond epsilon of
// it: here dropping (2, -0.11), then (1, -0.02) would leave 0.11 under one edge.
TEST(AreaSimplifier, TheErrorStaysWithinEpsilonBelowN) {
  const std::vector<Vec2> ring = {{0, 0}, {1, -0.02}, {2, -0.11}, {4, 0}, {4, 10}, {0, 10}};
  AreaSimplifier simplifier(100, 0.1, kWeight, 8);
  std::vector<int> kept;
  EXPECT_LE(simplifier.Simplify(ring, Vec2(2, 5), &kept), 0.1);
}

// A ray blocked at once ends at the centre: that vertex is never dropped (an edge past it would
// be pulled in to nothing), so its neighbours stay too.
TEST(AreaSimplifier, KeepsAVertexAtTheCentre) {
  const std::vector<Vec2> ring = {{100, 0},    {0, 0},       {100, 0.5}, {100, 100},
                                  {-100, 100}, {-100, -100}, {100, -100}};
  AreaSimplifier simplifier(6, 0.0, kWeight, 8);
  std::vector<int> kept;
  EXPECT_GE(simplifier.Simplify(ring, Vec2(0, 0), &kept), 0.0);
  EXPECT_NE(std::find(kept.begin(), kept.end(), 1), kept.end());
  EXPECT_LE(kept.size(), 6u);
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
