// Kernel stage 1: the full-scan polygon rasterized into the update mask. Hand-made grids, an
// exact brute-force oracle on random polygons, odd sizes, and both backends.
#include <random>

#include "host/host_backend.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

using test::SmallParams;

class RasterizeTest : public ::testing::TestWithParam<BackendKind> {};

// Builds a ring in fixed point from cell coordinates.
std::vector<std::int32_t> Ring(const std::vector<std::pair<double, double>>& cells) {
  std::vector<std::int32_t> v;
  for (const auto& [x, y] : cells) {
    v.push_back(std::int32_t(std::llround(x * kFixedOne)));
    v.push_back(std::int32_t(std::llround(y * kFixedOne)));
  }
  return v;
}

// Exact even-odd oracle: a centre is inside when an odd number of edges cross its row's centre
// line strictly left of it (the same tie rule the kernels document).
std::vector<std::uint8_t> Oracle(const std::vector<std::int32_t>& v, int width, int height) {
  const int n = int(v.size() / 2);
  std::vector<std::uint8_t> out(std::size_t(width) * height, kUpdateNone);
  for (int r = 0; r < height; ++r) {
    const std::int64_t yc = std::int64_t(r) * kFixedOne + kFixedHalf;
    for (int c = 0; c < width; ++c) {
      const std::int64_t xc = std::int64_t(c) * kFixedOne + kFixedHalf;
      bool inside = false;
      for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        const std::int64_t x0 = v[2 * i], y0 = v[2 * i + 1], x1 = v[2 * j], y1 = v[2 * j + 1];
        if ((y0 <= yc) == (y1 <= yc)) continue;
        // x_cross < xc  <=>  x0 * dy + (yc - y0) * dx < xc * dy  (flipped when dy < 0)
        const std::int64_t dy = y1 - y0;
        const std::int64_t lhs = x0 * dy + (yc - y0) * (x1 - x0), rhs = xc * dy;
        if (dy > 0 ? lhs < rhs : lhs > rhs) inside = !inside;
      }
      out[std::size_t(r) * width + c] = inside ? kUpdateFree : kUpdateNone;
    }
  }
  return out;
}

// Clears, in `mask`, the free cells the outline of edges 1 .. n - 2 touches, by its definition
// (RasterJob::clear_outline) taken point by point: in each row r, the edge's x on its line at
// every integer y of its part with 256 r <= y <= 256 (r + 1), floor-divided (a vertex's own x at
// the vertex); the cells from the least x to the greatest.
void ClearOutlineOracle(const std::vector<std::int32_t>& v, int width, int height,
                        std::vector<std::uint8_t>* mask) {
  const auto floor_div = [](std::int64_t a, std::int64_t b) {
    return a / b - ((a % b != 0 && (a < 0) != (b < 0)) ? 1 : 0);
  };
  const int n = int(v.size() / 2);
  for (int i = 1; i + 1 < n; ++i) {
    const std::int64_t x0 = v[2 * i], y0 = v[2 * i + 1], x1 = v[2 * i + 2], y1 = v[2 * i + 3];
    for (int r = 0; r < height; ++r) {
      std::int64_t lo = INT64_MAX, hi = INT64_MIN;
      for (std::int64_t y = std::int64_t(r) * kFixedOne; y <= std::int64_t(r + 1) * kFixedOne;
           ++y) {
        if (y < std::min(y0, y1) || y > std::max(y0, y1)) continue;
        const std::int64_t xa = y0 == y1 ? x0 : x0 + floor_div((y - y0) * (x1 - x0), y1 - y0);
        const std::int64_t xb = y0 == y1 ? x1 : xa;
        lo = std::min({lo, xa, xb});
        hi = std::max({hi, xa, xb});
      }
      if (lo > hi) continue;
      for (std::int64_t c = std::max<std::int64_t>(floor_div(lo, kFixedOne), 0);
           c <= std::min<std::int64_t>(floor_div(hi, kFixedOne), width - 1); ++c) {
        std::uint8_t& cell = (*mask)[std::size_t(r) * width + std::size_t(c)];
        if (cell == kUpdateFree) cell = kUpdateNone;
      }
    }
  }
}

