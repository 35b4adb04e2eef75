// ROS 1 bags in and out (the optional freespace_ros target, built when rosbag_storage and the
// message headers are installed). In: sensor_msgs/LaserScan scans with the pose from
// nav_msgs/Odometry or /tf, the sensor mount from /tf_static. Out: per scan the local map as a
// nav_msgs/OccupancyGrid and the free-space polygon as a geometry_msgs/PolygonStamped.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "freespace/io.hpp"
#include "freespace/result.hpp"

namespace freespace::ros_bag {

// How a PointCloud2 scan's points are split into layers: kAuto by the ring field when the
// clouds have an integer one, else by elevation; kRing requires the ring field.
enum class CloudLayers { kAuto, kRing, kElevation };

struct BagOptions {
  // Empty: the one sensor_msgs/LaserScan or sensor_msgs/PointCloud2 topic of the bag. Several
  // LaserScan topics separated by commas: a rig, sensor k the k-th topic (its name), each
  // mounted where /tf_static puts its frame.
  std::string scan_topic;
  std::string odom_topic;  // empty: the one nav_msgs/Odometry topic, or /tf without one
  // The vehicle frame whose pose the scans need: empty takes Odometry's child_frame_id, or
  // with /tf "base_link" (or the one child frame /tf moves, when there is one).
  std::string base_frame;
  // A scan farther than this from the nearest pose sample (before the first, after the last,
  // or in a gap between two samples) is skipped and reported.
  double max_pose_gap_s = 0.5;
  // PointCloud2 scans: layers by ring or elevation, and the elevation cut (as
  // LogOptions::kitti_layer_elevations_deg / kitti_layer_tolerance_deg). kRing or kElevation
  // for a bag of LaserScan scans is an InputError; LogReader::cuts_by_elevation() says whether
  // the cut is read.
  CloudLayers cloud_layers = CloudLayers::kAuto;
  std::vector<double> layer_elevations_deg = {-1.2, -0.4, 0.4, 1.2};
  double layer_tolerance_deg = 0.4;
};

// True when the file starts with the ROS 1 bag header "#ROSBAG V2.0".
bool IsRosBag(const std::string& path);

// Opens a bag as a scan log: one full scan per LaserScan or PointCloud2 message, its pose
// interpolated in time between the two nearest pose samples (x, y linearly, yaw along the
// shorter way). LaserScan beams follow REP 117: +inf or a range above range_max is a beam
// without echo; NaN, -inf and ranges below range_min are passed on as invalid ranges (the
// estimator counts them). A PointCloud2 (fields x, y, z float32 or float64, an optional integer
// ring; either byte order) is cut like a KITTI frame into a ScaLa-like scan: per layer and
// azimuth bin the nearest point is the echo, an empty bin a beam without echo; NaN points are
// left out (reported once), a cloud without x, y, z is reported and skipped. The sensor mount
// comes from /tf_static (base frame to the scan's frame_id); without one the reader's sensor()
// has a zero mount and says so in an issue. Messages are read one at a time. Throws InputError
// when the bag cannot be read, the topics are ambiguous or missing (the message lists the
// bag's topics), the first cloud cannot be cut or the layer cut is not valid.
std::unique_ptr<LogReader> OpenRosBag(const std::string& path, const BagOptions& options = {});

// Writes per processed scan a nav_msgs/OccupancyGrid of the local map on `topic_prefix`/map and
// a geometry_msgs/PolygonStamped (the closed counter-clockwise free-space polygon) on
// `topic_prefix`/polygon, both stamped with the scan's time, in `frame_id`.
class BagResultWriter {
 public:
  // Throws OutputError when the bag cannot be created; Write() and Close() when a write fails
  // (InputError from Write() for a scan before time 0, which a ROS time cannot hold). A bag that
  // failed to close is left undestroyed with its file open (rosbag's destructor would throw
  // again and end the program): a process that goes on after such an error holds it.
  BagResultWriter(const std::string& path, const std::string& frame_id,
                  const std::string& topic_prefix = "/freespace");
  ~BagResultWriter();
  BagResultWriter(const BagResultWriter&) = delete;
  BagResultWriter& operator=(const BagResultWriter&) = delete;

  void Write(const Result& result, const MapView& map);
  void Close();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace freespace::ros_bag
