// Kernel stage 4: the in-sight edges (paper IV.A). Label geometry, hand-made grids, the
// smallest-label tie-break, and both backends against a serial transcription of the paper's
// algorithm.
#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "core/exact_ray.hpp"
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

// The exact rays of the conservative polygon. TraceExactRayRows (the backends' way) gives the
// stops of TraceExactRay (a cell at a time) on random masks, sensors on cell corners and edges
// included, and every stop is where the straight ray first meets a blocked cell: the points
// before it lie in allowed cells, a point just beyond it in the stop cell.
TEST(ExactRays, RowsGiveTheStopsOfTheCellWalkAndStopWhereTheRayMeetsABlockedCell) {
  std::mt19937 rng(3);
  long rays = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int width = 1 + int(rng() % 120), height = 1 + int(rng() % 120);
    const int words = (width + 63) / 64;
    std::vector<std::uint64_t> bits(std::size_t(words) * height, 0);
    std::bernoulli_distribution blocked((trial % 10) * 0.05);
    for (int r = 0; r < height; ++r) {
      for (int c = 0; c < width; ++c) {
        if (!blocked(rng)) bits[std::size_t(r) * words + c / 64] |= std::uint64_t{1} << (c % 64);
      }
    }
    const auto allowed = [&](int x, int y) {
      return (bits[std::size_t(y) * words + (x >> 6)] >> (x & 63)) & 1;
    };
    SensorCell s;
    s.x = int(rng() % (width * kFixedOne));
    s.y = int(rng() % (height * kFixedOne));
    if (trial % 3 == 0) s.x -= s.x % (kFixedOne / 2);  // on a cell edge or centre line
    if (trial % 4 == 0) s.y -= s.y % kFixedOne;
    s.cell = {s.y / kFixedOne, s.x / kFixedOne};
    const Vec2 at(double(s.x) / kFixedOne, double(s.y) / kFixedOne);
    for (int l = 0; l < BorderLabelCount(height, width); ++l) {
      const CellIndex t = BorderCell(l, height, width);
      const RayStop walk = TraceExactRay(allowed, width, s, t.col, t.row);
      const RayStop rows = TraceExactRayRows(bits.data(), words, width, s, t.col, t.row);
      ASSERT_EQ(rows.cell, walk.cell) << "trial " << trial << " label " << l;
      ASSERT_EQ(rows.kind, walk.kind) << "trial " << trial << " label " << l;
      ASSERT_EQ(rows.line, walk.line) << "trial " << trial << " label " << l;
      const Vec2 end = RayStopPoint(s, t.col, t.row, walk), d = end - at;
      for (int k = 1; k < 64; ++k) {  // inside cells, away from their edges
        const Vec2 q = at + (k / 64.0) * d;
        const double fx = q.x() - std::floor(q.x()), fy = q.y() - std::floor(q.y());
        if (fx < 1e-9 || fx > 1 - 1e-9 || fy < 1e-9 || fy > 1 - 1e-9) continue;
        const int qc = int(std::floor(q.x())), qr = int(std::floor(q.y()));
        ASSERT_TRUE(allowed(qc, qr) || (qr == s.cell.row && qc == s.cell.col))
            << "trial " << trial << " label " << l << " passes " << q.transpose();
      }
      if (walk.kind == kRayCrossX || walk.kind == kRayCrossY) {
        const Vec2 beyond = end + 1e-6 * (Vec2(t.col + 0.5, t.row + 0.5) - at).normalized();
        EXPECT_EQ(int(std::floor(beyond.y())) * width + int(std::floor(beyond.x())), walk.cell);
      }
      ++rays;
    }
  }
  EXPECT_GT(rays, 20000);
}

