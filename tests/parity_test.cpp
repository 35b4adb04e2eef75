// The two backends end to end on the recorded logs: a TBB estimator and an OpenCL estimator
// process the same scans side by side, and after every scan the map (log-odds and free mask),
// C_Edge and the polygon must be identical, bit for bit. The host backend is the oracle.
// Skips with a message when the logs or an OpenCL device are absent.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "sim/rig.hpp"
#include "sim/simulator.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

// The indoor settings for the CARMEN logs (configs/indoor.yaml) with the log's sensor.
Config IndoorConfig(const SensorConfig& sensor) {
  Config c = test::LoadProjectConfig("indoor.yaml");
  c.sensor = sensor;
  return c;
}

// Creates the TBB and OpenCL estimators for `config`; on failure to create the OpenCL one, sets
// `skip` and leaves `opencl` null.
void MakePair(Config config, std::unique_ptr<Estimator>* tbb, std::unique_ptr<Estimator>* opencl,
              std::string* skip) {
  config.backend.kind = BackendKind::kTbb;
  *tbb = std::make_unique<Estimator>(config);
  if (!OpenClCompiledIn()) {
    *skip = "this build has no OpenCL backend";
    return;
  }
  config.backend.kind = BackendKind::kOpenCl;
  try {
    *opencl = std::make_unique<Estimator>(config);
  } catch (const BackendError& e) {
    *skip = std::string("no usable OpenCL device: ") + e.what();
  }
}

// Processes `scan` on both and compares everything; returns false (with a gtest failure naming
// the scan and the first difference) when they differ.
bool CompareBoth(Estimator& tbb, Estimator& opencl, const Result& a, const Result& b,
                 const std::string& what);

bool ProcessBoth(Estimator& tbb, Estimator& opencl, const Scan& scan, const std::string& what,
                 const Result** opencl_result = nullptr) {
  const Result& a = tbb.Process(scan);
  const Result& b = opencl.Process(scan);
  if (opencl_result) *opencl_result = &b;
  return CompareBoth(tbb, opencl, a, b, what);
}

// A rig's cycle on both, compared as ProcessBoth compares a scan.
bool ProcessCycleBoth(Estimator& tbb, Estimator& opencl, const std::vector<Scan>& cycle,
                      const std::string& what) {
  const Result& a = tbb.ProcessCycle(cycle);
  const Result& b = opencl.ProcessCycle(cycle);
  return CompareBoth(tbb, opencl, a, b, what);
}

bool CompareBoth(Estimator& tbb, Estimator& opencl, const Result& a, const Result& b,
                 const std::string& what) {
  const std::string where = what + " scan " + std::to_string(a.scan_index);
  const bool same_result =
      a.status == b.status && a.origin_cell_x == b.origin_cell_x &&
      a.origin_cell_y == b.origin_cell_y && a.vehicle_cell == b.vehicle_cell &&
      a.edge_cells == b.edge_cells && a.polygon_cells == b.polygon_cells &&
      a.polygon == b.polygon && a.pose_matched == b.pose_matched &&
      a.pose_correction.x == b.pose_correction.x && a.pose_correction.y == b.pose_correction.y &&
      a.pose_correction.yaw == b.pose_correction.yaw && a.sensor_pose.yaw == b.sensor_pose.yaw;
  EXPECT_TRUE(same_result) << where
                           << ": status, origin, vehicle cell, C_Edge, polygon or pose differ ("
                           << a.edge_cells.size() << " vs " << b.edge_cells.size()
                           << " edge cells, " << a.polygon.size() << " vs " << b.polygon.size()
                           << " vertices)";
  const MapView ma = tbb.map(), mb = opencl.map();
  const std::size_t cells = std::size_t(ma.width) * ma.height;
  if (std::memcmp(ma.log_odds, mb.log_odds, cells * sizeof(LogOdds)) != 0) {
    std::size_t i = 0;
    while (ma.log_odds[i] == mb.log_odds[i]) ++i;
    ADD_FAILURE() << where << ": log-odds differ first at row " << i / ma.width << " col "
                  << i % ma.width << ": tbb " << ma.log_odds[i] << ", opencl " << mb.log_odds[i];
    return false;
  }
  if (std::memcmp(ma.free, mb.free, cells) != 0) {
    std::size_t i = 0;
    while (ma.free[i] == mb.free[i]) ++i;
    ADD_FAILURE() << where << ": free mask differs first at row " << i / ma.width << " col "
                  << i % ma.width;
    return false;
  }
  return same_result;
}

