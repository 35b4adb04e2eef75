// sensor_msgs/PointCloud2 scans from ROS bags the tests write: clouds with a ring field cut into
// one layer per ring (ranges, no-echo beams, the nearest point per bin, the pose interpolated
// and the mount from /tf_static); without a ring field, layers by elevation as for KITTI; NaN
// points of organized clouds, big-endian data, a cloud without z and rings beyond the first
// cloud's reported; the scan topic chosen among LaserScan and PointCloud2 topics.
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/PointField.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>

#include "freespace/errors.hpp"
#include "freespace_ros/bag.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

using sensor_msgs::PointField;

constexpr double kDeg = M_PI / 180.0;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

ros::Time BagTime(double t) { return std::max(ros::Time(t), ros::TIME_MIN); }

std::string TempBag(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / ("freespace_cloud_" + name)).string();
}

struct CloudPoint {
  float x, y, z;
  int ring;
};

struct CloudSpec {
  bool ring = true, big_endian = false, z = true;
  std::uint8_t ring_type = PointField::UINT16;
};

// Appends `size` bytes of `value` in the cloud's byte order.
template <typename T>
void Put(std::vector<std::uint8_t>* data, std::size_t at, T value, bool big_endian) {
  std::uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (big_endian) std::reverse(bytes, bytes + sizeof(T));  // this machine is little-endian
  std::memcpy(data->data() + at, bytes, sizeof(T));
}

sensor_msgs::PointCloud2 MakeCloud(double t, const std::vector<CloudPoint>& points,
                                   const CloudSpec& spec) {
  sensor_msgs::PointCloud2 c;
  c.header.stamp = ros::Time(t);
  c.header.frame_id = "velodyne";
  const auto field = [&](const char* name, std::uint32_t offset, std::uint8_t type) {
    PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = type;
    f.count = 1;
    c.fields.push_back(f);
  };
  field("x", 0, PointField::FLOAT32);
  field("y", 4, PointField::FLOAT32);
  if (spec.z) field("z", 8, PointField::FLOAT32);
  field("intensity", 12, PointField::FLOAT32);
  if (spec.ring) field("ring", 16, spec.ring_type);
  c.point_step = 20;
  c.height = 1;
  c.width = std::uint32_t(points.size());
  c.row_step = c.width * c.point_step;
  c.is_bigendian = spec.big_endian;
  c.is_dense = false;
  c.data.assign(c.row_step, 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::size_t at = i * c.point_step;
    Put(&c.data, at, points[i].x, spec.big_endian);
    Put(&c.data, at + 4, points[i].y, spec.big_endian);
    Put(&c.data, at + 8, points[i].z, spec.big_endian);
    if (spec.ring_type == PointField::UINT8) {
      Put(&c.data, at + 16, std::uint8_t(points[i].ring), spec.big_endian);
    } else if (spec.ring_type == PointField::INT32) {
      Put(&c.data, at + 16, std::int32_t(points[i].ring), spec.big_endian);
    } else {
      Put(&c.data, at + 16, std::uint16_t(points[i].ring), spec.big_endian);
    }
  }
  return c;
}

// The scene: at every bin centre of the ScaLa aperture but a gap at [10, 20) deg, ring r at
// range 10 + r m and elevation -1.2 + 0.8 r deg (the default cut's layers); a farther point
// (14 m) behind ring 0's in each bin; a point at -8 deg (ground, below the cut) at 5 m; and
// NaN points as an organized cloud has for beams without return.
std::vector<CloudPoint> Scene() {
  std::vector<CloudPoint> points;
  for (int k = 0; k <= 580; ++k) {
    const double a = (-72.5 + 0.25 * k) * kDeg;
    if (a >= 10 * kDeg && a < 20 * kDeg) {
      points.push_back({kNaN, kNaN, kNaN, 0});
      continue;
    }
    const auto at = [&](double d, double elevation_deg, int ring) {
      points.push_back({float(d * std::cos(a)), float(d * std::sin(a)),
                        float(d * std::tan(elevation_deg * kDeg)), ring});
    };
    for (int r = 0; r < 4; ++r) at(10.0 + r, -1.2 + 0.8 * r, r);
    at(14.0, -1.2, 0);
    at(5.0, -8.0, 2);
  }
  return points;
}

nav_msgs::Odometry MakeOdometry(double t, double x) {
  nav_msgs::Odometry o;
  o.header.stamp = ros::Time(t);
  o.header.frame_id = "odom";
  o.child_frame_id = "base_link";
  o.pose.pose.position.x = x;
  o.pose.pose.orientation.w = 1.0;
  return o;
}

