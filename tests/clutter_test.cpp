// The DBSCAN clutter filter: hand-made clusters, range-growing eps, and random well-separated
// blobs against a brute-force all-pairs DBSCAN.
#include <random>

#include "core/crew.hpp"
#include "core/dbscan.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

constexpr double kBin = 0.25 * M_PI / 180.0;
constexpr int kBins = 581;  // -72.5 .. 72.5 deg

EchoPoint At(double x, double y) {
  EchoPoint p;
  p.x = float(x);
  p.y = float(y);
  p.range = float(std::hypot(x, y));
  p.angle = float(std::atan2(y, x));
  p.bin = std::clamp(int(std::lround((p.angle + 72.5 * M_PI / 180.0) / kBin)), 0, kBins - 1);
  return p;
}

ClutterConfig Params(double eps, double eps_per_m) {
  ClutterConfig c;
  c.eps_m = eps;
  c.eps_per_m = eps_per_m;
  c.min_points = 3;
  c.min_cluster_size = 5;
  return c;
}

TEST(Clutter, KeepsWallsAndDropsSmallClustersAndNoise) {
  std::vector<EchoPoint> points;
  for (int i = 0; i < 20; ++i) points.push_back(At(10.0, -2.0 + 0.2 * i));  // a wall: kept
  for (int i = 0; i < 4; ++i) points.push_back(At(20.0, 5.0 + 0.2 * i));    // 4 points: clutter
  for (int i = 0; i < 5; ++i) points.push_back(At(20.0, -5.0 - 0.2 * i));   // 5 points: kept
  points.push_back(At(5.0, 3.0));                                           // rain drops
  points.push_back(At(7.0, -1.0));
  ClutterFilter filter(Params(0.5, 0.0), kBins, kBin);
  std::vector<std::uint8_t> keep;
  EXPECT_EQ(filter.Run(points, &keep), 6);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(keep[i], 1) << i;
  for (int i = 20; i < 24; ++i) EXPECT_EQ(keep[i], 0) << i;
  for (int i = 24; i < 29; ++i) EXPECT_EQ(keep[i], 1) << i;
  EXPECT_EQ(keep[29], 0);
  EXPECT_EQ(keep[30], 0);
}

TEST(Clutter, EpsGrowsWithRangeForFarWalls) {
  // A wall at 100 m sampled every 0.25 deg: neighbours 0.44 m apart.
  std::vector<EchoPoint> points;
  for (int i = -20; i <= 20; ++i) {
    const double a = i * kBin;
    points.push_back(At(100.0 * std::cos(a), 100.0 * std::sin(a)));
  }
  std::vector<std::uint8_t> keep;
  ClutterFilter fixed(Params(0.3, 0.0), kBins, kBin);
  EXPECT_EQ(fixed.Run(points, &keep), int(points.size()));  // all noise with a fixed eps
  ClutterFilter growing(Params(0.3, 0.005), kBins, kBin);
  EXPECT_EQ(growing.Run(points, &keep), 0);
}

TEST(Clutter, DisabledKeepsEverything) {
  ClutterConfig c = Params(0.5, 0.0);
  c.enabled = false;
  ClutterFilter filter(c, kBins, kBin);
  std::vector<std::uint8_t> keep;
  EXPECT_EQ(filter.Run({At(5, 0), At(30, 10)}, &keep), 0);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{1, 1}));
}

// All-pairs DBSCAN; on well separated blobs no border point is shared, so cluster sizes and
// the keep decision do not depend on visiting order.
std::vector<std::uint8_t> BruteForce(const std::vector<EchoPoint>& p, const ClutterConfig& c) {
  const int n = int(p.size());
  auto near = [&](int i, int j) {
    const double eps = c.eps_m + c.eps_per_m * std::max(p[i].range, p[j].range);
    return std::hypot(double(p[i].x) - p[j].x, double(p[i].y) - p[j].y) <= eps;
  };
  std::vector<int> degree(n, 0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) degree[i] += near(i, j) ? 1 : 0;
  }
  std::vector<int> label(n, -1);
  int clusters = 0;
  for (int i = 0; i < n; ++i) {
    if (label[i] >= 0 || degree[i] < c.min_points) continue;
    std::vector<int> stack{i};
    label[i] = clusters;
    while (!stack.empty()) {
      const int k = stack.back();
      stack.pop_back();
      if (degree[k] < c.min_points) continue;
      for (int j = 0; j < n; ++j) {
        if (label[j] < 0 && near(k, j)) {
          label[j] = clusters;
          stack.push_back(j);
        }
      }
    }
    ++clusters;
  }
  std::vector<int> size(clusters, 0);
  for (const int l : label) {
    if (l >= 0) ++size[l];
  }
  std::vector<std::uint8_t> keep(n);
  for (int i = 0; i < n; ++i) keep[i] = label[i] >= 0 && size[label[i]] >= c.min_cluster_size;
  return keep;
}

