// A rig in files: the version 2 native log that carries a rig and each scan's sensor, a CARMEN
// log with a rear laser, and a surround drive written to files and scored from them.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "sim/rig.hpp"
#include "sim/simulator.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

using test::TwoAlike;
using test::Wall;

TEST(RigLog, Version2CarriesTheRigAndEachScansSensor) {
  const std::string path = ::testing::TempDir() + "/rig.fslog";
  Config c = TwoAlike();
  c.sensors[1].mount_yaw_deg = 180;
  c.rig.footprint_length_m = 4.5;
  {
    NativeLogWriter writer(path, c.sensors, c.rig);
    writer.Write(Wall(0.00, {0, 0, 0}, 0, 9.0));
    writer.Write(Wall(0.00, {0, 0, 0}, 1, 7.0));
    writer.Write(Wall(0.04, {0.5, 0, 0}, 1, 7.0));  // sensor 0 missed this cycle
    writer.Write(Wall(0.08, {1.0, 0, 0}, 0, 8.0));
    writer.Close();
  }
  {  // one more line with a sensor no SENSOR line names: reported, skipped
    std::ofstream out(path, std::ios::app);
    out << "SCAN 5 0.1 0 0 0 0\n";
  }
  auto reader = OpenLog(path);
  ASSERT_EQ(reader->sensors().size(), 2u);
  EXPECT_EQ(reader->sensors()[1].name, "b");
  EXPECT_DOUBLE_EQ(reader->sensors()[1].mount_yaw_deg, 180.0);
  EXPECT_DOUBLE_EQ(reader->rig().footprint_length_m, 4.5);
  CycleReader cycles(*reader, 2);
  std::vector<Scan> cycle;
  std::vector<std::size_t> sizes;
  while (cycles.Next(&cycle)) sizes.push_back(cycle.size());
  EXPECT_EQ(sizes, (std::vector<std::size_t>{2, 2}));  // {0, 1}, then {1, 0}
  const std::vector<LogIssue> issues = reader->TakeIssues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_NE(issues[0].message.find("sensor index '5'"), std::string::npos) << issues[0].message;

  // A second RIG line is refused (not silently the one that counts); a RIG line with one SENSOR
  // is noted as unused.
  std::ifstream whole(path);
  std::string text((std::istreambuf_iterator<char>(whole)), std::istreambuf_iterator<char>());
  const std::size_t rig_at = text.find("\nRIG ") + 1;
  const std::string rig_line = text.substr(rig_at, text.find('\n', rig_at) + 1 - rig_at);
  const std::string twice = ::testing::TempDir() + "/rig_twice.fslog";
  std::ofstream(twice) << text.substr(0, rig_at) + rig_line + text.substr(rig_at);
  try {
    OpenLog(twice);
    ADD_FAILURE() << "two RIG lines were read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a second RIG line"), std::string::npos) << e.what();
  }
  const std::size_t second_sensor = text.find("\nSENSOR b ") + 1;
  const std::string lone = ::testing::TempDir() + "/rig_lone.fslog";
  std::ofstream(lone) << text.substr(0, second_sensor) +
                             text.substr(text.find('\n', second_sensor) + 1);
  auto lone_reader = OpenLog(lone);
  EXPECT_EQ(lone_reader->sensors().size(), 1u);
  bool noted = false;
  for (const LogIssue& issue : lone_reader->TakeIssues()) {
    noted = noted ||
            (issue.note && issue.message.find("a RIG line with one SENSOR") != std::string::npos);
  }
  EXPECT_TRUE(noted);

  // Sensor names are read as written: a long one whole, one of other bytes as they are (which the
  // config then refuses), never turned into another name.
  const std::string long_name(60, 'n');
  const std::string names = ::testing::TempDir() + "/rig_names.fslog";
  std::string renamed = text;
  renamed.replace(renamed.find("SENSOR b "), 8, "SENSOR " + long_name);
  renamed.replace(renamed.find("SENSOR a "), 8, "SENSOR vorn_\xc3\xa4");
  std::ofstream(names) << renamed;
  auto named = OpenLog(names);
  ASSERT_EQ(named->sensors().size(), 2u);
  EXPECT_EQ(named->sensors()[0].name, "vorn_\xc3\xa4");
  EXPECT_EQ(named->sensors()[1].name, long_name);

  // A one-sensor log stays version 1 and gives one scan a cycle.
  const std::string one = ::testing::TempDir() + "/one.fslog";
  {
    NativeLogWriter writer(one, std::vector<SensorConfig>{c.sensors[0]});
    writer.Write(Wall(0.0, {0, 0, 0}, 0, 9.0));
    writer.Write(Wall(0.04, {0, 0, 0}, 0, 9.0));
    writer.Close();
  }
  std::ifstream in(one);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "FREESPACE_LOG 1");
  auto r1 = OpenLog(one);
  CycleReader c1(*r1, 1);
  int n = 0;
  while (c1.Next(&cycle)) n += cycle.size() == 1;
  EXPECT_EQ(n, 2);
}

}  // namespace
}  // namespace freespace

