// A ROS 1 bag as a scan log (freespace_ros/bag.hpp): the bag's topics sorted by message type,
// the scan and pose topics chosen (automatically when there is one of a kind), every pose
// sample and static transform read once, then one Scan per LaserScan or PointCloud2 message
// (read one at a time) with its pose interpolated at the scan's stamp.
#include <geometry_msgs/Transform.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <vector>

#include "cloud_cut.hpp"
#include "freespace/errors.hpp"
#include "freespace_ros/bag.hpp"
#include "ros_frames.hpp"

namespace freespace::ros_bag {
namespace {

constexpr const char* kLaserScan = "sensor_msgs/LaserScan";
constexpr const char* kPointCloud2 = "sensor_msgs/PointCloud2";
constexpr const char* kOdometry = "nav_msgs/Odometry";

// The scan topic (of one of `types_wanted`) or pose topic to read: `requested` (which must have
// such a type), else the only one.
std::string ChooseTopic(const std::map<std::string, std::string>& types,
                        const std::vector<std::string>& types_wanted, const std::string& requested,
                        const std::string& option, const std::string& path) {
  std::string listing, of_type, wanted;
  std::vector<std::string> candidates;
  const auto is_wanted = [&](const std::string& t) {
    return std::find(types_wanted.begin(), types_wanted.end(), t) != types_wanted.end();
  };
  for (const std::string& w : types_wanted) wanted += (wanted.empty() ? "" : " or ") + w;
  for (const auto& [topic, t] : types) {
    listing += (listing.empty() ? "" : ", ") + topic + " (" + t + ")";
    if (is_wanted(t)) candidates.push_back(topic);
  }
  if (!requested.empty()) {
    const auto it = types.find(requested);
    if (it == types.end())
      throw InputError(path + ": no topic " + requested + "; it has " + listing);
    if (!is_wanted(it->second)) {
      throw InputError(path + ": topic " + requested + " holds " + it->second + ", not " + wanted);
    }
    return requested;
  }
  if (candidates.size() == 1) return candidates[0];
  if (candidates.empty()) return "";
  for (const std::string& c : candidates) of_type += (of_type.empty() ? "" : ", ") + c;
  const std::string rig =
      option == "--scan-topic" ? " (or several, comma-separated, for a rig of scanners)" : "";
  throw InputError(path + ": several " + wanted + " topics (" + of_type + "): choose one with " +
                   option + rig);
}

// The comma-separated topics of `text` (empty: none).
std::vector<std::string> SplitTopics(const std::string& text) {
  std::vector<std::string> topics;
  std::size_t start = 0;
  while (start <= text.size() && !text.empty()) {
    const std::size_t comma = text.find(',', start);
    const std::size_t end = comma == std::string::npos ? text.size() : comma;
    if (end > start) topics.push_back(text.substr(start, end - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return topics;
}

// The time from a LaserScan's first beam to its last (sensor.sweep_s), from time_increment;
// 0 where that is not given, not finite or past a second.
double LaserSweep(const sensor_msgs::LaserScan& s) {
  const double sweep =
      double(s.time_increment) * double(s.ranges.empty() ? 0 : s.ranges.size() - 1);
  return std::isfinite(sweep) && std::abs(sweep) <= 1.0 ? sweep : 0.0;
}

class BagReader : public LogReader {
 public:
  BagReader(const std::string& path, const BagOptions& options)
      : LogReader(path, LogFormat::kAuto), options_(options) {
    Load();
  }

  bool Next(Scan* scan) override;

  // The 1-based index of the last scan message among the scan topic's messages.
  std::size_t line() const override { return current_; }
  double progress() const override { return total_ == 0 ? 1.0 : double(current_) / double(total_); }

 private:
  void Load();
  void ReadPoses(const std::string& odom_topic);
  void LoadRig(const std::vector<std::string>& topics,
               const std::map<std::string, std::string>& types, const std::string& base);
  void TakeSensor(const rosbag::MessageInstance& first);
  SensorConfig LaserSensor(const rosbag::MessageInstance& first) const;
  void TakeCloudSensor(const sensor_msgs::PointCloud2& first);
  void TakeMount(const std::string& base_frame, const std::string& laser, SensorConfig* sensor);
  bool FillCloud(const sensor_msgs::PointCloud2& cloud, Scan* scan);

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
  rosbag::Bag bag_;
  // The scan messages, read one at a time in the bag's (recording) order: a stamp before the
  // previous scan's is the estimator's to report (clock jitter or a jump back), not the
  // reader's to hide by sorting.
  std::unique_ptr<rosbag::View> scans_;
  rosbag::View::iterator it_;
  bool clouds_ = false;   // PointCloud2 scans, else LaserScan
  bool by_ring_ = false;  // clouds cut by their ring field
  bool said_not_finite_ = false;
  std::unique_ptr<io::LayerCut> cut_;
  std::vector<std::string> rig_topics_;  // a rig's scan topics, sensor k the k-th; else empty
  PoseTrack poses_;
  FrameTree statics_;
  std::size_t current_ = 0, total_ = 0;
};

bool BagReader::Next(Scan* scan) {
  while (it_ != scans_->end()) {
    ++current_;
    try {
      const rosbag::MessageInstance m = *it_;
      ++it_;
      const double t = m.getTime().toSec();
      sensor_msgs::LaserScan::ConstPtr laser;
      sensor_msgs::PointCloud2::ConstPtr cloud;
      if (clouds_) {
        cloud = m.instantiate<sensor_msgs::PointCloud2>();
      } else {
        laser = m.instantiate<sensor_msgs::LaserScan>();
      }
      if (!cloud && !laser) {
        Report(current_, "message at t = " + std::to_string(t) + " s skipped: not readable");
        continue;
      }
      // A LaserScan is stamped at its first beam (REP 117 / sensor_msgs): the scan's time is the
      // middle of its sweep, time_increment apart from beam to beam.
      const double stamp = clouds_ ? cloud->header.stamp.toSec()
                                   : laser->header.stamp.toSec() + 0.5 * LaserSweep(*laser);
      std::string why;
      if (!poses_.At(stamp, options_.max_pose_gap_s, &scan->pose, &why)) {
        Report(current_, "scan at t = " + std::to_string(stamp) + " s skipped: " + why);
        continue;
      }
      scan->timestamp_s = stamp;
      scan->sensor = 0;
      for (std::size_t k = 0; k < rig_topics_.size(); ++k) {
        if (rig_topics_[k] == m.getTopic()) scan->sensor = int(k);
      }
      if (clouds_) {
        if (!FillCloud(*cloud, scan)) continue;
      } else {
        FillPoints(*laser, scan);
      }
      return true;
    } catch (const std::exception& e) {
      // A damaged message (rosbag throws on bytes it cannot deserialize): reported, skipped.
      Report(current_, std::string("scan message skipped: ") + e.what());
    }
  }
  return false;
}

// One PointCloud2 through the layer cut; false (reported) when its layout cannot be read.
bool BagReader::FillCloud(const sensor_msgs::PointCloud2& cloud, Scan* scan) {
  CloudLayout layout;
  const std::string why = ReadLayout(cloud, &layout);
  const std::string at = "point cloud at t = " + std::to_string(scan->timestamp_s) + " s";
  if (!why.empty()) {
    Report(current_, at + " skipped: " + why);
    return false;
  }
  if (by_ring_ && layout.ring.offset < 0) {
    Report(current_, at + " skipped: no integer ring field (the first cloud had one)");
    return false;
  }
  CloudCounts counts;
  CutCloud(cloud, layout, by_ring_, cut_.get(), &scan->points, &counts);
  if (counts.ring_outside > 0) {
    Report(current_, at + ": " + std::to_string(counts.ring_outside) + " of " +
                         std::to_string(counts.points) + " points on a ring >= " +
                         std::to_string(cut_->layers()) + " (the first cloud's rings) left out");
  }
  if (counts.not_finite > 0 && !said_not_finite_) {
    said_not_finite_ = true;
    Report(current_, at + ": " + std::to_string(counts.not_finite) + " of " +
                         std::to_string(counts.points) +
                         " points are NaN or infinite (an organized cloud's beams without "
                         "return): left out, here and in later clouds without further notice");
  }
  return true;
}

void BagReader::Load() {
  try {
    bag_.open(path_, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    // The head says ROS bag (IsRosBag): most often one cut short, whose index is missing.
    throw InputError(path_ + ": not a readable ROS bag: " + e.what() +
                     " (a bag cut short or not closed by its writer has no index; `rosbag "
                     "reindex` repairs it)");
  }
  std::map<std::string, std::string> types;
  for (const rosbag::ConnectionInfo* c : rosbag::View(bag_).getConnections()) {
    types[c->topic] = c->datatype;
  }
  const std::vector<std::string> topics = SplitTopics(options_.scan_topic);
  const std::string scan_topic = topics.size() > 1
                                     ? topics.front()
                                     : ChooseTopic(types, {kLaserScan, kPointCloud2},
                                                   options_.scan_topic, "--scan-topic", path_);
  if (scan_topic.empty()) {
    throw InputError(path_ + ": no " + std::string(kLaserScan) + " or " + kPointCloud2 + " topic");
  }
  clouds_ = types[scan_topic] == kPointCloud2;
  if (!clouds_ && options_.cloud_layers != CloudLayers::kAuto) {
    throw InputError(path_ + ": layers by " +
                     (options_.cloud_layers == CloudLayers::kRing ? "ring" : "elevation") +
                     " asked for, but the scans are " + std::string(kLaserScan) +
                     " messages (one layer each), not point clouds");
  }
  const std::string odom_topic =
      ChooseTopic(types, {kOdometry}, options_.odom_topic, "--odom-topic", path_);
  ReadPoses(odom_topic);
  scans_ = std::make_unique<rosbag::View>(
      bag_, rosbag::TopicQuery(topics.size() > 1 ? topics : std::vector<std::string>{scan_topic}));
  total_ = scans_->size();
  if (total_ == 0) throw InputError(path_ + ": topic " + scan_topic + " has no message");
  const rosbag::MessageInstance first = *scans_->begin();
  std::string base;
  if (odom_topic.empty()) {
    // No odometry topic: the vehicle's pose from /tf.
    base = poses_.TakeFromTf(options_.base_frame, path_);
  } else {
    if (poses_.empty()) throw InputError(path_ + ": topic " + odom_topic + " has no message");
    base = options_.base_frame.empty() ? poses_.child_frame() : options_.base_frame;
  }
  poses_.Sort();
  it_ = scans_->begin();
  if (topics.size() > 1) {
    LoadRig(topics, types, base);
    return;
  }
  TakeSensor(first);
  TakeMount(base,
            clouds_ ? first.instantiate<sensor_msgs::PointCloud2>()->header.frame_id
                    : first.instantiate<sensor_msgs::LaserScan>()->header.frame_id,
            &sensor_);
}

// Several LaserScan topics: sensor k from the first message of topic k, mounted at its frame.
void BagReader::LoadRig(const std::vector<std::string>& topics,
                        const std::map<std::string, std::string>& types, const std::string& base) {
  if (topics.size() > std::size_t(kMaxSensors)) {
    throw InputError(path_ + ": --scan-topic lists " + std::to_string(topics.size()) +
                     " topics; a rig has at most " + std::to_string(kMaxSensors));
  }
  for (const std::string& topic : topics) {
    const auto it = types.find(topic);
    if (it == types.end()) throw InputError(path_ + ": no topic " + topic);
    if (it->second != kLaserScan) {
      throw InputError(path_ + ": topic " + topic + " holds " + it->second + "; a rig of several " +
                       "scan topics takes " + kLaserScan + " only");
    }
    if (std::count(topics.begin(), topics.end(), topic) > 1) {
      throw InputError(path_ + ": topic " + topic + " is listed twice in --scan-topic");
    }
    rosbag::View view(bag_, rosbag::TopicQuery(topic));
    if (view.size() == 0) throw InputError(path_ + ": topic " + topic + " has no message");
    const rosbag::MessageInstance first = *view.begin();
    SensorConfig sensor = LaserSensor(first);
    sensor.name = topic;
    TakeMount(base, first.instantiate<sensor_msgs::LaserScan>()->header.frame_id, &sensor);
    rig_.push_back(sensor);
  }
  rig_topics_ = topics;
  sensor_ = rig_.front();
}

void BagReader::ReadPoses(const std::string& odom_topic) {
  std::vector<std::string> topics = {"/tf", "/tf_static"};
  if (!odom_topic.empty()) topics.push_back(odom_topic);
  for (const rosbag::MessageInstance& m : rosbag::View(bag_, rosbag::TopicQuery(topics))) {
    const std::string& topic = m.getTopic();
    if (topic == odom_topic) {
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
}

// The sensor geometry from the first scan. LaserScan: one layer, its aperture, step and range
// limits. PointCloud2: TakeCloudSensor.
void BagReader::TakeSensor(const rosbag::MessageInstance& first) {
  if (clouds_) {
    const sensor_msgs::PointCloud2::ConstPtr cloud = first.instantiate<sensor_msgs::PointCloud2>();
    if (!cloud) throw InputError(path_ + ": the first point cloud cannot be read");
    TakeCloudSensor(*cloud);
    return;
  }
  sensor_ = LaserSensor(first);
}

// A LaserScan topic's sensor from its first message: one layer, its aperture, step and range
// limits.
SensorConfig BagReader::LaserSensor(const rosbag::MessageInstance& first) const {
  const sensor_msgs::LaserScan::ConstPtr scan = first.instantiate<sensor_msgs::LaserScan>();
  if (!scan)
    throw InputError(path_ + ": the first scan of " + first.getTopic() + " cannot be read");
  const sensor_msgs::LaserScan& s = *scan;
  if (s.ranges.empty() || !(s.angle_increment > 0)) {
    throw InputError(path_ + ": the first scan of " + first.getTopic() +
                     " has no beams or angle_increment <= 0");
  }
  constexpr double kDeg = 180.0 / M_PI;
  SensorConfig sensor;
  sensor.layers = 1;
  sensor.min_angle_deg = double(s.angle_min) * kDeg;
  sensor.angular_resolution_deg = double(s.angle_increment) * kDeg;
  sensor.max_angle_deg =
      (double(s.angle_min) + double(s.ranges.size() - 1) * double(s.angle_increment)) * kDeg;
  sensor.min_range_m = std::max(0.0, double(s.range_min));
  sensor.max_range_m = double(s.range_max);
  sensor.sweep_s = LaserSweep(s);
  return sensor;
}

// A point cloud's scan: the ScaLa aperture and resolution; layers by the ring field (ring r is
// layer r, as many as the first cloud's largest ring + 1) or by the configured elevations.
void BagReader::TakeCloudSensor(const sensor_msgs::PointCloud2& first) {
  const std::string cut_why =
      io::CheckElevationCut(options_.layer_elevations_deg, options_.layer_tolerance_deg);
  if (!cut_why.empty()) throw InputError(path_ + ": layer cut: " + cut_why);
  CloudLayout layout;
  const std::string why = ReadLayout(first, &layout);
  if (!why.empty()) throw InputError(path_ + ": the first point cloud: " + why);
  if (layout.ring_not_integer) {
    Note(0, "the point clouds' ring field is not an integer: layers by elevation");
  }
  const bool has_ring = layout.ring.offset >= 0;
  if (options_.cloud_layers == CloudLayers::kRing && !has_ring) {
    throw InputError(path_ +
                     ": layers by ring asked for, but the point clouds have no integer "
                     "ring field");
  }
  by_ring_ = has_ring && options_.cloud_layers != CloudLayers::kElevation;
  cuts_by_elevation_ = !by_ring_;
  sensor_ = SensorConfig{};
  sensor_.layers = int(options_.layer_elevations_deg.size());
  if (by_ring_) {
    const int rings = RingLayers(first, layout);
    if (rings < 1) throw InputError(path_ + ": the first point cloud has no finite point");
    if (rings > 255) {
      Report(0, "the first point cloud has rings up to " + std::to_string(rings - 1) +
                    ": rings 255 and above are left out (255 layers at most)");
    }
    sensor_.layers = std::min(rings, 255);
  }
  cut_ = std::make_unique<io::LayerCut>(sensor_, options_.layer_elevations_deg,
                                        options_.layer_tolerance_deg);
}

// The mount: the static transform from the base frame to the scan's frame.
void BagReader::TakeMount(const std::string& base_frame, const std::string& laser,
                          SensorConfig* sensor) {
  Rigid2 mount;
  if (laser == base_frame || statics_.Find(base_frame, laser, &mount)) {
    sensor->mount_x_m = mount.x;
    sensor->mount_y_m = mount.y;
    sensor->mount_yaw_deg = mount.yaw * 180.0 / M_PI;
  } else {
    Note(0, "no /tf_static transform from " + base_frame + " to the scan frame " + laser +
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
