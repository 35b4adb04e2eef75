// The inputs of `freespace run` on the command line: ROS 1 bags (`--log drive.bag` with
// --scan-topic, --odom-topic, --base-frame when the bag's topics need choosing, `--out-bag
// OUT.bag`) and the layer cut of KITTI frames and point clouds (--kitti-layers,
// --kitti-layer-tolerance, --cloud-layers). In a build without freespace_ros a bag is refused
// with a message that says how to get support.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "freespace/io.hpp"
#include "freespace/result.hpp"

namespace freespace::cli {

struct BagCliOptions {
  std::string scan_topic, odom_topic, base_frame;
  std::string out_bag;                  // --out-bag
  std::string out_bag_frame = "world";  // frame_id of what --out-bag writes
  // The elevation cut of KITTI frames and of point clouds without ring field (deg).
  std::vector<double> layer_elevations_deg = {-1.2, -0.4, 0.4, 1.2};  // --kitti-layers
  double layer_tolerance_deg = 0.4;                                   // --kitti-layer-tolerance
  std::string cloud_layers = "auto";                                  // --cloud-layers
  // The options only a ROS bag reads, and those only a layer cut reads (a KITTI frame or a
  // point cloud): given for another log, they are refused rather than left unread.
  std::vector<const CLI::Option*> bag_only, cut_only;
};
void AddBagOptions(CLI::App* command, BagCliOptions* options);

// Opens `path` as a ROS bag when it is one, else through OpenLog() (with the layer cut of
// `bag`). Throws InputError, naming the option when the layer cut is not valid.
std::unique_ptr<LogReader> OpenInput(const std::string& path, const LogOptions& log_options,
                                     const BagCliOptions& bag);

// The --out-bag writer; does nothing when --out-bag is not given.
class BagOutput {
 public:
  BagOutput();
  ~BagOutput();
  // Throws InputError when the bag cannot be created or ROS support is not built.
  void Open(const BagCliOptions& options);
  bool active() const;
  void Write(const Result& result, const MapView& map);
  void Close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace freespace::cli
