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

// Why a sensor a log gives cannot be used ("sensor.max_range_m = 4: must be > ..."), or "":
// ValidateSensor's message without its "config: ", for the reader to name its line.
std::string SensorProblem(const SensorConfig& sensor);

}  // namespace freespace::io
