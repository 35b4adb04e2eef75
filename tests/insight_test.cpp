// Kernel stage 4: the in-sight edges (paper IV.A). Label geometry, hand-made grids, the
// smallest-label tie-break, and both backends against a serial transcription of the paper's
// algorithm.
#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "host/host_backend.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

class InSightTest : public ::testing::TestWithParam<BackendKind> {};

std::vector<CellIndex> Edges(Backend& backend, const std::vector<std::uint8_t>& free,
                             CellIndex vehicle) {
  backend.WriteFree(free.data());
  std::vector<CellIndex> edges;
  edges.reserve(BorderLabelCount(backend.params().height, backend.params().width));
  backend.InSight(vehicle, &edges);
  return edges;
}

// The paper's loop run serially in label order; the first (smallest) label to reach a cell
// keeps it. C_Edge is the cells sorted by that label.
std::vector<CellIndex> Reference(const std::vector<std::uint8_t>& free, int width, int height,
                                 CellIndex vehicle) {
  std::vector<int> t(free.size(), -1);
  std::vector<CellIndex> edges;
  for (int l = 0; l < BorderLabelCount(height, width); ++l) {
    const CellIndex target = BorderCell(l, height, width);
    const int stop =
        host::CastRay(free.data(), width, vehicle.col, vehicle.row, target.col, target.row);
    if (t[stop] < 0) {
      t[stop] = l;
      edges.push_back({stop / width, stop % width});
    }
  }
  return edges;
}

TEST(BorderLabels, WalkTheBorderCounterClockwiseFromTheTopLeftCorner) {
  for (const auto& [width, height] :
       std::vector<std::pair<int, int>>{{1, 1}, {1, 4}, {5, 1}, {4, 3}, {300, 300}}) {
    const int labels = BorderLabelCount(height, width);
    std::vector<int> hits(std::size_t(width) * height, 0);
    for (int l = 0; l < labels; ++l) {
      const CellIndex c = BorderCell(l, height, width);
      ASSERT_TRUE(c.row == 0 || c.row == height - 1 || c.col == 0 || c.col == width - 1);
      ++hits[c.row * width + c.col];
      if (l + 1 < labels) {  // consecutive labels are the same or 8-adjacent cells
        const CellIndex n = BorderCell(l + 1, height, width);
        EXPECT_LE(std::abs(n.row - c.row), 1);
        EXPECT_LE(std::abs(n.col - c.col), 1);
      }
    }
    EXPECT_EQ(BorderCell(0, height, width), (CellIndex{height - 1, 0}));  // paper label 1
    EXPECT_EQ(BorderCell(height, height, width), (CellIndex{0, 0}));      // label H + 1
    if (width > 1 && height > 1) {
      // Every border cell is a target; the four corners twice.
      EXPECT_EQ(hits[0], 2);
      EXPECT_EQ(hits[width - 1], 2);
      EXPECT_EQ(hits[(height - 1) * width], 2);
      EXPECT_EQ(hits[(height - 1) * width + width - 1], 2);
      EXPECT_EQ(hits[width / 2], 1);
    }
  }
}

TEST_P(InSightTest, RingOfWallsIsTracedCounterClockwise) {
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), test::SmallParams(9, 9));
  // Free everywhere except a ring at Chebyshev distance 3 around the vehicle at (4, 4).
  std::vector<std::uint8_t> free(81, 1);
  for (int r = 0; r < 9; ++r) {
    for (int c = 0; c < 9; ++c) {
      if (std::max(std::abs(r - 4), std::abs(c - 4)) == 3) free[r * 9 + c] = 0;
    }
  }
  const auto edges = Edges(*backend, free, {4, 4});
  std::vector<CellIndex> ring;  // from the top-left corner, counter-clockwise
  for (int r = 7; r >= 1; --r) ring.push_back({r, 1});
  for (int c = 2; c <= 7; ++c) ring.push_back({1, c});
  for (int r = 2; r <= 7; ++r) ring.push_back({r, 7});
  for (int c = 6; c >= 2; --c) ring.push_back({7, c});
  EXPECT_EQ(edges, ring);
}

TEST_P(InSightTest, OpenMapGivesTheBorderAndTheVehicleCellNeverStops) {
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), test::SmallParams(6, 5));
  std::vector<std::uint8_t> free(30, 1);
  free[2 * 6 + 3] = 0;  // the vehicle's own cell is not free: it must not stop the rays
  const auto edges = Edges(*backend, free, {2, 3});
  std::vector<CellIndex> border;
  for (int l = 0; l < BorderLabelCount(5, 6); ++l) {
    const CellIndex c = BorderCell(l, 5, 6);
    if (std::find(border.begin(), border.end(), c) == border.end()) border.push_back(c);
  }
  EXPECT_EQ(edges, border);
  EXPECT_EQ(edges.size(), 2u * 5 + 2u * 6 - 4u);
}

