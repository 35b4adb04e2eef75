// Kernel stage 3: neighbourhood hysteresis and morphological opening. Hand-made grids, OpenCV's
// morphologyEx as an independent oracle for the opening, and both backends.
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "test_util.hpp"

namespace freespace {
namespace {

class ClassifyTest : public ::testing::TestWithParam<BackendKind> {};

// Builds a map from rows written north first: S strong free, W weak free, U unknown,
// O occupied.
std::vector<LogOdds> MapFromRows(const std::vector<std::string>& rows) {
  const int height = int(rows.size()), width = int(rows[0].size());
  std::vector<LogOdds> map(std::size_t(width) * height);
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const char k = rows[height - 1 - r][c];
      map[r * width + c] = k == 'S' ? -200 : k == 'W' ? -50 : k == 'O' ? 100 : 0;
    }
  }
  return map;
}

std::vector<std::uint8_t> Classified(Backend& backend, const std::vector<LogOdds>& map) {
  backend.WriteLogOdds(map.data());
  backend.Classify();
  std::vector<std::uint8_t> free(map.size());
  backend.ReadFree(free.data());
  return free;
}

std::string Render(const std::vector<std::uint8_t>& free, int width) {
  const int height = int(free.size()) / width;
  std::string out;
  for (int r = height - 1; r >= 0; --r) {
    for (int c = 0; c < width; ++c) out += free[r * width + c] ? 'F' : '.';
    out += '\n';
  }
  return out;
}

TEST_P(ClassifyTest, HysteresisHandMadeGrid) {
  const KernelParams p = test::SmallParams(5, 5, /*opening_radius=*/0);
  ASSERT_EQ(p.t_low, -83);   // p <= 0.42
  ASSERT_EQ(p.t_high, -21);  // p <= 0.48
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
  const auto free = Classified(*backend, MapFromRows({"WWUUW",  //
                                                      "WSUWU",  //
                                                      "UUUUU",  //
                                                      "OWUSW",  //
                                                      "WOUUU"}));
  EXPECT_EQ(Render(free, 5),
            "FF...\n"
            "FF...\n"
            ".....\n"
            "...FF\n"
            ".....\n");
}

TEST_P(ClassifyTest, UnknownIsNeverFree) {
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), test::SmallParams(6, 4, 0));
  const auto free = Classified(*backend, std::vector<LogOdds>(24, 0));
  EXPECT_EQ(std::count(free.begin(), free.end(), 1), 0);
}

TEST_P(ClassifyTest, OpeningKeepsOneCellHolesAndDropsNarrowCorridors) {
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), test::SmallParams(7, 7, 1));
  // All free but one occupied cell: every free cell lies in a 3 x 3 free square.
  EXPECT_EQ(Render(Classified(*backend, MapFromRows({"SSSSSSS", "SSSSSSS", "SSSSSSS", "SSSOSSS",
                                                     "SSSSSSS", "SSSSSSS", "SSSSSSS"})),
                   7),
            "FFFFFFF\nFFFFFFF\nFFFFFFF\nFFF.FFF\nFFFFFFF\nFFFFFFF\nFFFFFFF\n");
  // Corridors 1, 2 and 3 cells wide: only the last fits the 3 x 3 element.
  EXPECT_EQ(Render(Classified(*backend, MapFromRows({"UUUUUUU", "SSSSSSS", "UUUUUUU", "SSSSSSS",
                                                     "SSSSSSS", "UUUUUUU", "UUUUUUU"})),
                   7),
            ".......\n.......\n.......\n.......\n.......\n.......\n.......\n");
  EXPECT_EQ(Render(Classified(*backend, MapFromRows({"UUUUUUU", "USSSSSU", "USSSSSU", "USSSSSU",
                                                     "UUUUUUU", "UUUUUUU", "UUUUUUU"})),
                   7),
            ".......\n.FFFFF.\n.FFFFF.\n.FFFFF.\n.......\n.......\n.......\n");
}