void RunLog(const std::string& path, Config (*make_config)(const SensorConfig&),
            SensorModelKind model, AlignmentKind alignment = AlignmentKind::kCircle) {
  auto reader = OpenLog(path);
  Config config = make_config(reader->sensor());
  config.sensor_model.kind = model;
  config.alignment.kind = alignment;
  std::unique_ptr<Estimator> tbb, opencl;
  std::string skip;
  MakePair(config, &tbb, &opencl, &skip);
  if (!opencl) GTEST_SKIP() << skip;
  Scan scan;
  int scans = 0;
  while (reader->Next(&scan)) {
    ASSERT_TRUE(ProcessBoth(*tbb, *opencl, scan, path));
    ++scans;
  }
  EXPECT_GT(scans, 100);
}

Config Indoor(const SensorConfig& sensor) { return IndoorConfig(sensor); }

TEST(Parity, IntelLabEveryScan) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  RunLog(path, Indoor, SensorModelKind::kEnhanced);
}

Config IndoorInside(const SensorConfig& sensor) {
  Config c = IndoorConfig(sensor);
  c.polygon.shape = PolygonShape::kInside;
  return c;
}

TEST(Parity, IntelLabInsidePolygonEveryScan) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  RunLog(path, IndoorInside, SensorModelKind::kEnhanced);
}

// The margin reads the map back from the device every scan and works on the host. With the
// road setup's sensor model too: no free update where the scan's outline touches a cell.
Config IndoorInsideMargin(const SensorConfig& sensor) {
  Config c = IndoorInside(sensor);
  c.polygon.margin_cells = 1;
  c.polygon.margin_cone_deg = 45.0;
  c.sensor_model.free_on_outline = false;
  return c;
}

TEST(Parity, IntelLabInsidePolygonMarginEveryScan) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  RunLog(path, IndoorInsideMargin, SensorModelKind::kEnhanced);
}

// The face layer: worked out on the host from each scan's outline, uploaded as bitsets.
Config IndoorInsideFaces(const SensorConfig& sensor) {
  Config c = IndoorInsideMargin(sensor);
  c.polygon.margin_cone_deg = 20.0;
  c.polygon.face_tolerance_m = 0.05;
  return c;
}

TEST(Parity, IntelLabInsidePolygonFacesEveryScan) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  RunLog(path, IndoorInsideFaces, SensorModelKind::kEnhanced);
}

// How the host waits for the device's result must not change it: spinning reads the stop cells
// only once the read-back is complete, as blocking does (the default, auto, is tested above).
Config IndoorSpin(const SensorConfig& sensor) {
  Config c = IndoorConfig(sensor);
  c.backend.opencl_wait = OpenClWait::kSpin;
  return c;
}
Config IndoorBlock(const SensorConfig& sensor) {
  Config c = IndoorConfig(sensor);
  c.backend.opencl_wait = OpenClWait::kBlock;
  return c;
}

TEST(Parity, IntelLabEveryScanSpinning) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  RunLog(path, IndoorSpin, SensorModelKind::kEnhanced);
}

TEST(Parity, IntelLabEveryScanBlocking) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  RunLog(path, IndoorBlock, SensorModelKind::kEnhanced);
}

TEST(Parity, AcesBuildingEveryScan) {
  FREESPACE_REQUIRE_DATA("carmen/aces-corrected.log", path);
  RunLog(path, Indoor, SensorModelKind::kEnhanced);
}

// The raw logs: odometry poses, clock jitter, and (Intel) scans the estimator rejects.
TEST(Parity, IntelRawOdometryEveryScan) {
  FREESPACE_REQUIRE_DATA("carmen/intel.clf", path);
  RunLog(path, Indoor, SensorModelKind::kEnhanced);
}

TEST(Parity, AcesRawOdometryEveryScan) {
  FREESPACE_REQUIRE_DATA("carmen/aces.clf", path);
  RunLog(path, Indoor, SensorModelKind::kEnhanced);
}

// alignment.scan_match on the raw odometry of a real drive: the heading corrected from the
// OpenCL backend's map read back, as the TBB backend's is read in place.
Config IndoorMatched(const SensorConfig& sensor) {
  Config c = IndoorConfig(sensor);
  c.alignment.scan_match = true;
  return c;
}

TEST(Parity, IntelRawOdometryHeadingCorrected) {
  FREESPACE_REQUIRE_DATA("carmen/intel.clf", path);
  auto reader = OpenLog(path);
  std::unique_ptr<Estimator> tbb, opencl;
  std::string skip;
  MakePair(IndoorMatched(reader->sensor()), &tbb, &opencl, &skip);
  if (!opencl) GTEST_SKIP() << skip;
  Scan scan;
  int scans = 0, matched = 0;
  double turned = 0.0;
  while (scans < 3000 && reader->Next(&scan)) {
    const Result* r = nullptr;
    ASSERT_TRUE(ProcessBoth(*tbb, *opencl, scan, path, &r));
    matched += r->pose_matched;
    turned = std::max(turned, std::abs(r->pose_correction.yaw));
    ++scans;
  }
  // The correction ran and turned the heading: the comparison compared something.
  EXPECT_GT(matched, scans / 2);
  EXPECT_GT(turned, 0.001);
}