// The exact rays over full blocks (TraceExactRayBlocks) give the stops of TraceExactRay on
// random masks that are mostly allowed (so that most blocks are full): sparse blocked cells and
// blocked rectangles, sensors on block corners and edges and cell edges included.
TEST(ExactRays, FullBlocksGiveTheStopsOfTheCellWalk) {
  std::mt19937 rng(8);
  long rays = 0, through_blocks = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int width = 1 + int(rng() % 200), height = 1 + int(rng() % 200);
    const int words = (width + 63) / 64;
    std::vector<std::uint64_t> bits(std::size_t(words) * height, 0);
    std::bernoulli_distribution blocked((trial % 5) * 0.002);
    std::vector<std::uint8_t> cells(std::size_t(width) * height, 1);
    for (auto& c : cells) c = !blocked(rng);
    if (trial % 3 == 2) {  // a cell at some block corners: what a ray through the corner meets
      for (int y = kBlockCells; y < height; y += kBlockCells) {
        for (int x = kBlockCells; x < width; x += kBlockCells) {
          if (rng() % 8 != 0) continue;
          cells[std::size_t(y - int(rng() % 2)) * width + x - int(rng() % 2)] = 0;
        }
      }
    }
    for (int k = int(rng() % 6); k > 0; --k) {  // walls and boxes
      const int c0 = int(rng() % width), r0 = int(rng() % height);
      const int c1 = std::min(width, c0 + 1 + int(rng() % 12));
      const int r1 = std::min(height, r0 + 1 + int(rng() % 12));
      for (int r = r0; r < r1; ++r) {
        for (int c = c0; c < c1; ++c) cells[std::size_t(r) * width + c] = 0;
      }
    }
    for (int r = 0; r < height; ++r) {
      for (int c = 0; c < width; ++c) {
        if (cells[std::size_t(r) * width + c])
          bits[std::size_t(r) * words + c / 64] |= std::uint64_t{1} << (c % 64);
      }
    }
    const auto allowed = [&](int x, int y) {
      return (bits[std::size_t(y) * words + (x >> 6)] >> (x & 63)) & 1;
    };
    std::vector<std::uint64_t> block_bits;
    const int row_begin = trial % 7 == 0 ? height / 3 : 0;  // rows below it set nothing
    for (int r = 0; r < row_begin; ++r) {
      for (int w = 0; w < words; ++w) bits[std::size_t(r) * words + w] = 0;
    }
    const BlockView blocks =
        FullBlocks(bits.data(), words, width, height, row_begin, height, &block_bits);
    SensorCell s;
    s.x = int(rng() % (width * kFixedOne));
    s.y = int(rng() % (height * kFixedOne));
    if (trial % 3 != 1) s.x -= s.x % (kBlockCells * kFixedOne);  // on a block edge or corner
    if (trial % 4 != 1) s.y -= s.y % (trial % 2 == 0 ? kBlockCells * kFixedOne : kFixedOne);
    if (trial % 5 == 1) s.x -= s.x % (kFixedOne / 2);
    s.cell = {s.y / kFixedOne, s.x / kFixedOne};
    for (int l = 0; l < BorderLabelCount(height, width); ++l) {
      const CellIndex t = BorderCell(l, height, width);
      const RayStop walk = TraceExactRay(allowed, width, s, t.col, t.row);
      const RayStop fast = TraceExactRayBlocks(bits.data(), words, width, blocks, s, t.col, t.row);
      ASSERT_EQ(fast.cell, walk.cell) << "trial " << trial << " label " << l;
      ASSERT_EQ(fast.kind, walk.kind) << "trial " << trial << " label " << l;
      ASSERT_EQ(fast.line, walk.line) << "trial " << trial << " label " << l;
      ++rays;
      through_blocks += blocks.Full(s.cell.col >> kBlockShift, s.cell.row >> kBlockShift);
    }
  }
  EXPECT_GT(rays, 50000);
  EXPECT_GT(through_blocks, 20000);  // rays that start in a full block
}