// Odometry at 10 Hz along +x at 2 m/s, a base_link -> velodyne mount 1.2 m ahead, and a cloud
// at 0.05, 0.15, 0.25 s, each made by `cloud(i)`.
template <typename MakeCloudAt>
std::string WriteBag(const std::string& name, MakeCloudAt cloud, int clouds = 3) {
  const std::string path = TempBag(name);
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  tf2_msgs::TFMessage mount;
  geometry_msgs::TransformStamped tf;
  tf.header.frame_id = "base_link";
  tf.child_frame_id = "velodyne";
  tf.transform.translation.x = 1.2;
  tf.transform.rotation.w = 1.0;
  mount.transforms.push_back(tf);
  bag.write("/tf_static", BagTime(0.0), mount);
  for (int i = 0; i <= 4; ++i) bag.write("/odom", BagTime(0.1 * i), MakeOdometry(0.1 * i, 0.2 * i));
  for (int i = 0; i < clouds; ++i) {
    const double t = 0.05 + 0.1 * i;
    bag.write("/points", BagTime(t), cloud(i, t));
  }
  bag.close();
  return path;
}

std::string Issues(LogReader& reader) {
  std::string all;
  for (const LogIssue& issue : reader.TakeIssues()) all += issue.ToString() + "\n";
  return all;
}

// Layer l's echoes at `range(l)`, 40 no-echo beams per layer in the gap.
template <typename Range>
void ExpectLayers(const Scan& scan, int layers, Range range) {
  ASSERT_EQ(scan.points.size(), std::size_t(layers) * 581);
  std::vector<int> no_echo(layers, 0);
  for (const ScanPoint& p : scan.points) {
    ASSERT_LT(p.layer, layers);
    if (!p.echo) {
      ++no_echo[p.layer];
      EXPECT_TRUE(p.angle_rad >= 10 * kDeg - 1e-6 && p.angle_rad < 20 * kDeg);
      continue;
    }
    EXPECT_NEAR(p.range_m, range(p.layer), 1e-4) << "layer " << int(p.layer);
  }
  for (int l = 0; l < layers; ++l) EXPECT_EQ(no_echo[l], 40) << "layer " << l;
}

TEST(RosCloud, RingsAreLayersWithTheNearestPointPerBin) {
  for (std::uint8_t type : {PointField::UINT8, PointField::UINT16, PointField::INT32}) {
    CloudSpec spec;
    spec.ring_type = type;
    const std::string path =
        WriteBag("rings.bag", [&](int, double t) { return MakeCloud(t, Scene(), spec); });
    auto reader = ros_bag::OpenRosBag(path);
    EXPECT_EQ(reader->sensor().layers, 4);
    EXPECT_FALSE(reader->cuts_by_elevation()) << "layers by ring";
    EXPECT_NEAR(reader->sensor().mount_x_m, 1.2, 1e-12);
    Scan scan;
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(reader->Next(&scan));
      EXPECT_NEAR(scan.timestamp_s, 0.05 + 0.1 * i, 1e-9);
      EXPECT_NEAR(scan.pose.x, 2 * (0.05 + 0.1 * i), 1e-9);
      // Ring 2 holds the ground point at 5 m: nearer than the wall, so it is the echo.
      ExpectLayers(scan, 4, [](int l) { return l == 2 ? 5.0 : 10.0 + l; });
    }
    EXPECT_FALSE(reader->Next(&scan));
    const std::string issues = Issues(*reader);
    EXPECT_NE(issues.find("40 of 3286 points are NaN or infinite"), std::string::npos) << issues;
    EXPECT_EQ(std::count(issues.begin(), issues.end(), '\n'), 1) << "said once: " << issues;
  }
}