// The opening's element for OpenCV: the cells whose centres lie within radius + 1/2 of the
// centre's, worked out here in floating point.
cv::Mat Disk(int radius) {
  const int side = 2 * radius + 1;
  cv::Mat disk(side, side, CV_8UC1);
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      disk.at<std::uint8_t>(dy + radius, dx + radius) =
          std::hypot(double(dx), double(dy)) <= radius + 0.5 ? 1 : 0;
    }
  }
  return disk;
}

TEST(OpeningElement, IsADiskAsWideAsTheSquare) {
  // Radius 4 (a 1.8 m vehicle on 0.2 m cells): rows of half-widths 4, 4, 4, 3, 2 from the centre.
  const int expected[] = {4, 4, 4, 3, 2};
  for (int dy = 0; dy <= 4; ++dy) {
    EXPECT_EQ(OpeningHalfWidth(4, dy), expected[dy]) << dy;
    EXPECT_EQ(OpeningHalfWidth(4, -dy), expected[dy]) << dy;
  }
  for (int radius = 0; radius <= 127; ++radius) {
    EXPECT_EQ(OpeningHalfWidth(radius, 0), radius);
    for (int dy = 0; dy <= radius; ++dy) {
      const int w = OpeningHalfWidth(radius, dy);
      EXPECT_LE(std::hypot(double(w), double(dy)), radius + 0.5) << radius << " " << dy;
      EXPECT_GT(std::hypot(double(w + 1), double(dy)), radius + 0.5) << radius << " " << dy;
    }
  }
}

TEST_P(ClassifyTest, OpeningKeepsADiagonalPassageAsWideAsTheElement) {
  // A passage 7 cells wide across at 45 degrees (every cell within 3.5 cells of the diagonal):
  // the disk of radius 3 (7 cells across) runs along it; a 7 x 7 square, 9.9 cells across its
  // diagonal, would fit nowhere.
  const int n = 40;
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), test::SmallParams(n, n, 3));
  std::vector<LogOdds> map(std::size_t(n) * n, 200);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      if (std::abs(c - r) / std::sqrt(2.0) <= 3.5) map[std::size_t(r) * n + c] = -300;
    }
  }
  const auto free = Classified(*backend, map);
  for (int k = 8; k < n - 8; ++k) {
    EXPECT_TRUE(free[std::size_t(k) * n + k]) << "on the diagonal at " << k;
  }
}

TEST_P(ClassifyTest, OpeningMatchesOpenCvOnRandomMasks) {
  std::mt19937 rng(13);
  for (const auto& [width, height] : std::vector<std::pair<int, int>>{
           {1, 1}, {3, 11}, {17, 4}, {64, 64}, {301, 299}, {1500, 1500}}) {
    for (const int radius : {0, 1, 2, 4, 5, 31, 32, 70}) {
      if (width == 1500 && radius != 4) continue;
      if (radius > 4 && width != 64 && width != 301) continue;
      // Wide elements need denser masks for some disks to fit: about one not-free cell per
      // three squares' area.
      const double not_free = radius <= 4 ? 0.2 : 0.3 / double((2 * radius + 1) * (2 * radius + 1));
      std::uniform_real_distribution<double> uniform(0.0, 1.0);
      FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), test::SmallParams(width, height, radius));
      // Strong cells only, so that free0 is exactly the strong mask.
      std::vector<LogOdds> map(std::size_t(width) * height);
      cv::Mat strong(height, width, CV_8UC1);
      for (int r = 0; r < height; ++r) {
        for (int c = 0; c < width; ++c) {
          const bool s = uniform(rng) >= not_free;
          map[std::size_t(r) * width + c] = s ? -300 : LogOdds(rng() % 2 ? 0 : 200);
          strong.at<std::uint8_t>(r, c) = s ? 1 : 0;
        }
      }
      cv::Mat opened;
      cv::morphologyEx(strong, opened, cv::MORPH_OPEN, Disk(radius), cv::Point(-1, -1), 1,
                       cv::BORDER_CONSTANT, cv::Scalar(0));
      const auto free = Classified(*backend, map);
      for (int r = 0; r < height; ++r) {
        for (int c = 0; c < width; ++c) {
          ASSERT_EQ(free[std::size_t(r) * width + c], opened.at<std::uint8_t>(r, c))
              << width << "x" << height << " radius " << radius << " at " << r << "," << c;
        }
      }
    }
  }
}

