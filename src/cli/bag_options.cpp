// ROS 1 bags and the layer cut on the command line (bag_options.hpp); the ROS side is
// freespace_ros (ros/).
#include "bag_options.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/layer_cut.hpp"
#include "engine_options.hpp"
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

// Throws InputError naming the option when the layer cut is not valid.
void CheckLayerCut(const BagCliOptions& o) {
  const std::string why = io::CheckElevationCut(o.layer_elevations_deg, o.layer_tolerance_deg);
  if (why.empty()) return;
  if (why.rfind("tolerance", 0) == 0) throw InputError("--kitti-layer-tolerance: " + why);
  std::ostringstream given;
  for (std::size_t i = 0; i < o.layer_elevations_deg.size(); ++i) {
    given << (i ? "," : "") << o.layer_elevations_deg[i];
  }
  throw InputError("--kitti-layers " + given.str() + ": " + why);
}

// Throws InputError when an option of `options` was given: it does not apply to `what`.
void RefuseGiven(const std::vector<const CLI::Option*>& options, const std::string& what) {
  for (const CLI::Option* option : options) {
    if (option->count() > 0) {
      throw InputError(option->get_name() + " does not apply to " + what);
    }
  }
}

// The layer cut's options are read only where the scans are cut by elevation.
void RefuseUncut(const LogReader& reader, const BagCliOptions& bag, const std::string& what) {
  if (!reader.cuts_by_elevation()) {
    RefuseGiven(bag.cut_only, what + ", only to KITTI frames and point clouds cut by elevation");
  }
}

}  // namespace

void AddBagOptions(CLI::App* command, BagCliOptions* o) {
  CLI::Option* scan_topic = command->add_option(
      "--scan-topic", o->scan_topic,
      "ROS bag: the sensor_msgs/LaserScan or sensor_msgs/PointCloud2 topic (when\n"
      "the bag has several); several LaserScan topics with commas: a rig");
  CLI::Option* odom_topic = command->add_option(
      "--odom-topic", o->odom_topic,
      "ROS bag: the nav_msgs/Odometry topic (when several; none: poses from /tf)");
  CLI::Option* base_frame =
      command->add_option("--base-frame", o->base_frame,
                          "ROS bag: the vehicle frame (default: Odometry's child_frame_id, or\n"
                          "base_link on /tf)");
  CLI::Option* out_bag = command->add_option(
      "--out-bag", o->out_bag,
      "Write a ROS bag: per scan /freespace/map (nav_msgs/OccupancyGrid) and\n"
      "/freespace/polygon (geometry_msgs/PolygonStamped), stamped like the scan");
  command->add_option("--out-bag-frame", o->out_bag_frame, "frame_id of the --out-bag messages")
      ->needs(out_bag)
      ->capture_default_str();
  CLI::Option* layers =
      command
          ->add_option(
              "--kitti-layers", o->layer_elevations_deg,
              "KITTI frames and point clouds without ring field: the elevation (deg) of\n"
              "each cut layer, increasing, comma-separated (--kitti-layers=-1.2,-0.4,0.4,1.2)")
          ->delimiter(',')
          ->capture_default_str();
  CLI::Option* tolerance =
      command
          ->add_option("--kitti-layer-tolerance", o->layer_tolerance_deg,
                       "A point joins the nearest cut layer within this many degrees, (0, 10]")
          ->capture_default_str();
  CLI::Option* cloud_layers =
      command
          ->add_option(
              "--cloud-layers", o->cloud_layers,
              "ROS bag PointCloud2 scans: layers by the ring field (ring r is layer r), by\n"
              "elevation (--kitti-layers), or auto (ring when the clouds have one)")
          ->check(CLI::IsMember({"auto", "ring", "elevation"}))
          ->capture_default_str();
  o->bag_only = {scan_topic, odom_topic, base_frame, cloud_layers};
  o->cut_only = {layers, tolerance};
}

std::unique_ptr<LogReader> OpenInput(const std::string& path, const LogOptions& log_options,
                                     const BagCliOptions& bag) {
  CheckLayerCut(bag);
  RequireLogPath(path);
  if (!LooksLikeBag(path)) {
    LogOptions options = log_options;
    options.kitti_layer_elevations_deg = bag.layer_elevations_deg;
    options.kitti_layer_tolerance_deg = bag.layer_tolerance_deg;
    std::unique_ptr<LogReader> reader = OpenLog(path, options);
    const std::string what = std::string("a ") + ToString(reader->format()) + " log (" + path + ")";
    RefuseGiven(bag.bag_only, what + ", only to a ROS bag");
    RefuseUncut(*reader, bag, what);
    return reader;
  }
#ifdef FREESPACE_WITH_ROS
  ros_bag::BagOptions options;
  options.scan_topic = bag.scan_topic;
  options.odom_topic = bag.odom_topic;
  options.base_frame = bag.base_frame;
  options.layer_elevations_deg = bag.layer_elevations_deg;
  options.layer_tolerance_deg = bag.layer_tolerance_deg;
  options.cloud_layers = bag.cloud_layers == "ring"        ? ros_bag::CloudLayers::kRing
                         : bag.cloud_layers == "elevation" ? ros_bag::CloudLayers::kElevation
                                                           : ros_bag::CloudLayers::kAuto;
  std::unique_ptr<LogReader> reader = ros_bag::OpenRosBag(path, options);
  RefuseUncut(*reader, bag,
              "a ROS bag (" + path +
                  ") of LaserScan messages or of point clouds layered by their ring field");
  return reader;
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
  // Its folder is made as --out's and --save-map's are.
  const std::filesystem::path parent = std::filesystem::path(options.out_bag).parent_path();
  if (!parent.empty()) MakeDirectories(parent.string());
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
