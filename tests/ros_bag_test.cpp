// ROS 1 bags in and out (freespace_ros), on bags the tests write with the same libraries:
// LaserScan + Odometry + /tf_static read back as scans with interpolated poses, the mount and
// REP 117's no-echo beams; poses from /tf; topics chosen or asked for; scans without a pose
// reported; --out-bag's OccupancyGrid and PolygonStamped per scan; a CARMEN log and the bag
// made from it give the same polygons; `freespace run --log X.bag` end to end.
#include <geometry_msgs/PolygonStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
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

constexpr float kInf = std::numeric_limits<float>::infinity();

geometry_msgs::Quaternion Yaw(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(yaw / 2);
  q.w = std::cos(yaw / 2);
  return q;
}

std::string TempBag(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / ("freespace_ros_" + name)).string();
}

sensor_msgs::LaserScan MakeLaserScan(double t, const std::vector<float>& ranges) {
  sensor_msgs::LaserScan s;
  s.header.stamp = ros::Time(t);
  s.header.frame_id = "laser";
  s.angle_min = float(-M_PI / 2);
  s.angle_increment = float(M_PI / 180);
  s.angle_max = s.angle_min + s.angle_increment * float(ranges.size() - 1);
  s.range_min = 0.1f;
  s.range_max = 30.0f;
  s.ranges = ranges;
  return s;
}

nav_msgs::Odometry MakeOdometry(double t, double x, double y, double yaw) {
  nav_msgs::Odometry o;
  o.header.stamp = ros::Time(t);
  o.header.frame_id = "odom";
  o.child_frame_id = "base_link";
  o.pose.pose.position.x = x;
  o.pose.pose.position.y = y;
  o.pose.pose.orientation = Yaw(yaw);
  return o;
}

geometry_msgs::TransformStamped MakeTransform(double t, const std::string& parent,
                                              const std::string& child, double x, double y,
                                              double yaw) {
  geometry_msgs::TransformStamped tf;
  tf.header.stamp = ros::Time(t);
  tf.header.frame_id = parent;
  tf.child_frame_id = child;
  tf.transform.translation.x = x;
  tf.transform.translation.y = y;
  tf.transform.rotation = Yaw(yaw);
  return tf;
}

void WriteStaticMount(rosbag::Bag* bag, double x, double y, double yaw) {
  tf2_msgs::TFMessage tf;
  tf.transforms.push_back(MakeTransform(0.0, "base_link", "laser", x, y, yaw));
  bag->write("/tf_static", BagTime(0.001), tf);
}

// Odometry at 10 Hz for 1 s along +x at 2 m/s turning at 0.1 rad/s; scans at 0.05, 0.15, ...
std::string WriteDrive(const std::string& name, bool with_odometry) {
  const std::string path = TempBag(name);
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  WriteStaticMount(&bag, 1.5, 0.2, 0.1);
  for (int i = 0; i <= 10; ++i) {
    const double t = 0.1 * i;
    if (with_odometry) {
      bag.write("/odom", BagTime(t), MakeOdometry(t, 2 * t, 0.0, 0.1 * t));
    } else {
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(MakeTransform(t, "odom", "base_link", 2 * t, 0.0, 0.1 * t));
      bag.write("/tf", BagTime(t), tf);
    }
  }
  for (int i = 0; i < 10; ++i) {
    const double t = 0.05 + 0.1 * i;
    std::vector<float> ranges(181, 10.0f);
    ranges[0] = kInf;                                     // REP 117: no echo
    ranges[1] = 31.0f;                                    // above range_max: no echo
    ranges[2] = std::numeric_limits<float>::quiet_NaN();  // invalid
    ranges[3] = -kInf;                                    // too close
    bag.write("/scan", BagTime(t), MakeLaserScan(t, ranges));
  }
  bag.close();
  return path;
}

void ExpectDriveScans(LogReader& reader) {
  const SensorConfig& s = reader.sensor();
  EXPECT_EQ(s.layers, 1);
  EXPECT_NEAR(s.min_angle_deg, -90.0, 1e-4);
  EXPECT_NEAR(s.max_angle_deg, 90.0, 1e-4);
  EXPECT_NEAR(s.angular_resolution_deg, 1.0, 1e-5);
  EXPECT_NEAR(s.max_range_m, 30.0, 1e-6);
  EXPECT_NEAR(s.mount_x_m, 1.5, 1e-12);
  EXPECT_NEAR(s.mount_y_m, 0.2, 1e-12);
  EXPECT_NEAR(s.mount_yaw_deg, 0.1 * 180 / M_PI, 1e-9);
  Scan scan;
  int n = 0;
  while (reader.Next(&scan)) {
    const double t = 0.05 + 0.1 * n;
    EXPECT_NEAR(scan.timestamp_s, t, 1e-9);
    EXPECT_NEAR(scan.pose.x, 2 * t, 1e-9) << "interpolated between the 10 Hz samples";
    EXPECT_NEAR(scan.pose.y, 0.0, 1e-12);
    EXPECT_NEAR(scan.pose.yaw, 0.1 * t, 1e-9);
    ASSERT_EQ(scan.points.size(), 181u);
    EXPECT_FALSE(scan.points[0].echo);
    EXPECT_FALSE(scan.points[1].echo);
    EXPECT_TRUE(scan.points[2].echo && std::isnan(scan.points[2].range_m));
    EXPECT_TRUE(scan.points[3].echo && scan.points[3].range_m == -kInf);
    EXPECT_TRUE(scan.points[90].echo);
    EXPECT_FLOAT_EQ(scan.points[90].range_m, 10.0f);
    EXPECT_NEAR(scan.points[90].angle_rad, 0.0, 1e-6);
    ++n;
  }
  EXPECT_EQ(n, 10);
  EXPECT_TRUE(reader.TakeIssues().empty());
}

