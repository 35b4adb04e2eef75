// ROS 1 bags on the command line: `freespace run --log drive.bag` (with --scan-topic,
// --odom-topic, --base-frame when the bag's topics need choosing) and `--out-bag OUT.bag`. In a
// build without freespace_ros a bag is refused with a message that says how to get support.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <string>

#include "freespace/io.hpp"
#include "freespace/result.hpp"

namespace freespace::cli {

struct BagCliOptions {
  std::string scan_topic, odom_topic, base_frame;
  std::string out_bag;                  // --out-bag
  std::string out_bag_frame = "world";  // frame_id of what --out-bag writes
};
void AddBagOptions(CLI::App* command, BagCliOptions* options);

// Opens `path` as a ROS bag when it is one, else through OpenLog(). Throws InputError.
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