// 25 blobs of up to max_size echoes each (Gaussian, `sigma` m), their centres on a coarse polar
// grid (shifted by 3 m on odd trials), so blobs stay far apart; shuffled.
std::vector<EchoPoint> Blobs(std::mt19937* rng, int trial, int max_size, double sigma) {
  std::vector<EchoPoint> points;
  for (int blob = 0; blob < 25; ++blob) {
    const double r = 4.0 + 6.0 * (blob % 5) + 3.0 * (trial % 2);
    const double a = (-60.0 + 25.0 * (blob / 5)) * M_PI / 180.0;
    const int size = int((*rng)() % unsigned(max_size + 1));
    for (int k = 0; k < size; ++k) {
      std::normal_distribution<double> jitter(0.0, sigma);
      points.push_back(At(r * std::cos(a) + jitter(*rng), r * std::sin(a) + jitter(*rng)));
    }
  }
  std::shuffle(points.begin(), points.end(), *rng);
  return points;
}

std::vector<std::uint8_t> Kept(const std::vector<EchoPoint>& points, const ClutterConfig& c) {
  ClutterFilter filter(c, kBins, kBin);
  std::vector<std::uint8_t> keep;
  filter.Run(points, &keep);
  return keep;
}

TEST(Clutter, MatchesAllPairsDbscanOnRandomBlobs) {
  std::mt19937 rng(29);
  const ClutterConfig c = Params(0.4, 0.01);
  for (int trial = 0; trial < 30; ++trial) {
    const std::vector<EchoPoint> points = Blobs(&rng, trial, 8, 0.15);
    EXPECT_EQ(Kept(points, c), BruteForce(points, c)) << "trial " << trial;
  }
}

// The same for neighbourhoods beyond the few neighbours each echo remembers: min_points and
// min_cluster_size up to 30, on blobs of up to 60 echoes (min_points of 10 and more once wrote
// past each echo's record).
TEST(Clutter, MatchesAllPairsDbscanWithLargeMinimums) {
  std::mt19937 rng(37);
  for (const auto& [min_points, min_size] : {std::pair{9, 9}, std::pair{10, 12}, std::pair{16, 5},
                                             std::pair{30, 30}, std::pair{3, 30}}) {
    ClutterConfig c = Params(0.4, 0.01);
    c.min_points = min_points;
    c.min_cluster_size = min_size;
    for (int trial = 0; trial < 8; ++trial) {
      const std::vector<EchoPoint> points = Blobs(&rng, trial, 60, 0.12);
      const std::vector<std::uint8_t> keep = Kept(points, c);
      const std::vector<std::uint8_t> expected = BruteForce(points, c);
      EXPECT_EQ(keep, expected) << "min_points " << min_points << ", trial " << trial;
      EXPECT_GT(std::count(expected.begin(), expected.end(), 1), 0);
      EXPECT_GT(std::count(expected.begin(), expected.end(), 0), 0);
    }
  }
}

// The passes on a backend's own threads (Backend::HostCrew, as the OpenCL backend split over
// devices has) give the same result as on TBB's, with many chunks per pass and threads racing
// on the union-find.
TEST(Clutter, OnACrewMatchesTbbAndAllPairsDbscan) {
  std::mt19937 rng(31);
  const ClutterConfig c = Params(0.4, 0.01);
  Crew one(1), three(3);
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<EchoPoint> points;
    std::uniform_real_distribution<double> range(1.0, 60.0), angle(-1.2, 1.2);
    std::normal_distribution<double> jitter(0.0, 0.2);
    for (int blob = 0; blob < 400; ++blob) {
      const double r = range(rng), a = angle(rng);
      const int size = int(rng() % 12);
      for (int k = 0; k < size; ++k) {
        points.push_back(At(r * std::cos(a) + jitter(rng), r * std::sin(a) + jitter(rng)));
      }
    }
    ASSERT_GT(points.size(), 1500u);  // a dozen chunks of 128 echoes and more
    std::shuffle(points.begin(), points.end(), rng);
    ClutterFilter tbb(c, kBins, kBin), on_one(c, kBins, kBin), on_three(c, kBins, kBin);
    on_one.UseCrew(&one);
    on_three.UseCrew(&three);
    std::vector<std::uint8_t> a, b, d;
    const int clutter = tbb.Run(points, &a);
    EXPECT_EQ(on_one.Run(points, &b), clutter) << "trial " << trial;
    EXPECT_EQ(on_three.Run(points, &d), clutter) << "trial " << trial;
    EXPECT_EQ(b, a) << "trial " << trial;
    EXPECT_EQ(d, a) << "trial " << trial;
    EXPECT_EQ(a, BruteForce(points, c)) << "trial " << trial;
    // Some clusters kept, some dropped: the comparison has both kinds.
    EXPECT_GT(clutter, 0);
    EXPECT_LT(clutter, int(points.size()));
  }
}

}  // namespace
}  // namespace freespace