// Every block FullBlocks() calls full has all its cells allowed and inside the map, and every
// other block does not.
TEST(ExactRays, FullBlocksAreTheBlocksOfAllowedCells) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 100; ++trial) {
    const int width = 1 + int(rng() % 300), height = 1 + int(rng() % 100);
    const int words = (width + 63) / 64;
    std::vector<std::uint64_t> bits(std::size_t(words) * height, 0);
    std::bernoulli_distribution blocked(0.002 * (trial % 4));
    for (int r = 0; r < height; ++r) {
      for (int c = 0; c < width; ++c) {
        if (!blocked(rng)) bits[std::size_t(r) * words + c / 64] |= std::uint64_t{1} << (c % 64);
      }
    }
    std::vector<std::uint64_t> block_bits;
    const BlockView blocks = FullBlocks(bits.data(), words, width, height, 0, height, &block_bits);
    for (int br = -1; br <= height / kBlockCells + 1; ++br) {
      for (int bc = -1; bc <= width / kBlockCells + 1; ++bc) {
        bool full = br >= 0 && bc >= 0;
        for (int r = br * kBlockCells; full && r < (br + 1) * kBlockCells; ++r) {
          for (int c = bc * kBlockCells; full && c < (bc + 1) * kBlockCells; ++c) {
            full = r < height && c < width &&
                   ((bits[std::size_t(r) * words + c / 64] >> (c % 64)) & 1);
          }
        }
        ASSERT_EQ(blocks.Full(bc, br), full) << "trial " << trial << " block " << bc << ", " << br;
      }
    }
  }
}

// Both backends' exact rays on a mask made by stage 3b with no margin: the free mask plus the
// sensor's cell, against TraceExactRay.
TEST_P(InSightTest, ExactRaysMatchTheCellWalk) {
  std::mt19937 rng(19);
  for (int trial = 0; trial < 30; ++trial) {
    const int width = 10 + int(rng() % 200), height = 10 + int(rng() % 150);
    Config config = test::SmallConfig(width, height);
    config.polygon.shape = PolygonShape::kInside;
    const KernelParams p = MakeKernelParams(config);
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
    std::vector<std::uint8_t> free(std::size_t(width) * height);
    std::bernoulli_distribution open(0.8 + 0.02 * (trial % 10));
    for (auto& f : free) f = open(rng);
    const std::vector<LogOdds> unknown(free.size(), 0);
    backend->WriteLogOdds(unknown.data());
    backend->WriteFree(free.data());
    backend->SetEchoes(nullptr, 0);
    const SensorCell s = MakeSensorCell(
        Vec2((rng() % (width * 4)) / 4.0, (rng() % (height * 4)) / 4.0), width, height);
    free[std::size_t(s.cell.row) * width + s.cell.col] = 1;
    MarginViews views;
    views.Add(s);
    backend->Mask(s, views);
    std::vector<RayStop> stops;
    std::vector<CellIndex> edges;
    edges.reserve(BorderLabelCount(height, width));
    backend->InSightExact(s, &stops, &edges);
    ASSERT_EQ(int(stops.size()), BorderLabelCount(height, width));
    const auto allowed = [&](int x, int y) { return free[std::size_t(y) * width + x] != 0; };
    std::vector<std::int32_t> cells;
    for (int l = 0; l < BorderLabelCount(height, width); ++l) {
      const CellIndex t = BorderCell(l, height, width);
      const RayStop want = TraceExactRay(allowed, width, s, t.col, t.row);
      ASSERT_EQ(stops[l].cell, want.cell) << "trial " << trial << " label " << l;
      ASSERT_EQ(stops[l].kind, want.kind) << "trial " << trial << " label " << l;
      ASSERT_EQ(stops[l].line, want.line) << "trial " << trial << " label " << l;
      if (std::find(cells.begin(), cells.end(), want.cell) == cells.end())
        cells.push_back(want.cell);
    }
    ASSERT_EQ(edges.size(), cells.size());  // C_Edge: each stop cell once, by smallest label
    for (std::size_t i = 0; i < cells.size(); ++i) {
      EXPECT_EQ(edges[i].row * width + edges[i].col, cells[i]);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, InSightTest, ::testing::ValuesIn(test::AllBackends()),
                         test::BackendParamName);

}  // namespace
}  // namespace freespace
