// ROS 1 bags on the command line (bag_options.hpp); the ROS side is freespace_ros (ros/).
#include "bag_options.hpp"

#include <fstream>

#include "freespace/errors.hpp"

#ifdef FREESPACE_WITH_ROS
#include "freespace_ros/bag.hpp"
#endif

namespace freespace::cli {
namespace {

constexpr const char* kNoRos =
    "this build of freespace has no ROS bag support (scripts/install-deps.sh installs "
    "librosbag-storage-dev and the message headers; then reconfigure)";

bool LooksLikeBag(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[12] = {};
  in.read(head, sizeof head);
  return in.gcount() == 12 && std::string(head, 12) == "#ROSBAG V2.0";
}

}  // namespace

void AddBagOptions(CLI::App* command, BagCliOptions* o) {
  command->add_option("--scan-topic", o->scan_topic,
                      "ROS bag: the sensor_msgs/LaserScan topic (when the bag has several)");
  command->add_option("--odom-topic", o->odom_topic,
                      "ROS bag: the nav_msgs/Odometry topic (when several; none: poses from /tf)");
  command->add_option("--base-frame", o->base_frame,
                      "ROS bag: the vehicle frame (default: Odometry's child_frame_id, or\n"
                      "base_link on /tf)");
  command->add_option("--out-bag", o->out_bag,
                      "Write a ROS bag: per scan /freespace/map (nav_msgs/OccupancyGrid) and\n"
                      "/freespace/polygon (geometry_msgs/PolygonStamped), stamped like the scan");
  command->add_option("--out-bag-frame", o->out_bag_frame, "frame_id of the --out-bag messages")
      ->capture_default_str();
}

std::unique_ptr<LogReader> OpenInput(const std::string& path, const LogOptions& log_options,
                                     const BagCliOptions& bag) {
  if (!LooksLikeBag(path)) return OpenLog(path, log_options);
#ifdef FREESPACE_WITH_ROS
  ros_bag::BagOptions options;
  options.scan_topic = bag.scan_topic;
  options.odom_topic = bag.odom_topic;
  options.base_frame = bag.base_frame;
  return ros_bag::OpenRosBag(path, options);
#else
  (void)bag;
  throw InputError(path + ": a ROS bag, but " + kNoRos);
#endif
}

struct BagOutput::Impl {
#ifdef FREESPACE_WITH_ROS
  std::unique_ptr<ros_bag::BagResultWriter> writer;
#endif
};

BagOutput::BagOutput() : impl_(std::make_unique<Impl>()) {}
BagOutput::~BagOutput() = default;

void BagOutput::Open(const BagCliOptions& options) {
  if (options.out_bag.empty()) return;
#ifdef FREESPACE_WITH_ROS
  impl_->writer =
      std::make_unique<ros_bag::BagResultWriter>(options.out_bag, options.out_bag_frame);
#else
  throw InputError("--out-bag " + options.out_bag + ": " + kNoRos);
#endif
}

bool BagOutput::active() const {
#ifdef FREESPACE_WITH_ROS
  return impl_->writer != nullptr;
#else
  return false;
#endif
}

void BagOutput::Write(const Result& result, const MapView& map) {
#ifdef FREESPACE_WITH_ROS
  if (impl_->writer) impl_->writer->Write(result, map);
#else
  (void)result;
  (void)map;
#endif
}

void BagOutput::Close() {
#ifdef FREESPACE_WITH_ROS
  if (impl_->writer) impl_->writer->Close();
#endif
}

}  // namespace freespace::cli
