// ROS bags through the estimator: --out-bag's messages read back (an OccupancyGrid with the
// map's values and a PolygonStamped with the polygon per scan, stamped like the scan); a CARMEN
// log written as a bag (LaserScan + Odometry + /tf_static) gives the CARMEN log's polygons; and
// `freespace run --log X.bag --out-bag Y.bag` end to end.
#include <geometry_msgs/PolygonStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <sys/resource.h>
#include <tf2_msgs/TFMessage.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

#include "freespace_ros/bag.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

// A bag's record time: at least ros::TIME_MIN (1 ns), which rosbag requires.
ros::Time BagTime(double t) { return std::max(ros::Time(t), ros::TIME_MIN); }

std::string TempPath(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / ("freespace_rosio_" + name)).string();
}

// Writes the scans of a one-layer log as a bag: a LaserScan per scan (no-echo beams +inf), an
// Odometry at the scan's stamp with the log's pose, and an identity base_link -> laser mount.
// Messages are recorded in the log's order, as a recorder receives them: the record time never
// goes back even where a stamp does (intel-corrected.log has 4 such stamps).
void WriteBag(const std::string& path, const std::vector<Scan>& scans, const SensorConfig& s) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  tf2_msgs::TFMessage mount;
  geometry_msgs::TransformStamped tf;
  tf.header.frame_id = "base_link";
  tf.child_frame_id = "laser";
  tf.transform.rotation.w = 1.0;
  mount.transforms.push_back(tf);
  bag.write("/tf_static", BagTime(scans.front().timestamp_s), mount);
  sensor_msgs::LaserScan ls;
  ls.header.frame_id = "laser";
  ls.angle_min = float(s.min_angle_deg * M_PI / 180);
  ls.angle_increment = float(s.angular_resolution_deg * M_PI / 180);
  ls.angle_max = float(s.max_angle_deg * M_PI / 180);
  ls.range_min = float(s.min_range_m);
  ls.range_max = float(s.max_range_m);
  nav_msgs::Odometry odom;
  odom.header.frame_id = "odom";
  odom.child_frame_id = "base_link";
  ros::Time record = ros::TIME_MIN;
  for (const Scan& scan : scans) {
    const ros::Time stamp(scan.timestamp_s);
    record = std::max(record + ros::Duration(0, 1), BagTime(scan.timestamp_s));
    ls.header.stamp = odom.header.stamp = stamp;
    ls.ranges.resize(scan.points.size());
    for (std::size_t i = 0; i < scan.points.size(); ++i) {
      const ScanPoint& p = scan.points[i];
      ls.ranges[i] = p.echo ? p.range_m : std::numeric_limits<float>::infinity();
    }
    odom.pose.pose.position.x = scan.pose.x;
    odom.pose.pose.position.y = scan.pose.y;
    odom.pose.pose.orientation.z = std::sin(scan.pose.yaw / 2);
    odom.pose.pose.orientation.w = std::cos(scan.pose.yaw / 2);
    bag.write("/odom", record, odom);
    bag.write("/scan", record, ls);
  }
}

// Polygons of `scans` through one estimator.
std::vector<std::vector<Vec2>> Polygons(const std::vector<Scan>& scans, const Config& config) {
  Estimator estimator(config);
  std::vector<std::vector<Vec2>> out;
  for (const Scan& scan : scans) out.push_back(estimator.Process(scan).polygon);
  return out;
}

// How two runs' polygons compare: identical ones, and the largest vertex distance among those
// with the same vertex count.
struct PolygonDiff {
  std::size_t identical = 0, same_count = 0;
  double worst_m = 0.0;
};
PolygonDiff Compare(const std::vector<std::vector<Vec2>>& a,
                    const std::vector<std::vector<Vec2>>& b) {
  PolygonDiff d;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (a[i] == b[i]) ++d.identical;
    if (a[i].size() != b[i].size()) continue;
    ++d.same_count;
    for (std::size_t k = 0; k < a[i].size(); ++k) {
      d.worst_m = std::max(d.worst_m, (a[i][k] - b[i][k]).norm());
    }
  }
  return d;
}

