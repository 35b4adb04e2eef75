// The conventional inverse sensor model (the paper's baseline): one Bresenham ray per echo,
// cells updated as often as rays cross them, on both backends.
#include <random>

#include "host/host_backend.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

class RaysTest : public ::testing::TestWithParam<BackendKind> {};

std::vector<std::int32_t> Delta(Backend& backend, int col, int row,
                                const std::vector<std::int32_t>& ends) {
  RayJob job;
  job.origin_col = col;
  job.origin_row = row;
  job.ends = ends.data();
  job.ray_count = int(ends.size() / 2);
  job.row_begin = 0;
  job.row_end = backend.params().height;
  backend.CastRays(job);
  std::vector<std::int32_t> delta(std::size_t(backend.params().width) * backend.params().height);
  backend.ReadRayDelta(delta.data());
  return delta;
}

TEST_P(RaysTest, CellsCrossedTwiceAreUpdatedTwice) {
  const KernelParams p = test::SmallParams(6, 4);
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
  // From (col 0, row 1): one ray to (5, 1), one to (3, 1): cells 0..2 are crossed twice.
  const auto delta = Delta(*backend, 0, 1, {5, 1, 3, 1});
  const int f = p.l_free, o = p.l_occupied;
  const std::vector<std::int32_t> row1 = {2 * f, 2 * f, 2 * f, o + f, f, o};
  EXPECT_EQ(std::vector<std::int32_t>(delta.begin() + 6, delta.begin() + 12), row1);
  EXPECT_EQ(std::count(delta.begin(), delta.end(), 0), 18);
}

TEST_P(RaysTest, RaysLeavingTheMapAreClippedAndFusionClampsAndClears) {
  const KernelParams p = test::SmallParams(4, 4);
  FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
  // From outside the map, through it, to an end outside: only free updates inside.
  auto delta = Delta(*backend, -3, 2, {9, 2});
  for (int c = 0; c < 4; ++c) EXPECT_EQ(delta[2 * 4 + c], p.l_free);
  std::vector<LogOdds> map(16, 0);
  map[2 * 4 + 1] = LogOdds(p.l_min + 3);
  backend->WriteLogOdds(map.data());
  backend->FuseRays(0, 4);
  backend->ReadLogOdds(map.data());
  EXPECT_EQ(map[2 * 4 + 1], p.l_min);  // clamped once after summing
  EXPECT_EQ(map[2 * 4 + 0], p.l_free);
  EXPECT_EQ(map[0], 0);
  backend->ReadRayDelta(delta.data());
  EXPECT_EQ(std::count(delta.begin(), delta.end(), 0), 16);  // cleared for the next scan
}

TEST_P(RaysTest, RandomFansMatchASerialSum) {
  std::mt19937 rng(41);
  for (const auto& [width, height] :
       std::vector<std::pair<int, int>>{{1, 1}, {9, 5}, {300, 300}, {1500, 1500}}) {
    const KernelParams p = test::SmallParams(width, height);
    FREESPACE_BACKEND_OR_SKIP(backend, GetParam(), p);
    const int col = int(rng() % width), row = int(rng() % height);
    std::vector<std::int32_t> ends;
    for (int i = 0; i < 2000; ++i) {
      ends.push_back(int(rng() % (width + 40)) - 20);
      ends.push_back(int(rng() % (height + 40)) - 20);
    }
    std::vector<std::int32_t> expected(std::size_t(width) * height, 0);
    for (int i = 0; i < 2000; ++i) {
      host::AccumulateRay(expected.data(), width, height, col, row, ends[2 * i], ends[2 * i + 1],
                          p.l_free, p.l_occupied);
    }
    EXPECT_EQ(Delta(*backend, col, row, ends), expected) << width << "x" << height;
    backend->FuseRays(0, height);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, RaysTest, ::testing::ValuesIn(test::AllBackends()),
                         test::BackendParamName);

}  // namespace
}  // namespace freespace