std::vector<std::uint8_t> Rasterize(Backend& backend, const std::vector<std::int32_t>& ring,
                                    const std::vector<std::int32_t>& occupied, int row_begin,
                                    int row_end, bool clear_outline = false) {
  RasterJob job;
  job.clear_outline = clear_outline;
  job.vertices = ring.data();
  job.vertex_count = int(ring.size() / 2);
  job.occupied = occupied.data();
  job.occupied_count = int(occupied.size());
  job.row_begin = row_begin;
  job.row_end = row_end;
  backend.Rasterize(job);
  std::vector<std::uint8_t> mask(std::size_t(backend.params().width) * backend.params().height);
  backend.ReadUpdateMask(mask.data());
  return mask;
}

TEST_P(RasterizeTest, TriangleHandComputed) {
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), SmallParams(8, 8));
  // Triangle (0,0) (8,0) (0,8): centre (c + .5, r + .5) inside iff c + r <= 7. A centre
  // exactly on an edge counts as left of it, so the centres on the hypotenuse (c + r = 7) are
  // inside. Cell (row 2, col 1) is occupied.
  const auto mask = Rasterize(*backend, Ring({{0, 0}, {8, 0}, {0, 8}}), {2 * 8 + 1}, 0, 8);
  const char* expected[8] = {
      // row 7 (north) first
      "F.......",  //
      "FF......",  //
      "FFF.....",  //
      "FFFF....",  //
      "FFFFF...",  //
      "FOFFFF..",  //
      "FFFFFFF.",  //
      "FFFFFFFF",  //
  };
  for (int r = 0; r < 8; ++r) {
    for (int c = 0; c < 8; ++c) {
      const char e = expected[7 - r][c];
      const std::uint8_t want = e == 'F' ? kUpdateFree : e == 'O' ? kUpdateOccupied : kUpdateNone;
      EXPECT_EQ(mask[r * 8 + c], want) << "row " << r << " col " << c;
    }
  }
}

TEST_P(RasterizeTest, CellsTheOutlineTouchesGetNoFreeUpdate) {
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), SmallParams(8, 8));
  // The triangle above with sensor_model.free_on_outline off: its one edge between beams, the
  // hypotenuse from (8, 0) to (0, 8), touches the cells with c + r = 7 (and c + r = 8, outside
  // anyway); the two edges at the sensor (vertex 0) clear nothing. The echo keeps its cell.
  const auto mask = Rasterize(*backend, Ring({{0, 0}, {8, 0}, {0, 8}}), {2 * 8 + 1}, 0, 8,
                              /*clear_outline=*/true);
  for (int r = 0; r < 8; ++r) {
    for (int c = 0; c < 8; ++c) {
      const std::uint8_t want = (r == 2 && c == 1) ? kUpdateOccupied
                                : c + r <= 6       ? kUpdateFree
                                                   : kUpdateNone;
      EXPECT_EQ(mask[r * 8 + c], want) << "row " << r << " col " << c;
    }
  }
  // The next scan without the rule fills the diagonal again: nothing of the outline is left over.
  const auto again = Rasterize(*backend, Ring({{0, 0}, {8, 0}, {0, 8}}), {}, 0, 8);
  EXPECT_EQ(again[7], kUpdateFree);
  EXPECT_EQ(again[7 * 8], kUpdateFree);
}

TEST_P(RasterizeTest, RowsOutsideTheRangeAreUntouched) {
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), SmallParams(10, 10));
  std::vector<std::uint8_t> fill(100, 7);
  backend->WriteUpdateMask(fill.data());
  const auto mask = Rasterize(*backend, Ring({{1, 1}, {9, 1}, {9, 9}, {1, 9}}), {}, 3, 6);
  for (int r = 0; r < 10; ++r) {
    for (int c = 0; c < 10; ++c) {
      const std::uint8_t got = mask[r * 10 + c];
      if (r < 3 || r >= 6) {
        EXPECT_EQ(got, 7) << r << "," << c;
      } else {
        EXPECT_EQ(got, (c >= 1 && c <= 8) ? kUpdateFree : kUpdateNone) << r << "," << c;
      }
    }
  }
}

