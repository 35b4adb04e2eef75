// The integer map shift of the vehicle-on-a-circle alignment (eqs. 4, 5), on both backends.
#include <algorithm>
#include <random>

#include "test_util.hpp"

namespace freespace {
namespace {

class ShiftTest : public ::testing::TestWithParam<BackendKind> {};

TEST_P(ShiftTest, MovesByWholeCellsAndFillsUnknown) {
  std::mt19937 rng(5);
  for (const auto& [width, height] :
       std::vector<std::pair<int, int>>{{1, 1}, {5, 3}, {64, 47}, {1500, 1500}}) {
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), test::SmallParams(width, height));
    const std::size_t cells = std::size_t(width) * height;
    for (const auto& [dx, dy] : std::vector<std::pair<int, int>>{
             {0, 0}, {1, 0}, {0, -1}, {-3, 2}, {width / 2, -height / 3}, {width, 0}, {-7000, 9}}) {
      std::vector<LogOdds> map(cells);
      for (auto& m : map) m = LogOdds(int(rng() % 2001) - 1000);
      backend->WriteLogOdds(map.data());
      backend->Shift(dx, dy);
      std::vector<LogOdds> out(cells);
      backend->ReadLogOdds(out.data());
      for (int r = 0; r < height; ++r) {
        for (int c = 0; c < width; ++c) {
          const int sr = r + dy, sc = c + dx;
          const bool inside = sr >= 0 && sr < height && sc >= 0 && sc < width;
          const LogOdds want = inside ? map[std::size_t(sr) * width + sc] : LogOdds(0);
          ASSERT_EQ(out[std::size_t(r) * width + c], want)
              << width << "x" << height << " shift " << dx << "," << dy << " at " << r << "," << c;
        }
      }
    }
  }
}

// A map known on a few rows only, shifted back and forth and fused on other rows after each
// shift (on OpenCL the row pass that shifts and fuses at once): the backends touch only the rows
// that can hold a known cell, and each step must still equal a plain shift and fusion of the
// whole map, rows that the other map buffer held before included; stage 3, which skips the rows
// it knows to be empty, must equal stage 3 on a map written whole.
TEST_P(ShiftTest, KnownRowsOnlyMatchAWholeMapShift) {
  const int width = 97, height = 211;
  const KernelParams params = test::SmallParams(width, height);
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), params);
  FREESPACE_BACKEND_OR_SKIP(oracle, GetParam(), params);  // classifies the whole map each time
  std::mt19937 rng(11);
  std::vector<LogOdds> want(std::size_t(width) * height, 0), got(want.size());
  std::vector<std::uint8_t> free(want.size()), free_want(want.size());
  backend->Clear();
  for (int step = 0; step < 60; ++step) {
    const int dx = int(rng() % 41) - 20, dy = int(rng() % 61) - 30;
    const int r0 = int(rng() % height), r1 = std::min(height, r0 + 1 + int(rng() % 25));
    backend->Shift(dx, dy);
    std::vector<LogOdds> shifted(want.size(), 0);
    for (int r = 0; r < height; ++r) {
      for (int c = 0; c < width; ++c) {
        const int sr = r + dy, sc = c + dx;
        if (sr >= 0 && sr < height && sc >= 0 && sc < width) {
          shifted[std::size_t(r) * width + c] = want[std::size_t(sr) * width + sc];
        }
      }
    }
    want.swap(shifted);
    // A rectangle over every column of rows [r0, r1): those rows free, alternating in sign
    // so that cells return to unknown (0) now and then.
    const std::int32_t x0 = -kFixedOne, x1 = (width + 1) * kFixedOne;
    const std::int32_t y0 = r0 * kFixedOne, y1 = r1 * kFixedOne;
    const std::int32_t ring[8] = {x0, y0, x1, y0, x1, y1, x0, y1};
    std::vector<std::int32_t> occupied;
    if (step % 2) {
      for (int r = r0; r < r1; ++r) {
        for (int c = 0; c < width; ++c) occupied.push_back(r * width + c);
      }
    }
    RasterJob job;
    job.vertices = ring;
    job.vertex_count = 4;
    job.occupied = occupied.data();
    job.occupied_count = int(occupied.size());
    job.row_begin = r0;
    job.row_end = r1;
    backend->Rasterize(job);
    // Every third step fuses one row fewer than it rasterized, which OpenCL runs as a shift and
    // a fusion on their own instead of its row pass.
    const int fuse_end = step % 3 == 2 ? r1 - 1 : r1;
    backend->Fuse(r0, fuse_end);
    const int delta = step % 2 ? params.l_occupied : params.l_free;
    for (int r = r0; r < fuse_end; ++r) {
      for (int c = 0; c < width; ++c) {
        LogOdds& m = want[std::size_t(r) * width + c];
        m = LogOdds(std::clamp(int(m) + delta, int(params.l_min), int(params.l_max)));
      }
    }
    backend->ReadLogOdds(got.data());
    for (std::size_t i = 0; i < want.size(); ++i) {
      ASSERT_EQ(got[i], want[i]) << "step " << step << " shift " << dx << "," << dy << " rows "
                                 << r0 << ".." << r1 << " at " << i / width << "," << i % width;
    }
    // Stage 3 on the known rows only (and those it set before) against the whole map.
    backend->Classify();
    oracle->WriteLogOdds(want.data());
    oracle->Classify();
    backend->ReadFree(free.data());
    oracle->ReadFree(free_want.data());
    for (std::size_t i = 0; i < want.size(); ++i) {
      ASSERT_EQ(free[i], free_want[i])
          << "step " << step << " free mask at " << i / width << "," << i % width;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, ShiftTest, ::testing::ValuesIn(test::AllBackends()),
                         test::BackendParamName);

}  // namespace
}  // namespace freespace
