// The integer map shift of the vehicle-on-a-circle alignment (eqs. 4, 5), on both backends.
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

INSTANTIATE_TEST_SUITE_P(Backends, ShiftTest, ::testing::ValuesIn(test::AllBackends()),
                         test::BackendParamName);

}  // namespace
}  // namespace freespace
