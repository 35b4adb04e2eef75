// The capped Douglas-Peucker's order of splits: the simplifier keeps its segments on a heap;
// here a plain greedy recomputes every edge's deviating vertex at each step and splits the
// edge whose priority is highest (of equal ones the first in ring order). On random rings,
// with and without the inward weight, capped and uncapped, both must keep the same vertices.
#include "core/simplifier.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace freespace {
namespace {

struct Edge {
  int from, to;  // ring indices; `to` may equal `from` + the ring's size (the wrapping edge)
};

// The interior vertex of the edge with the highest priority (weighted squared distance), and
// that priority; -1 without interior vertices.
int WorstOf(const std::vector<Vec2>& ring, const Edge& e, double weight, double* priority) {
  const int n = int(ring.size());
  const Vec2 a = ring[std::size_t(e.from)];
  const Vec2 ab = ring[std::size_t(e.to % n)] - a;
  const double len2 = ab.squaredNorm(), inverse = len2 > 0.0 ? 1.0 / len2 : 0.0;
  int worst = -1;
  double best = -1.0;
  for (int k = e.from + 1; k < e.to; ++k) {
    const Vec2 ap = ring[std::size_t(k % n)] - a;
    const double t = std::clamp(ap.dot(ab) * inverse, 0.0, 1.0);
    const double d2 = (ap - t * ab).squaredNorm();
    const double key = ab.x() * ap.y() - ab.y() * ap.x() > 0.0 ? d2 * weight * weight : d2;
    if (key > best) {
      best = key;
      worst = k % n;
    }
  }
  *priority = std::sqrt(best);
  return worst;
}

// Greedy splits by priority alone, for rings whose simplification never needs a split to
// keep `inside` (a point left of every edge from the first two on: see Reference's caller).
std::vector<int> Reference(const std::vector<Vec2>& ring, int max_vertices, double epsilon,
                           double weight, const std::vector<int>& start) {
  const int n = int(ring.size());
  std::vector<int> kept = start;
  while (int(kept.size()) < max_vertices) {
    int best_edge = -1, best_vertex = -1;
    double best = 0.0;
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const int to = k + 1 < kept.size() ? kept[k + 1] : kept[0] + n;
      double priority = 0.0;
      const int v = WorstOf(ring, {kept[k], to}, weight, &priority);
      if (v >= 0 && (best_edge < 0 || priority > best)) {
        best_edge = int(k);
        best_vertex = v;
        best = priority;
      }
    }
    if (best_edge < 0 || (best <= epsilon && kept.size() >= 3)) break;
    kept.push_back(best_vertex);
    std::sort(kept.begin(), kept.end());
  }
  return kept;
}

TEST(Simplifier, SplitsInTheOrderOfAPlainGreedy) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    // A ring around the origin with integer vertices, far enough apart that their angles
    // around it keep increasing; every other one the same side four times, turned by quarter
    // turns, so that priorities tie and the tie-break decides.
    std::vector<Vec2> ring;
    int n = 0;
    if (trial % 2 == 0) {
      n = 20 + int(unit(rng) * 300);
      for (int i = 0; i < n; ++i) {
        const double a = 2 * M_PI * i / n;
        const double r = std::round(300 + 100 * unit(rng) * std::sin(3 * a) + 60 * unit(rng));
        ring.emplace_back(std::round(r * std::cos(a)), std::round(r * std::sin(a)));
      }
    } else {
      const int side = 5 + int(unit(rng) * 60), step = 400 / side;
      std::vector<Vec2> first;
      for (int i = 0; i < side; ++i) {
        first.emplace_back(-200 + i * step, -200 - std::round(20 * unit(rng)));
      }
      for (int turn = 0; turn < 4; ++turn) {
        for (Vec2 p : first) {
          for (int k = 0; k < turn; ++k) p = Vec2(-p.y(), p.x());
          ring.push_back(p);
        }
      }
      n = int(ring.size());
    }
    const int max_vertices = 3 + int(unit(rng) * 120);
    const double epsilon = trial % 3 == 0 ? 0.0 : unit(rng) * 20.0;
    const double weight = trial % 4 < 2 ? 1.0 : 4.0;
    // `inside` far to the left of every edge is impossible for a closed ring; the origin is
    // left of every edge once no edge spans half a turn. Start the reference where the
    // simplifier's containment splits end, and compare only when they did nothing after.
    PolygonSimplifier simplifier(max_vertices, epsilon);
    simplifier.set_inward_weight(weight);
    std::vector<int> kept;
    simplifier.Simplify(ring, Vec2(0, 0), &kept);
    PolygonSimplifier contain_only(max_vertices, 1e9);
    contain_only.set_inward_weight(weight);
    std::vector<int> start;
    contain_only.Simplify(ring, Vec2(0, 0), &start);
    if (int(start.size()) >= max_vertices || start.size() < 3) continue;
    EXPECT_EQ(kept, Reference(ring, max_vertices, epsilon, weight, start))
        << "trial " << trial << ", n " << n << ", N " << max_vertices;
    ++compared;
  }
  EXPECT_GT(compared, 100);
}

}  // namespace
}  // namespace freespace