TEST(RosBag, LaserScanWithOdometryAndStaticMount) {
  const std::string path = WriteDrive("odom.bag", true);
  EXPECT_TRUE(ros_bag::IsRosBag(path));
  auto reader = ros_bag::OpenRosBag(path);
  EXPECT_FALSE(reader->cuts_by_elevation()) << "LaserScan beams are one layer";
  ExpectDriveScans(*reader);
  // Layers by ring or elevation are for point clouds: asked of LaserScan scans, an error.
  for (ros_bag::CloudLayers layers :
       {ros_bag::CloudLayers::kRing, ros_bag::CloudLayers::kElevation}) {
    ros_bag::BagOptions options;
    options.cloud_layers = layers;
    EXPECT_THROW(ros_bag::OpenRosBag(path, options), InputError);
  }
  // The estimator takes the bag's sensor geometry and counts the REP 117 beams.
  Config config = test::SmallConfig(100, 100, 0.2);
  config.sensor = ros_bag::OpenRosBag(path)->sensor();
  Estimator estimator(config);
  auto again = ros_bag::OpenRosBag(path);
  Scan scan;
  ASSERT_TRUE(again->Next(&scan));
  const Result& r = estimator.Process(scan);
  EXPECT_EQ(r.stats.no_echo, 2);
  EXPECT_EQ(r.stats.invalid_range, 2);
}

// A LaserScan with time_increment: the sensor sweeps (sensor.sweep_s from the first message),
// and each scan is stamped at the middle of its sweep, header.stamp being its first beam's time,
// with the pose interpolated there.
TEST(RosBag, LaserScanTimeIncrementIsTheSweep) {
  const std::string path = TempBag("sweep.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    WriteStaticMount(&bag, 1.5, 0.2, 0.1);
    for (int i = 0; i <= 10; ++i) {
      const double t = 0.1 * i;
      bag.write("/odom", BagTime(t), MakeOdometry(t, 2 * t, 0.0, 0.1 * t));
    }
    for (int i = 0; i < 5; ++i) {
      sensor_msgs::LaserScan scan = MakeLaserScan(0.05 + 0.1 * i, std::vector<float>(181, 10.0f));
      scan.time_increment = 1e-4f;  // 18 ms from the first beam to the last
      bag.write("/scan", BagTime(0.05 + 0.1 * i), scan);
    }
  }
  auto reader = ros_bag::OpenRosBag(path);
  EXPECT_NEAR(reader->sensor().sweep_s, 180 * 1e-4, 1e-9);
  Scan scan;
  int n = 0;
  while (reader->Next(&scan)) {
    const double t = 0.05 + 0.1 * n + 0.5 * 180 * 1e-4;
    EXPECT_NEAR(scan.timestamp_s, t, 1e-6);
    EXPECT_NEAR(scan.pose.x, 2 * t, 1e-6);
    ++n;
  }
  EXPECT_EQ(n, 5);
  // Without time_increment (WriteDrive's scans) nothing sweeps: ExpectDriveScans checks the
  // stamps, and the sensor says 0.
  EXPECT_EQ(ros_bag::OpenRosBag(WriteDrive("nosweep.bag", true))->sensor().sweep_s, 0.0);
}

TEST(RosBag, PosesFromTfWithoutOdometry) {
  auto reader = ros_bag::OpenRosBag(WriteDrive("tf.bag", false));
  ExpectDriveScans(*reader);
}

