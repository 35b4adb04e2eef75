// A ROS 1 bag as a scan log (freespace_ros/bag.hpp): the bag's topics sorted by message type,
// the scan and pose topics chosen (automatically when there is one of a kind), every pose
// sample and static transform read once, then one Scan per LaserScan message with its pose
// interpolated at the scan's stamp.
#include <geometry_msgs/Transform.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <vector>

#include "freespace/errors.hpp"
#include "freespace_ros/bag.hpp"
#include "ros_frames.hpp"

namespace freespace::ros_bag {
namespace {

constexpr const char* kLaserScan = "sensor_msgs/LaserScan";
constexpr const char* kOdometry = "nav_msgs/Odometry";

// The topic of `type` to read: `requested` (which must have that type), else the only one.
std::string ChooseTopic(const std::map<std::string, std::string>& types, const std::string& type,
                        const std::string& requested, const std::string& option,
                        const std::string& path) {
  std::string listing, of_type;
  std::vector<std::string> candidates;
  for (const auto& [topic, t] : types) {
    listing += (listing.empty() ? "" : ", ") + topic + " (" + t + ")";
    if (t == type) candidates.push_back(topic);
  }
  if (!requested.empty()) {
    const auto it = types.find(requested);
    if (it == types.end())
      throw InputError(path + ": no topic " + requested + "; it has " + listing);
    if (it->second != type) {
      throw InputError(path + ": topic " + requested + " holds " + it->second + ", not " + type);
    }
    return requested;
  }
  if (candidates.size() == 1) return candidates[0];
  if (candidates.empty()) return "";
  for (const std::string& c : candidates) of_type += (of_type.empty() ? "" : ", ") + c;
  throw InputError(path + ": several " + type + " topics (" + of_type + "): choose one with " +
                   option);
}

class BagReader : public LogReader {
 public:
  BagReader(const std::string& path, const BagOptions& options)
      : LogReader(path, LogFormat::kAuto), options_(options) {
    Load();
  }

  bool Next(Scan* scan) override {
    while (next_ < scans_.size()) {
      current_ = next_++;
      const sensor_msgs::LaserScan& s = *scans_[current_];
      const double t = s.header.stamp.toSec();
      std::string why;
      if (!poses_.At(t, options_.max_pose_gap_s, &scan->pose, &why)) {
        Report(current_ + 1, "scan at t = " + std::to_string(t) + " s skipped: " + why);
        continue;
      }
      scan->timestamp_s = t;
      FillPoints(s, scan);
      return true;
    }
    return false;
  }

  // The 1-based index of the last scan message among the scan topic's messages.
  std::size_t line() const override { return current_ + 1; }
  double progress() const override {
    return scans_.empty() ? 1.0 : double(next_) / double(scans_.size());
  }

 private:
  void Load();
  void ReadMessages(rosbag::Bag& bag, const std::string& scan_topic, const std::string& odom_topic);
  void TakeSensor();
  void TakeMount(const std::string& base_frame);

  // REP 117: +inf (or above range_max) is no echo; NaN, -inf and short ranges go on as they
  // are, for the estimator to count as invalid.
  static void FillPoints(const sensor_msgs::LaserScan& s, Scan* scan) {
    scan->points.resize(s.ranges.size());
    for (std::size_t i = 0; i < s.ranges.size(); ++i) {
      ScanPoint& p = scan->points[i];
      const float r = s.ranges[i];
      p.layer = 0;
      p.angle_rad = float(double(s.angle_min) + double(i) * double(s.angle_increment));
      p.echo = !(r > s.range_max);  // +inf and too far are no echo; NaN compares false
      p.range_m = p.echo ? r : s.range_max;
    }
  }