TEST_P(RasterizeTest, RandomStarPolygonsMatchTheExactOracle) {
  std::mt19937 rng(7);
  for (const auto& [width, height] :
       std::vector<std::pair<int, int>>{{1, 1}, {1, 9}, {9, 1}, {13, 5}, {37, 61}, {128, 96}}) {
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), SmallParams(width, height));
    for (int trial = 0; trial < 20; ++trial) {
      // A sensor somewhere around the map and a fan of beams, some far outside.
      std::uniform_real_distribution<double> pos(-0.3, 1.3), range(0.0, 1.5 * (width + height));
      const double sx = pos(rng) * width, sy = pos(rng) * height;
      std::vector<std::pair<double, double>> cells{{sx, sy}};
      const int beams = 3 + int(rng() % 200);
      const double a0 = std::uniform_real_distribution<double>(0, 6.28)(rng);
      for (int b = 0; b < beams; ++b) {
        const double a = a0 + 4.0 * b / beams, r = range(rng);
        cells.push_back({sx + r * std::cos(a), sy + r * std::sin(a)});
      }
      // Vertices exactly on cell centres and on rows exercise the tie rules.
      if (trial % 3 == 0) {
        for (auto& [x, y] : cells) {
          x = std::floor(x) + 0.5;
          y = std::floor(y) + 0.5;
        }
      }
      const auto ring = Ring(cells);
      auto expected = Oracle(ring, width, height);
      std::vector<std::int32_t> occupied;
      for (int k = 0; k < 5; ++k) {
        const std::int32_t cell = std::int32_t(rng() % (width * height));
        occupied.push_back(cell);
        expected[cell] = kUpdateOccupied;
      }
      EXPECT_EQ(Rasterize(*backend, ring, occupied, 0, height), expected)
          << width << "x" << height << " trial " << trial;
      // With the outline rule: the same less the free cells its outline touches.
      auto outlined = Oracle(ring, width, height);
      ClearOutlineOracle(ring, width, height, &outlined);
      for (const std::int32_t cell : occupied) outlined[cell] = kUpdateOccupied;
      EXPECT_EQ(Rasterize(*backend, ring, occupied, 0, height, true), outlined)
          << width << "x" << height << " trial " << trial << ", outline";
      // The host's per-row reference agrees as well.
      std::vector<std::uint8_t> row(width);
      for (int r = 0; r < height; ++r) {
        host::RasterizeRow(ring.data(), int(ring.size() / 2), width, r, row.data());
        for (int c = 0; c < width; ++c) {
          if (expected[r * width + c] != kUpdateOccupied) {
            ASSERT_EQ(row[c], expected[r * width + c]) << r << "," << c;
          }
        }
      }
    }
  }
}

TEST_P(RasterizeTest, LargeMapOfFifteenHundredCells) {
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), SmallParams(1500, 1500));
  // A star of 581 beams (the ScaLa's 145 deg at 0.25 deg) from the map's centre.
  std::mt19937 rng(3);
  std::vector<std::pair<double, double>> cells{{750.3, 749.6}};
  for (int b = 0; b < 581; ++b) {
    const double a = (-72.5 + 0.25 * b) * M_PI / 180.0;
    const double r = 50.0 + double(rng() % 700);
    cells.push_back({750.3 + r * std::cos(a), 749.6 + r * std::sin(a)});
  }
  const auto ring = Ring(cells);
  const auto mask = Rasterize(*backend, ring, {}, 0, 1500);
  // Spot-check rows against the per-row reference.
  std::vector<std::uint8_t> row(1500);
  for (int r = 0; r < 1500; r += 37) {
    host::RasterizeRow(ring.data(), int(ring.size() / 2), 1500, r, row.data());
    ASSERT_TRUE(std::equal(row.begin(), row.end(), mask.begin() + std::size_t(r) * 1500)) << r;
  }
  EXPECT_EQ(mask[750 * 1500 + 760], kUpdateFree);  // just ahead of the sensor
  EXPECT_EQ(mask[750 * 1500 + 740], kUpdateNone);  // behind it: outside the aperture
}

INSTANTIATE_TEST_SUITE_P(Backends, RasterizeTest, ::testing::ValuesIn(test::AllBackends()),
                         test::BackendParamName);

}  // namespace
}  // namespace freespace