TEST(RosBag, TopicsAreChosenOrAskedFor) {
  const std::string path = TempBag("two_scans.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.write("/odom", BagTime(1.0), MakeOdometry(1.0, 0, 0, 0));
    bag.write("/front", BagTime(1.0), MakeLaserScan(1.0, std::vector<float>(10, 5.0f)));
    bag.write("/rear", BagTime(1.0), MakeLaserScan(1.0, std::vector<float>(20, 5.0f)));
  }
  try {
    ros_bag::OpenRosBag(path);
    ADD_FAILURE() << "two LaserScan topics need a choice";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--scan-topic"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/front, /rear"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("comma-separated, for a rig"), std::string::npos)
        << e.what();
  }
  ros_bag::BagOptions options;
  options.scan_topic = "/rear";
  auto reader = ros_bag::OpenRosBag(path, options);
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  EXPECT_EQ(scan.points.size(), 20u);
  // The mount is missing from /tf_static: said, not silently assumed.
  const auto issues = reader->TakeIssues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_NE(issues[0].message.find("no /tf_static transform"), std::string::npos);
  EXPECT_TRUE(issues[0].note);  // nothing was left out: no malformed line, no skip
  options.scan_topic = "/odom";
  EXPECT_THROW(ros_bag::OpenRosBag(path, options), InputError);
  options.scan_topic = "/nothing";
  EXPECT_THROW(ros_bag::OpenRosBag(path, options), InputError);
  std::ofstream(TempBag("not.bag")) << "hello\n";
  EXPECT_FALSE(ros_bag::IsRosBag(TempBag("not.bag")));
  EXPECT_THROW(ros_bag::OpenRosBag(TempBag("not.bag")), InputError);
}

// Two LaserScan topics listed in --scan-topic are a rig: each topic a sensor mounted where
// /tf_static puts its frame, each message a scan of its sensor, in the bag's order.
TEST(RosBag, SeveralLaserScanTopicsAreARig) {
  const std::string path = TempBag("rig.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(MakeTransform(0.0, "base_link", "front_laser", 3.7, 0.0, 0.0));
    tf.transforms.push_back(MakeTransform(0.0, "base_link", "rear_laser", -1.0, 0.0, M_PI));
    bag.write("/tf_static", BagTime(0.001), tf);
    for (int i = 0; i <= 10; ++i)
      bag.write("/odom", BagTime(0.1 * i), MakeOdometry(0.1 * i, 0.2 * i, 0, 0));
    for (int i = 0; i < 5; ++i) {
      sensor_msgs::LaserScan front = MakeLaserScan(0.05 + 0.2 * i, std::vector<float>(181, 8.0f));
      front.header.frame_id = "front_laser";
      sensor_msgs::LaserScan rear = MakeLaserScan(0.06 + 0.2 * i, std::vector<float>(91, 6.0f));
      rear.header.frame_id = "rear_laser";
      bag.write("/front/scan", BagTime(0.05 + 0.2 * i), front);
      bag.write("/rear/scan", BagTime(0.06 + 0.2 * i), rear);
    }
    bag.close();
  }
  ros_bag::BagOptions options;
  options.scan_topic = "/front/scan,/rear/scan";
  auto reader = ros_bag::OpenRosBag(path, options);
  const std::vector<SensorConfig> sensors = reader->sensors();
  ASSERT_EQ(sensors.size(), 2u);
  EXPECT_EQ(sensors[1].name, "/rear/scan");
  EXPECT_NEAR(sensors[0].mount_x_m, 3.7, 1e-9);
  EXPECT_NEAR(sensors[1].mount_x_m, -1.0, 1e-9);
  EXPECT_NEAR(std::abs(sensors[1].mount_yaw_deg), 180.0, 1e-6);
  EXPECT_NEAR(sensors[1].max_angle_deg, 0.0, 1e-4);  // 91 beams from -90 deg
  CycleReader cycles(*reader, 2);
  std::vector<Scan> cycle;
  int n = 0;
  while (cycles.Next(&cycle)) {
    ASSERT_EQ(cycle.size(), 2u);
    EXPECT_EQ(cycle[0].sensor, 0);
    EXPECT_EQ(cycle[1].sensor, 1);
    EXPECT_EQ(cycle[1].points.size(), 91u);
    EXPECT_NEAR(cycle[1].pose.x, 2.0 * cycle[1].timestamp_s, 1e-9);
    ++n;
  }
  EXPECT_EQ(n, 5);
  EXPECT_TRUE(reader->TakeIssues().empty());

  options.scan_topic = "/front/scan,/odom";
  EXPECT_THROW(ros_bag::OpenRosBag(path, options), InputError);
}

TEST(RosBag, ScansFarFromEveryPoseAreReportedAndSkipped) {
  const std::string path = TempBag("gap.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    WriteStaticMount(&bag, 0, 0, 0);
    bag.write("/odom", BagTime(1.0), MakeOdometry(1.0, 0, 0, 0));
    bag.write("/odom", BagTime(1.2), MakeOdometry(1.2, 1, 0, 0));
    bag.write("/scan", BagTime(1.1), MakeLaserScan(1.1, std::vector<float>(10, 5.0f)));
    bag.write("/scan", BagTime(3.0), MakeLaserScan(3.0, std::vector<float>(10, 5.0f)));
  }
  auto reader = ros_bag::OpenRosBag(path);
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  EXPECT_NEAR(scan.pose.x, 0.5, 1e-9);
  EXPECT_FALSE(reader->Next(&scan));
  const auto issues = reader->TakeIssues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].line, 2u);
  EXPECT_NE(issues[0].message.find("1.8"), std::string::npos) << issues[0].message;
}

}  // namespace
}  // namespace freespace