// The rotate baseline warps the map on the host between the kernel stages of either backend.
TEST(Parity, IntelLabRotateAlignmentEveryScan) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  RunLog(path, Indoor, SensorModelKind::kEnhanced, AlignmentKind::kRotate);
}

TEST(Parity, IntelLabConventionalModelEveryScan) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  RunLog(path, Indoor, SensorModelKind::kConventional);
}

// A KITTI frame has no poses: it is replayed along a curve at 15 m/s, so that the map shifts
// every scan, on the paper's 300 x 300 map and on 1500 x 1500.
void RunKitti(const std::string& path, int cells, int scans) {
  auto reader = OpenLog(path);
  Scan frame;
  ASSERT_TRUE(reader->Next(&frame));
  Config config;
  config.sensor = reader->sensor();
  config.map.width_cells = config.map.height_cells = cells;
  std::unique_ptr<Estimator> tbb, opencl;
  std::string skip;
  MakePair(config, &tbb, &opencl, &skip);
  if (!opencl) GTEST_SKIP() << skip;
  std::int64_t first_origin = 0, last_origin = 0;
  for (int k = 0; k < scans; ++k) {
    Scan scan = frame;
    scan.timestamp_s = 0.04 * k;
    scan.pose = {0.6 * k, 0.004 * k * k, 0.01 * k};
    ASSERT_TRUE(ProcessBoth(*tbb, *opencl, scan, path + " " + std::to_string(cells)));
    // The same scan again (the same timestamp: clock jitter, fused without a speed sample).
    const Result* r = nullptr;
    ASSERT_TRUE(ProcessBoth(*tbb, *opencl, scan, path + " repeated " + std::to_string(cells), &r));
    ASSERT_TRUE(r->timestamp_jitter);
    last_origin = r->origin_cell_x;
    if (k == 0) first_origin = last_origin;
  }
  // The map moved under the vehicle: the shift ran.
  EXPECT_GT(last_origin, first_origin + 20);
}

// A simulated highway drive with traffic, the road setup (configs/scala.yaml: the conservative
// polygon with its margin, the veto of this scan's echoes), both map sizes: every stage 3b mask,
// every exact ray and every veto the same on both backends.
TEST(Parity, SimulatedHighwayRoadSetup) {
  for (const int cells : {300, 1500}) {
    sim::SimulationOptions options;
    options.scenario = "highway";
    options.seed = 3;
    sim::Simulation simulation(options);
    Config config = test::LoadProjectConfig("scala.yaml");
    config.sensor = simulation.truth().scanner.EngineSensor();
    config.map.width_cells = config.map.height_cells = cells;
    std::unique_ptr<Estimator> tbb, opencl;
    std::string skip;
    MakePair(config, &tbb, &opencl, &skip);
    if (!opencl) GTEST_SKIP() << skip;
    Scan scan;
    for (int k = 0; k < (cells == 300 ? 250 : 60) && simulation.Next(&scan); ++k) {
      ASSERT_TRUE(ProcessBoth(*tbb, *opencl, scan, "highway " + std::to_string(cells)));
    }
  }
}

// The surround rig (four scanners, each scan fused from its own corner, the footprint, the
// border rays from the reference point) with the road setup, on a parking drive: the same on
// both backends after every cycle.
TEST(Parity, SimulatedSurroundRigRoadSetup) {
  sim::SimulationOptions options;
  options.scenario = "parking";
  options.seed = 5;
  options.rig = "surround";
  sim::Simulation simulation(options);
  const Config config = sim::WithRig(test::LoadProjectConfig("scala.yaml"), simulation.rig());
  std::unique_ptr<Estimator> tbb, opencl;
  std::string skip;
  MakePair(config, &tbb, &opencl, &skip);
  if (!opencl) GTEST_SKIP() << skip;
  std::vector<Scan> cycle;
  for (int k = 0; k < 200 && simulation.NextCycle(&cycle); ++k) {
    ASSERT_TRUE(ProcessCycleBoth(*tbb, *opencl, cycle, "surround parking"));
  }
}

TEST(Parity, KittiFramesOnBothMapSizes) {
  FREESPACE_REQUIRE_DATA("kitti/kitti_00_000000.bin", first);
  FREESPACE_REQUIRE_DATA("kitti/kitti_raw_2011_09_26_drive_0079_extract_0000000000.bin", second);
  for (const std::string& path : {first, second}) {
    RunKitti(path, 300, 40);
    RunKitti(path, 1500, 12);
  }
}

}  // namespace
}  // namespace freespace
