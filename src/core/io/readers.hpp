// The concrete log readers, created by OpenLog().
#pragma once

#include <memory>
#include <string>

#include "freespace/io.hpp"

namespace freespace::io {

std::unique_ptr<LogReader> OpenCarmen(const std::string& path, const LogOptions& options);
std::unique_ptr<LogReader> OpenKitti(const std::string& path, const LogOptions& options);
// A KITTI odometry sequence folder (kitti_sequence.cpp).
std::unique_ptr<LogReader> OpenKittiSequence(const std::string& dir, const LogOptions& options);
std::unique_ptr<LogReader> OpenNative(const std::string& path, const LogOptions& options);

}  // namespace freespace::io