// The bag carries the log's float32 ranges exactly, its poses (float64) and stamps (ns), but
// beam angles only as LaserScan's float32 angle_min + i * angle_increment: with those angles
// the log gives exactly the bag's polygons; with the log's own angles, nearly all.
TEST(RosBagIo, CarmenLogAndItsBagGiveTheSamePolygons) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  auto carmen = OpenLog(path);
  const SensorConfig sensor = carmen->sensor();
  std::vector<Scan> scans;
  for (Scan s; carmen->Next(&s);) scans.push_back(s);
  const std::string bag = TempPath("intel.bag");
  WriteBag(bag, scans, sensor);

  Config config = test::LoadProjectConfig("indoor.yaml");
  config.sensor = sensor;
  auto from_bag = ros_bag::OpenRosBag(bag);
  EXPECT_EQ(from_bag->sensor().layers, 1);
  EXPECT_NEAR(from_bag->sensor().min_angle_deg, sensor.min_angle_deg, 1e-5);
  std::vector<Scan> bag_scans;
  for (Scan s; from_bag->Next(&s);) bag_scans.push_back(s);
  ASSERT_EQ(bag_scans.size(), scans.size());
  EXPECT_TRUE(from_bag->TakeIssues().empty());
  // What the bag carries differently: stamps (ns), yaw (through a quaternion, wrapped), angles.
  double dt = 0, dxy = 0, dyaw = 0, dangle = 0, drange = 0;
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const Scan &a = scans[k], &b = bag_scans[k];
    dt = std::max(dt, std::abs(a.timestamp_s - b.timestamp_s));
    dxy = std::max(dxy, std::hypot(a.pose.x - b.pose.x, a.pose.y - b.pose.y));
    dyaw = std::max(dyaw, std::abs(std::remainder(a.pose.yaw - b.pose.yaw, 2 * M_PI)));
    for (std::size_t i = 0; i < a.points.size(); ++i) {
      dangle = std::max(dangle, double(std::abs(a.points[i].angle_rad - b.points[i].angle_rad)));
      if (a.points[i].echo) {
        drange = std::max(drange, double(std::abs(a.points[i].range_m - b.points[i].range_m)));
      }
    }
  }
  std::cout << "bag vs log: stamps " << dt << " s, positions " << dxy << " m, yaw " << dyaw
            << " rad, beam angles " << dangle << " rad, ranges " << drange << " m apart at most\n";
  EXPECT_LT(dt, 1e-6);
  EXPECT_LT(dxy, 1e-9);
  EXPECT_LT(dyaw, 1e-12);
  EXPECT_LT(dangle, 1e-6);
  EXPECT_EQ(drange, 0.0) << "float32 ranges travel unchanged";

  // The log with LaserScan's float32 beam angles.
  const float angle_min = float(sensor.min_angle_deg * M_PI / 180);
  const float increment = float(sensor.angular_resolution_deg * M_PI / 180);
  std::vector<Scan> rounded = scans;
  for (Scan& s : rounded) {
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      s.points[i].angle_rad = float(double(angle_min) + double(i) * double(increment));
    }
  }
  const auto from_log = Polygons(scans, config);
  const auto from_rounded = Polygons(rounded, config);
  const auto from_bag_polygons = Polygons(bag_scans, config);
  const PolygonDiff exact = Compare(from_rounded, from_bag_polygons);
  const PolygonDiff raw = Compare(from_log, from_bag_polygons);
  std::cout << "intel-corrected.log as a bag: " << raw.identical << " of " << scans.size()
            << " polygons identical to the log's (" << raw.same_count
            << " with the same vertex count, the largest vertex distance among those "
            << raw.worst_m << " m); with LaserScan's float32 angles " << exact.identical << " of "
            << scans.size() << "\n";
  EXPECT_EQ(exact.identical, scans.size());
  EXPECT_GE(raw.identical, scans.size() * 98 / 100);
}