TEST(RosCloud, WithoutRingTheLayersComeByElevation) {
  CloudSpec spec;
  spec.ring = false;
  auto reader = ros_bag::OpenRosBag(
      WriteBag("elevation.bag", [&](int, double t) { return MakeCloud(t, Scene(), spec); }));
  EXPECT_EQ(reader->sensor().layers, 4);
  EXPECT_TRUE(reader->cuts_by_elevation());
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  // The ground point is below the cut; the farther point behind layer 0 is hidden.
  ExpectLayers(scan, 4, [](int l) { return 10.0 + l; });
  // A ring field ignored on request, and another cut.
  ros_bag::BagOptions options;
  options.cloud_layers = ros_bag::CloudLayers::kElevation;
  options.layer_elevations_deg = {-8.0, 0.4};
  auto by_elevation = ros_bag::OpenRosBag(
      WriteBag("rings2.bag", [&](int, double t) { return MakeCloud(t, Scene(), {}); }), options);
  EXPECT_EQ(by_elevation->sensor().layers, 2);
  EXPECT_TRUE(by_elevation->cuts_by_elevation());
  ASSERT_TRUE(by_elevation->Next(&scan));
  ExpectLayers(scan, 2, [](int l) { return l == 0 ? 5.0 : 12.0; });
  options.cloud_layers = ros_bag::CloudLayers::kRing;
  EXPECT_THROW(
      ros_bag::OpenRosBag(
          WriteBag("noring.bag", [&](int, double t) { return MakeCloud(t, Scene(), spec); }),
          options),
      InputError);
  options.layer_elevations_deg = {0.4, -0.4};
  options.cloud_layers = ros_bag::CloudLayers::kAuto;
  EXPECT_THROW(ros_bag::OpenRosBag(TempBag("rings2.bag"), options), InputError);
}

TEST(RosCloud, BigEndianCloudsReadAsLittleEndianOnes) {
  CloudSpec spec;
  spec.big_endian = true;
  auto reader = ros_bag::OpenRosBag(
      WriteBag("big.bag", [&](int, double t) { return MakeCloud(t, Scene(), spec); }));
  EXPECT_EQ(reader->sensor().layers, 4);
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  ExpectLayers(scan, 4, [](int l) { return l == 2 ? 5.0 : 10.0 + l; });
}

TEST(RosCloud, BadCloudsAreReportedAndSkipped) {
  // The second cloud has no z; the third has rings up to 5 where the first had 0 .. 3.
  const std::string path = WriteBag("bad.bag", [](int i, double t) {
    CloudSpec spec;
    spec.z = i != 1;
    std::vector<CloudPoint> points = Scene();
    if (i == 2) points.push_back({3.0f, 0.0f, 0.0f, 5});
    return MakeCloud(t, points, spec);
  });
  auto reader = ros_bag::OpenRosBag(path);
  Scan scan;
  int scans = 0;
  while (reader->Next(&scan)) ++scans;
  EXPECT_EQ(scans, 2);
  const std::string issues = Issues(*reader);
  EXPECT_NE(issues.find(":2: point cloud at t = 0.150000 s skipped: needs float32 fields x, y "
                        "and z; it has x (float32), y (float32), intensity (float32), ring "
                        "(uint16)"),
            std::string::npos)
      << issues;
  EXPECT_NE(issues.find(":3: point cloud at t = 0.250000 s: 1 of 3287 points on a ring >= 4"),
            std::string::npos)
      << issues;
  // A first cloud without z: nothing to take the scan's geometry from.
  CloudSpec no_z;
  no_z.z = false;
  EXPECT_THROW(ros_bag::OpenRosBag(
                   WriteBag("noz.bag", [&](int, double t) { return MakeCloud(t, Scene(), no_z); })),
               InputError);
}

TEST(RosCloud, TheScanTopicIsChosenAmongLaserScansAndClouds) {
  const std::string path = TempBag("mixed.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.write("/odom", BagTime(0.0), MakeOdometry(0.0, 0.0));
    sensor_msgs::LaserScan ls;
    ls.header.stamp = ros::Time(0.01);
    ls.angle_min = -1.0f;
    ls.angle_increment = 0.1f;
    ls.range_max = 30.0f;
    ls.ranges.assign(21, 5.0f);
    bag.write("/scan", BagTime(0.01), ls);
    bag.write("/points", BagTime(0.01), MakeCloud(0.01, Scene(), {}));
  }
  try {
    ros_bag::OpenRosBag(path);
    ADD_FAILURE() << "a LaserScan and a PointCloud2 topic need a choice";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("(/points, /scan): choose one with --scan-topic"),
              std::string::npos)
        << e.what();
  }
  ros_bag::BagOptions options;
  options.scan_topic = "/points";
  Scan scan;
  ASSERT_TRUE(ros_bag::OpenRosBag(path, options)->Next(&scan));
  EXPECT_EQ(scan.points.size(), 4u * 581);
  options.scan_topic = "/scan";
  ASSERT_TRUE(ros_bag::OpenRosBag(path, options)->Next(&scan));
  EXPECT_EQ(scan.points.size(), 21u);
}

}  // namespace
}  // namespace freespace