  BagOptions options_;
  std::vector<sensor_msgs::LaserScan::ConstPtr> scans_;
  PoseTrack poses_;
  FrameTree statics_;
  std::string pose_source_;
  std::size_t next_ = 0, current_ = 0;
};

void BagReader::Load() {
  rosbag::Bag bag;
  try {
    bag.open(path_, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw InputError(path_ + ": not a readable ROS bag: " + e.what());
  }
  std::map<std::string, std::string> types;
  for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections()) {
    types[c->topic] = c->datatype;
  }
  const std::string scan_topic =
      ChooseTopic(types, kLaserScan, options_.scan_topic, "--scan-topic", path_);
  if (scan_topic.empty()) throw InputError(path_ + ": no " + std::string(kLaserScan) + " topic");
  const std::string odom_topic =
      ChooseTopic(types, kOdometry, options_.odom_topic, "--odom-topic", path_);
  ReadMessages(bag, scan_topic, odom_topic);
  if (scans_.empty()) throw InputError(path_ + ": topic " + scan_topic + " has no message");
  if (odom_topic.empty()) {
    // No odometry topic: the vehicle's pose from /tf.
    const std::string base = poses_.TakeFromTf(options_.base_frame, path_);
    pose_source_ = "/tf " + base;
    TakeMount(base);
  } else {
    if (poses_.empty()) throw InputError(path_ + ": topic " + odom_topic + " has no message");
    pose_source_ = odom_topic;
    TakeMount(options_.base_frame.empty() ? poses_.child_frame() : options_.base_frame);
  }
  poses_.Sort();
  TakeSensor();
}

void BagReader::ReadMessages(rosbag::Bag& bag, const std::string& scan_topic,
                             const std::string& odom_topic) {
  std::vector<std::string> topics = {scan_topic, "/tf", "/tf_static"};
  if (!odom_topic.empty()) topics.push_back(odom_topic);
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topics))) {
    const std::string& topic = m.getTopic();
    if (topic == scan_topic) {
      scans_.push_back(m.instantiate<sensor_msgs::LaserScan>());
    } else if (topic == odom_topic) {
      const nav_msgs::Odometry::ConstPtr o = m.instantiate<nav_msgs::Odometry>();
      poses_.AddOdometry(o->header.stamp.toSec(), o->child_frame_id,
                         RigidFromPose(o->pose.pose.position.x, o->pose.pose.position.y,
                                       o->pose.pose.orientation));
    } else if (m.getDataType() == "tf2_msgs/TFMessage") {
      const tf2_msgs::TFMessage::ConstPtr tf = m.instantiate<tf2_msgs::TFMessage>();
      for (const geometry_msgs::TransformStamped& t : tf->transforms) {
        const Rigid2 r = RigidFromPose(t.transform.translation.x, t.transform.translation.y,
                                       t.transform.rotation);
        if (topic == "/tf_static") {
          statics_.Add(t.header.frame_id, t.child_frame_id, r);
        } else {
          poses_.AddTf(t.header.stamp.toSec(), t.header.frame_id, t.child_frame_id, r);
        }
      }
    }
  }
  // Scans stay in the bag's (recording) order: a stamp before the previous scan's is the
  // estimator's to report (clock jitter or a jump back), not the reader's to hide by sorting.
}

// The sensor geometry from the first scan: one layer, its aperture, step and range limits.
void BagReader::TakeSensor() {
  const sensor_msgs::LaserScan& s = *scans_.front();
  if (s.ranges.empty() || !(s.angle_increment > 0)) {
    throw InputError(path_ + ": the first scan has no beams or angle_increment <= 0");
  }
  constexpr double kDeg = 180.0 / M_PI;
  sensor_.layers = 1;
  sensor_.min_angle_deg = double(s.angle_min) * kDeg;
  sensor_.angular_resolution_deg = double(s.angle_increment) * kDeg;
  sensor_.max_angle_deg =
      (double(s.angle_min) + double(s.ranges.size() - 1) * double(s.angle_increment)) * kDeg;
  sensor_.min_range_m = std::max(0.0, double(s.range_min));
  sensor_.max_range_m = double(s.range_max);
}

// The mount: the static transform from the base frame to the scan's frame.
void BagReader::TakeMount(const std::string& base_frame) {
  const std::string& laser = scans_.front()->header.frame_id;
  Rigid2 mount;
  if (laser == base_frame || statics_.Find(base_frame, laser, &mount)) {
    sensor_.mount_x_m = mount.x;
    sensor_.mount_y_m = mount.y;
    sensor_.mount_yaw_deg = mount.yaw * 180.0 / M_PI;
  } else {
    Report(0, "no /tf_static transform from " + base_frame + " to the scan frame " + laser +
                  ": the sensor mount is the config's (zero without a sensor section)");
  }
}

}  // namespace

bool IsRosBag(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[13] = {};
  in.read(head, 12);
  return in.gcount() == 12 && std::string(head, 12) == "#ROSBAG V2.0";
}

std::unique_ptr<LogReader> OpenRosBag(const std::string& path, const BagOptions& options) {
  return std::make_unique<BagReader>(path, options);
}

}  // namespace freespace::ros_bag