TEST_P(ClassifyTest, HysteresisMatchesTheDefinitionOnRandomMaps) {
  std::mt19937 rng(17);
  const int width = 53, height = 41;
  const KernelParams p = test::SmallParams(width, height, 0);
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
  std::vector<LogOdds> map(std::size_t(width) * height);
  for (auto& m : map) m = LogOdds(int(rng() % 400) - 250);
  const auto free = Classified(*backend, map);
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const LogOdds l = map[r * width + c];
      bool near_strong = false;
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if (rr >= 0 && rr < height && cc >= 0 && cc < width && map[rr * width + cc] <= p.t_low) {
            near_strong = true;
          }
        }
      }
      const bool want = l <= p.t_low || (l <= p.t_high && near_strong);
      ASSERT_EQ(free[r * width + c], want ? 1 : 0) << r << "," << c;
    }
  }
}

// Classify() after shifts and fusions (the estimator's order, in which the OpenCL backend keeps
// the level bits from pass to pass and shifts them with the map) gives the free mask of a fresh
// classification of the same map.
TEST_P(ClassifyTest, AfterShiftsAndFusionsEqualsAFreshClassification) {
  std::mt19937 rng(29);
  for (const auto& [width, height] :
       std::vector<std::pair<int, int>>{{1, 1}, {5, 3}, {70, 33}, {130, 97}}) {
    const KernelParams p = test::SmallParams(width, height, 1);
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
    FREESPACE_BACKEND_OR_SKIP(fresh, GetParam(), p);
    const std::size_t cells = std::size_t(width) * height;
    std::vector<LogOdds> map(cells);
    for (auto& m : map) m = LogOdds(int(rng() % 400) - 250);
    backend->WriteLogOdds(map.data());
    backend->Classify();
    // A triangle on the second quarter of the rows (fixed point), and a few echoes in it.
    const auto fixed = [](double cells) { return std::int32_t(std::lround(cells * kFixedOne)); };
    const std::vector<std::int32_t> ring = {fixed(0.5 * width), fixed(0.26 * height),
                                            fixed(0.9 * width), fixed(0.49 * height),
                                            fixed(0.1 * width), fixed(0.45 * height)};
    const int r0 = height / 4, r1 = std::max(r0 + 1, height / 2);
    std::vector<std::int32_t> echoes;
    for (int r = r0; r < r1; r += 3) echoes.push_back(r * width + (r * 7) % width);
    RasterJob job;
    job.vertices = ring.data();
    job.vertex_count = 3;
    job.occupied = echoes.data();
    job.occupied_count = int(echoes.size());
    job.row_begin = r0;
    job.row_end = r1;
    for (const auto& [dx, dy] : std::vector<std::pair<int, int>>{
             {1, 0}, {0, -1}, {-33, 2}, {40, -5}, {3, 3}, {-1, -1}, {0, 0}, {65, 1}, {-64, 0}}) {
      backend->Shift(dx, dy);
      backend->Rasterize(job);
      backend->Fuse(r0, r1);
      backend->Classify();
      std::vector<std::uint8_t> got(cells), want(cells);
      backend->ReadFree(got.data());
      backend->ReadLogOdds(map.data());
      fresh->WriteLogOdds(map.data());
      fresh->Classify();
      fresh->ReadFree(want.data());
      ASSERT_EQ(got, want) << width << "x" << height << " after shift " << dx << "," << dy;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, ClassifyTest, ::testing::ValuesIn(test::AllBackends()),
                         test::BackendParamName);

}  // namespace
}  // namespace freespace