TEST(RosBagIo, OutBagHoldsAGridAndAPolygonPerScan) {
  const std::string in = TempPath("drive.bag");
  // The drive: a one-layer scanner moving down a corridor 8 m wide.
  SensorConfig sensor;
  sensor.layers = 1;
  sensor.min_angle_deg = -90;
  sensor.max_angle_deg = 90;
  sensor.angular_resolution_deg = 1;
  sensor.max_range_m = 30;
  std::vector<Scan> scans;
  for (int k = 0; k < 12; ++k) {
    std::vector<double> angles;
    std::vector<double> ranges;
    for (int a = -90; a <= 90; ++a) {
      const double rad = a * M_PI / 180;
      angles.push_back(a);
      ranges.push_back(std::abs(std::sin(rad)) > 0.05 ? 4.0 / std::abs(std::sin(rad)) : 31.0);
    }
    scans.push_back(test::MakeScan(0.1 * k, {0.3 * k, 0.0, 0.0}, angles, ranges));
  }
  WriteBag(in, scans, sensor);
  auto reader = ros_bag::OpenRosBag(in);
  Config config = test::SmallConfig(120, 120, 0.2);
  config.sensor = reader->sensor();
  Estimator estimator(config);
  const std::string out = TempPath("out.bag");
  std::vector<Result> results;
  std::vector<std::vector<std::int8_t>> grids;
  {
    ros_bag::BagResultWriter writer(out, "odom");
    Scan scan;
    while (reader->Next(&scan)) {
      const Result& r = estimator.Process(scan);
      writer.Write(r, estimator.map());
      results.push_back(r);
      grids.push_back(OccupancyGrid(estimator.map()));
    }
    writer.Close();
  }
  ASSERT_EQ(results.size(), 12u);
  rosbag::Bag bag(out, rosbag::bagmode::Read);
  std::size_t maps = 0, polygons = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (auto g = m.instantiate<nav_msgs::OccupancyGrid>()) {
      ASSERT_EQ(m.getTopic(), "/freespace/map");
      ASSERT_LT(maps, results.size());
      EXPECT_EQ(g->header.frame_id, "odom");
      EXPECT_NEAR(g->header.stamp.toSec(), results[maps].timestamp_s, 1e-9);
      EXPECT_EQ(g->info.width, 120u);
      EXPECT_NEAR(g->info.origin.position.x, results[maps].origin.x(), 1e-12);
      EXPECT_EQ(g->data, grids[maps]);
      ++maps;
    } else if (auto p = m.instantiate<geometry_msgs::PolygonStamped>()) {
      ASSERT_EQ(m.getTopic(), "/freespace/polygon");
      ASSERT_LT(polygons, results.size());
      const Result& r = results[polygons];
      EXPECT_NEAR(p->header.stamp.toSec(), r.timestamp_s, 1e-9);
      ASSERT_EQ(p->polygon.points.size(), r.polygon.size());
      for (std::size_t k = 0; k < r.polygon.size(); ++k) {
        EXPECT_NEAR(p->polygon.points[k].x, r.polygon[k].x(), 1e-5);
        EXPECT_NEAR(p->polygon.points[k].y, r.polygon[k].y(), 1e-5);
      }
      ++polygons;
    }
  }
  EXPECT_EQ(maps, 12u);
  EXPECT_EQ(polygons, 12u);
  EXPECT_GT(results.back().polygon.size(), 3u);

  // The command line: the same bag in, a bag out (into folders it makes), one polygons.jsonl
  // line per scan.
  const std::string dir = TempPath("cli");
  std::filesystem::remove_all(dir);
  const std::string command = std::string(FREESPACE_CLI_PATH) + " run --quiet --log " + in +
                              " --out " + dir + " --out-bag " + dir + "/bags/new/out.bag 2>" + dir +
                              ".err";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream lines(dir + "/polygons.jsonl");
  int n = 0;
  for (std::string line; std::getline(lines, line);) ++n;
  EXPECT_EQ(n, 12);
  rosbag::Bag cli_bag(dir + "/bags/new/out.bag", rosbag::bagmode::Read);
  EXPECT_EQ(rosbag::View(cli_bag).size(), 24u);
}

// A bag that cannot be written whole: the failure is an OutputError naming the file, and
// destroying the writer afterwards (whose bag then fails to close again, which rosbag's own
// destructor would throw from) does not end the program. On /dev/full the bag's header fails;
// under a file size limit of 256 kB (RLIMIT_FSIZE, SIGXFSZ ignored) a write or the close does.
TEST(RosBagIo, AFailedWriteIsAnOutputErrorAndTheWriterStillGoes) {
  Config config = test::SmallConfig(300, 300, 0.2);
  Estimator estimator(config);
  const Result& r = estimator.Process(test::MakeScan(0.1, {0, 0, 0}, {0.0, 1.0}, {5.0, 5.0}));
  const auto write = [&](const std::string& path) {
    std::string message;
    std::unique_ptr<ros_bag::BagResultWriter> writer;
    try {
      writer = std::make_unique<ros_bag::BagResultWriter>(path, "odom");
      for (int k = 0; k < 20; ++k) writer->Write(r, estimator.map());  // 90 kB each
      writer->Close();
    } catch (const OutputError& e) {
      message = e.what();
    }
    writer.reset();
    return message;
  };
  if (access("/dev/full", W_OK) == 0) {
    const std::string message = write("/dev/full");
    EXPECT_NE(message.find("/dev/full: cannot create the bag"), std::string::npos) << message;
  }
  rlimit before;
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &before), 0);
  rlimit limit = before;
  limit.rlim_cur = 256 * 1024;
  const auto handler = std::signal(SIGXFSZ, SIG_IGN);
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limit), 0);
  const std::string path = TempPath("limited.bag");
  const std::string message = write(path);
  setrlimit(RLIMIT_FSIZE, &before);
  std::signal(SIGXFSZ, handler);
  EXPECT_NE(message.find(path + ": write failed"), std::string::npos) << message;
}

}  // namespace
}  // namespace freespace
