// Kernel stage 2: fixed-point log-odds fusion with clamping, on both backends.
#include <random>

#include "test_util.hpp"

namespace freespace {
namespace {

class FuseTest : public ::testing::TestWithParam<BackendKind> {};

TEST_P(FuseTest, AddsOncePerScanAndClamps) {
  const KernelParams p = test::SmallParams(4, 1);
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
  const std::vector<LogOdds> map = {0, LogOdds(p.l_max - 10), LogOdds(p.l_min + 10), 17};
  const std::vector<std::uint8_t> update = {kUpdateFree, kUpdateOccupied, kUpdateFree, kUpdateNone};
  backend->WriteLogOdds(map.data());
  backend->WriteUpdateMask(update.data());
  backend->Fuse(0, 1);
  std::vector<LogOdds> out(4);
  backend->ReadLogOdds(out.data());
  EXPECT_EQ(out[0], p.l_free);
  EXPECT_EQ(out[1], p.l_max);  // clamped above
  EXPECT_EQ(out[2], p.l_min);  // clamped below
  EXPECT_EQ(out[3], 17);       // no update
  // The paper's probabilities: one free observation is p = 0.40, one hit p = 0.65.
  EXPECT_NEAR(ProbabilityFromLogOdds(out[0]), 0.40, 1e-3);
  EXPECT_EQ(p.l_occupied, LogOddsFromProbability(0.65));
}

TEST_P(FuseTest, RandomMapsOnlyInsideTheRowRange) {
  std::mt19937 rng(11);
  for (const auto& [width, height] :
       std::vector<std::pair<int, int>>{{1, 1}, {7, 3}, {300, 300}, {1500, 1500}}) {
    const KernelParams p = test::SmallParams(width, height);
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
    const std::size_t cells = std::size_t(width) * height;
    std::vector<LogOdds> map(cells);
    std::vector<std::uint8_t> update(cells);
    for (auto& m : map) m = LogOdds(int(rng() % (p.l_max - p.l_min + 1)) + p.l_min);
    for (auto& u : update) u = std::uint8_t(rng() % 3);
    backend->WriteLogOdds(map.data());
    backend->WriteUpdateMask(update.data());
    const int r0 = height / 3, r1 = height - height / 4;
    backend->Fuse(r0, r1);
    std::vector<LogOdds> out(cells);
    backend->ReadLogOdds(out.data());
    for (std::size_t i = 0; i < cells; ++i) {
      const int row = int(i / width);
      int want = map[i];
      if (row >= r0 && row < r1) {
        want += update[i] == kUpdateFree       ? p.l_free
                : update[i] == kUpdateOccupied ? p.l_occupied
                                               : 0;
        want = std::clamp<int>(want, p.l_min, p.l_max);
      }
      ASSERT_EQ(out[i], want) << width << "x" << height << " cell " << i;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, FuseTest, ::testing::ValuesIn(test::AllBackends()),
                         test::BackendParamName);

}  // namespace
}  // namespace freespace