namespace freespace {
namespace {

// A FLASER-layout line: n ranges, the laser pose, the odometry pose, timestamps.
std::string FlaserLine(const char* name, int n, double range, const Pose2D& laser,
                       const Pose2D& odometry, double t) {
  std::string line = std::string(name) + " " + std::to_string(n);
  for (int i = 0; i < n; ++i) line += " " + std::to_string(range);
  char tail[200];
  std::snprintf(tail, sizeof tail, " %.6f %.6f %.6f %.6f %.6f %.6f %.6f host %.6f\n", laser.x,
                laser.y, laser.yaw, odometry.x, odometry.y, odometry.yaw, t, t);
  return line + tail;
}

// A CARMEN log with a rear laser (RLASER): a rig of two, poses the odometry's, each laser at the
// mount its first line gives.
TEST(RigLog, CarmenRearLaserMakesARig) {
  const std::string path = ::testing::TempDir() + "/rear.clf";
  {
    std::ofstream out(path);
    for (int k = 0; k < 3; ++k) {
      const Pose2D odo{1.0 * k, 2.0, M_PI / 2};
      // Front laser 0.5 m ahead of the odometry origin, rear one 0.4 m behind, turned around.
      out << FlaserLine("FLASER", 181, 5.0, {1.0 * k, 2.5, M_PI / 2}, odo, 0.1 * k);
      out << FlaserLine("RLASER", 181, 4.0, {1.0 * k, 1.6, -M_PI / 2}, odo, 0.1 * k + 0.05);
    }
  }
  auto reader = OpenLog(path);
  const std::vector<SensorConfig> sensors = reader->sensors();
  ASSERT_EQ(sensors.size(), 2u);
  EXPECT_NEAR(sensors[0].mount_x_m, 0.5, 1e-6);
  EXPECT_NEAR(sensors[0].mount_y_m, 0.0, 1e-6);
  EXPECT_NEAR(sensors[1].mount_x_m, -0.4, 1e-6);
  EXPECT_NEAR(std::abs(sensors[1].mount_yaw_deg), 180.0, 1e-4);
  CycleReader cycles(*reader, 2);
  std::vector<Scan> cycle;
  int n = 0;
  while (cycles.Next(&cycle)) {
    ASSERT_EQ(cycle.size(), 2u);
    EXPECT_EQ(cycle[0].sensor, 0);
    EXPECT_EQ(cycle[1].sensor, 1);
    EXPECT_NEAR(cycle[1].pose.y, 2.0, 1e-9);  // the odometry pose, not the laser's
    EXPECT_EQ(cycle[1].points.size(), 181u);
    ++n;
  }
  EXPECT_EQ(n, 3);
  EXPECT_TRUE(reader->TakeIssues().empty());

  // The rig runs: both lasers' walls are in the map.
  Config config;
  config.sensors = sensors;
  Estimator estimator(config);
  auto again = OpenLog(path);
  CycleReader c2(*again, 2);
  ASSERT_TRUE(c2.Next(&cycle));
  const Result& r = estimator.ProcessCycle(cycle);
  EXPECT_EQ(r.status, ScanStatus::kOk) << r.message;
  EXPECT_EQ(r.cycle_sensor_poses.size(), 2u);
}

// Without a second laser a CARMEN log is one sensor at the laser poses, as always.
TEST(RigLog, CarmenFrontLaserAloneIsOneSensor) {
  const std::string path = ::testing::TempDir() + "/front.clf";
  {
    std::ofstream out(path);
    out << FlaserLine("FLASER", 181, 5.0, {0.0, 2.5, 0.3}, {0, 2, 0.3}, 0.0);
  }
  auto reader = OpenLog(path);
  ASSERT_EQ(reader->sensors().size(), 1u);
  EXPECT_EQ(reader->sensor().mount_x_m, 0.0);
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  EXPECT_NEAR(scan.pose.y, 2.5, 1e-9);  // the laser pose
}

}  // namespace
}  // namespace freespace

namespace freespace {
namespace {

// A surround drive written to files: the log holds the four sensors and the rig's vehicle, the
// truth file names the rig, so `eval` from files scores it as the rig it is.
TEST(RigSimulation, SurroundDriveFilesCarryTheRig) {
  const std::string dir = ::testing::TempDir() + "/surround_drive";
  std::filesystem::create_directories(dir);
  sim::SimulationOptions options;
  options.scenario = "parking";
  options.duration_s = 0.2;
  options.rig = "surround";
  options.keep_truth_scans = false;
  sim::Simulation simulation(options);
  sim::SimulationWriter writer(dir, simulation.truth());
  EXPECT_FALSE(writer.writes_carmen());
  EXPECT_EQ(sim::WriteDrive(&simulation, &writer), 6u);
  writer.Close();
  const sim::Truth truth = sim::ReadTruth(writer.truth_path());
  EXPECT_EQ(truth.rig.name, "surround");
  EXPECT_EQ(truth.rig.scanners.size(), 4u);
  EXPECT_EQ(truth.scans.size(), 6u);
  auto reader = OpenLog(writer.log_path());
  EXPECT_EQ(reader->sensors().size(), 4u);
  EXPECT_DOUBLE_EQ(reader->rig().footprint_length_m, 4.7);
  CycleReader cycles(*reader, 4);
  std::vector<Scan> cycle;
  int n = 0;
  while (cycles.Next(&cycle)) n += cycle.size() == 4;
  EXPECT_EQ(n, 6);
}

}  // namespace
}  // namespace freespace
