// Every kernel stage of the OpenCL backend in both work shapes (per row, per vector) against the
// host backend, on random inputs. Compiled only when the OpenCL backend is; each case skips
// when no OpenCL device exists here.
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "host/host_backend.hpp"
#include "opencl/backend.hpp"
#include "opencl/runtime.hpp"
#include "opencl_device.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

// Random inputs for every stage, run on the host backend and on an OpenCL backend forced to one
// work shape; every buffer compared after every stage.
class WorkShapeTest : public ::testing::TestWithParam<OpenClBackend::WorkShape> {};

std::vector<std::int32_t> StarPolygon(std::mt19937& rng, int width, int height) {
  std::uniform_real_distribution<double> pos(-0.2, 1.2), unit(0.0, 1.0);
  const double sx = pos(rng) * width, sy = pos(rng) * height;
  std::vector<std::int32_t> ring = {std::int32_t(sx * kFixedOne), std::int32_t(sy * kFixedOne)};
  const int beams = 3 + int(rng() % 300);
  for (int b = 0; b < beams; ++b) {
    const double a = 4.0 * b / beams, r = unit(rng) * 1.2 * (width + height);
    ring.push_back(std::int32_t((sx + r * std::cos(a)) * kFixedOne));
    ring.push_back(std::int32_t((sy + r * std::sin(a)) * kFixedOne));
  }
  return ring;
}

TEST_P(WorkShapeTest, EveryStageMatchesTheHost) {
  FREESPACE_DEVICE_OR_SKIP(found);
  if (GetParam() == OpenClBackend::WorkShape::kVectorPerItem &&
      opencl::DeviceCount(BackendConfig{}) > 1) {
    GTEST_SKIP() << "the GPU shape runs on one device; " << opencl::kDevicesEnv
                 << " asks for a split over " << opencl::DeviceCount(BackendConfig{});
  }
  std::mt19937 rng(29);
  for (const auto& [width, height, radius] :
       std::vector<std::tuple<int, int, int>>{{1, 1, 0},
                                              {5, 3, 1},
                                              {9, 3, 4},  // the window wider than the map
                                              {33, 17, 2},
                                              {37, 61, 4},
                                              {300, 300, 4},
                                              {517, 263, 18},
                                              {333, 170, 70}}) {
    const KernelParams params = test::SmallParams(width, height, radius);
    HostBackend host(params, 0);
    OpenClBackend ocl(params, BackendConfig{}, GetParam());
    const std::size_t cells = std::size_t(width) * height;
    const std::string where = std::to_string(width) + "x" + std::to_string(height);
    auto same_map = [&](const char* stage) {
      std::vector<LogOdds> a(cells), b(cells);
      host.ReadLogOdds(a.data());
      ocl.ReadLogOdds(b.data());
      EXPECT_EQ(a, b) << where << " map after " << stage;
    };
    std::vector<LogOdds> map(cells);
    for (auto& m : map) m = LogOdds(int(rng() % 601) - 400);
    host.WriteLogOdds(map.data());
    ocl.WriteLogOdds(map.data());
    for (int scan = 0; scan < 4; ++scan) {
      // As the estimator calls them: shift, rasterize, fuse. On odd scans the three run as one
      // kernel; on even ones the update mask is read in between, so each runs on its own.
      const int dx = int(rng() % 7) - 3, dy = int(rng() % 7) - 3;
      host.Shift(dx, dy);
      ocl.Shift(dx, dy);
      if (scan % 2 == 0) same_map("shift");
      const auto ring = StarPolygon(rng, width, height);
      std::vector<std::int32_t> occupied;
      for (int k = 0; k < 30; ++k) occupied.push_back(std::int32_t(rng() % cells));
      RasterJob job;
      job.vertices = ring.data();
      job.vertex_count = int(ring.size() / 2);
      job.occupied = occupied.data();
      job.occupied_count = int(occupied.size());
      job.row_begin = 0;
      job.row_end = height;
      job.row_begin = scan % 2 ? int(rng() % height) : 0;
      job.row_end = scan % 2 ? job.row_begin + 1 + int(rng() % height) : height;
      job.clear_outline = scan >= 2;  // sensor_model.free_on_outline off on the last two
      host.Rasterize(job);
      ocl.Rasterize(job);
      std::vector<std::uint8_t> ua(cells), ub(cells);
      if (scan % 2 == 0) {  // the row pass on its own, then the fusion
        host.ReadUpdateMask(ua.data());
        ocl.ReadUpdateMask(ub.data());
        EXPECT_EQ(ua, ub) << where << " update mask";
      }
      host.Fuse(job.row_begin, job.row_end);
      ocl.Fuse(job.row_begin, job.row_end);
      host.ReadUpdateMask(ua.data());
      ocl.ReadUpdateMask(ub.data());
      EXPECT_EQ(ua, ub) << where << " update mask after fuse";
      same_map("fuse");
      host.Classify();
      ocl.Classify();
      std::vector<std::uint8_t> fa(cells), fb(cells);
      host.ReadFree(fa.data());
      ocl.ReadFree(fb.data());
      EXPECT_EQ(fa, fb) << where << " free mask";
      std::vector<CellIndex> ea, eb;
      ea.reserve(BorderLabelCount(height, width));
      eb.reserve(BorderLabelCount(height, width));
      const CellIndex vehicle{int(rng() % height), int(rng() % width)};
      host.InSight(vehicle, &ea);
      ocl.InSight(vehicle, &eb);
      EXPECT_EQ(ea, eb) << where << " C_Edge";
      std::vector<std::int32_t> ends;
      for (int k = 0; k < 200; ++k) {
        ends.push_back(int(rng() % (width + 20)) - 10);
        ends.push_back(int(rng() % (height + 20)) - 10);
      }
      RayJob rays;
      rays.origin_col = vehicle.col;
      rays.origin_row = vehicle.row;
      rays.ends = ends.data();
      rays.ray_count = 200;
      rays.row_begin = 0;
      rays.row_end = height;
      host.CastRays(rays);
      ocl.CastRays(rays);
      std::vector<std::int32_t> da(cells), db(cells);
      host.ReadRayDelta(da.data());
      ocl.ReadRayDelta(db.data());
      EXPECT_EQ(da, db) << where << " ray deltas";
      host.FuseRays(0, height);
      ocl.FuseRays(0, height);
      same_map("rays");
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, WorkShapeTest,
                         ::testing::Values(OpenClBackend::WorkShape::kRowPerItem,
                                           OpenClBackend::WorkShape::kVectorPerItem),
                         [](const ::testing::TestParamInfo<OpenClBackend::WorkShape>& info) {
                           return info.param == OpenClBackend::WorkShape::kRowPerItem
                                      ? "row_per_item"
                                      : "vector_per_item";
                         });

}  // namespace
}  // namespace freespace