TEST_P(InSightTest, SmallestLabelWinsWhenRaysShareAStopCell) {
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), test::SmallParams(7, 7));
  // A single obstacle right of the vehicle stops a whole fan of rays to the right border.
  std::vector<std::uint8_t> free(49, 1);
  free[3 * 7 + 4] = 0;
  const auto edges = Edges(*backend, free, {3, 3});
  const auto count = std::count(edges.begin(), edges.end(), CellIndex{3, 4});
  EXPECT_EQ(count, 1);
  EXPECT_EQ(edges, Reference(free, 7, 7, {3, 3}));
}

TEST_P(InSightTest, RandomMapsMatchThePapersSerialAlgorithm) {
  std::mt19937 rng(23);
  // The maps of 8192 cells a side (the largest a config allows) and the sparse obstacles of
  // the last trials give rays thousands of cells long.
  const std::vector<std::pair<int, int>> sizes = {
      {1, 1}, {2, 1}, {1, 5}, {13, 7}, {64, 80}, {300, 300}, {1500, 1500}, {8192, 5}, {7, 8192}};
  for (const auto& [width, height] : sizes) {
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), test::SmallParams(width, height));
    const int trials = std::max(width, height) >= 300 ? 3 : 8;
    for (int trial = 0; trial < trials; ++trial) {
      std::vector<std::uint8_t> free(std::size_t(width) * height);
      const unsigned density = trial == trials - 1 ? 99990 : 80000 + rng() % 20000;
      for (auto& f : free) f = rng() % 100000 < density ? 1 : 0;
      const CellIndex vehicle{int(rng() % height), int(rng() % width)};
      ASSERT_EQ(Edges(*backend, free, vehicle), Reference(free, width, height, vehicle))
          << width << "x" << height << " trial " << trial;
    }
  }
}

// host::RaySlope's closed form against the exact floor((2 d k + n) / (2 n)) for every step of
// every ray up to 300 cells, and of rays up to 8192 cells (a map's largest side) and 46340 (the
// bound it claims), and against the cells host::CastRay visits.
TEST(RaySteps, ClosedFormIsExactUpTo46340Steps) {
  const auto check = [](int n, int d) {
    const std::uint64_t slope = host::RaySlope(n, d);
    for (int k = 0; k <= n; ++k) {
      const int exact = int((2 * std::int64_t(d) * k + n) / (2 * std::int64_t(n)));
      if (host::RayMinorStep(slope, k) != exact) {
        ADD_FAILURE() << "n " << n << " d " << d << " step " << k;
        return false;
      }
    }
    return true;
  };
  for (int n = 1; n <= 300; ++n) {
    for (int d = 0; d <= n; ++d) ASSERT_TRUE(check(n, d));
  }
  std::mt19937 rng(5);
  for (const int n : {8191, 8192, 46339, 46340}) {
    for (int trial = 0; trial < 40; ++trial) {
      const int d = trial < 4 ? std::vector<int>{0, 1, n - 1, n}[trial] : int(rng() % (n + 1));
      ASSERT_TRUE(check(n, d));
    }
  }
  // CastRay's cells on a shallow and a steep ray, every direction.
  for (const auto& [dx, dy] : std::vector<std::pair<int, int>>{{8191, 2963}, {1777, 8190}}) {
    for (const int sx : {-1, 1}) {
      for (const int sy : {-1, 1}) {
        const int n = std::max(dx, dy), d = std::min(dx, dy);
        const std::uint64_t slope = host::RaySlope(n, d);
        int k = 0;
        host::CastRay(
            [&](int x, int y) {
              ++k;
              const int m = host::RayMinorStep(slope, k);
              const int want_x = dx >= dy ? sx * k : sx * m, want_y = dx >= dy ? sy * m : sy * k;
              EXPECT_EQ(x, want_x) << "step " << k;
              EXPECT_EQ(y, want_y) << "step " << k;
              return x == want_x && y == want_y;
            },
            1, 0, 0, sx * dx, sy * dy);
        EXPECT_EQ(k, n);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, InSightTest, ::testing::ValuesIn(test::AllBackends()),
                         test::BackendParamName);

}  // namespace
}  // namespace freespace
