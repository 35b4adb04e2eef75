// Readers and writers for scan logs: CARMEN (FLASER, ROBOTLASER1), KITTI Velodyne frames
// (one .bin file, or an odometry benchmark sequence folder with poses) cut into a ScaLa-like
// multi-layer scan, and the project's own multi-layer log format
// (docs/formats.md). Malformed input is skipped and reported with file and line, never fatal
// to the reader; the caller decides whether an issue stops the run.
#pragma once

#include <cstddef>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "freespace/config.hpp"
#include "freespace/scan.hpp"

namespace freespace {

// A part of the input that could not be used: where, and why. Or, with `note`, what the reader
// assumed for a part the input does not have (a KITTI sequence without times.txt or calib.txt):
// nothing was left out, and a note is no malformed line.
struct LogIssue {
  std::string file;
  std::size_t line = 0;  // 1-based; 0 when it concerns the whole file
  std::string message;
  bool note = false;
  std::string ToString() const;  // "file:line: message"
};

enum class LogFormat { kAuto, kCarmen, kKitti, kNative };

struct LogOptions {
  LogFormat format = LogFormat::kAuto;
  // CARMEN: ranges >= max_range - margin are "no echo". 0 = the largest range in the log
  // (the saturation value of the scanner, e.g. 81.83 in intel.clf).
  double carmen_max_range_m = 0.0;
  // KITTI: the elevation (deg) of each cut layer, 1 to 255 of them, increasing (layer 0 the
  // lowest), each in (-90, 90); a point joins the nearest layer within
  // kitti_layer_tolerance_deg, (0, 10]. Azimuth aperture and binning are the ScaLa's.
  std::vector<double> kitti_layer_elevations_deg = {-1.2, -0.4, 0.4, 1.2};
  double kitti_layer_tolerance_deg = 0.4;
};

class LogReader {
 public:
  virtual ~LogReader() = default;

  // Reads the next full scan into `scan`; returns false at the end of the input. Lines that
  // cannot be used are skipped and reported through TakeIssues().
  virtual bool Next(Scan* scan) = 0;

  // The line (record) of the input where the last scan returned by Next() started.
  virtual std::size_t line() const = 0;
  // The fraction of the input consumed, 0 .. 1.
  virtual double progress() const = 0;
  // The sensor geometry the log implies (layers, aperture, resolution, max range, mount).
  const SensorConfig& sensor() const { return sensor_; }
  // Every sensor the log holds scans of (a rig: Scan::sensor indexes this list); one for a
  // log of one sensor.
  std::vector<SensorConfig> sensors() const {
    return rig_.empty() ? std::vector<SensorConfig>{sensor_} : rig_;
  }
  // A rig's reference point and footprint when the log gives them (else the defaults).
  const RigConfig& rig() const { return rig_vehicle_; }
  const std::string& path() const { return path_; }
  // The log's format (never kAuto).
  LogFormat format() const { return format_; }
  // Whether its scans are cut into layers by elevation (LogOptions::kitti_layer_*): KITTI
  // frames, and ROS bag point clouds without a ring field or with layers by elevation asked for.
  bool cuts_by_elevation() const { return cuts_by_elevation_; }

  // Issues found since the last call.
  std::vector<LogIssue> TakeIssues();

 protected:
  LogReader(std::string path, LogFormat format) : path_(std::move(path)), format_(format) {}
  void Report(std::size_t line, std::string message);
  void Note(std::size_t line, std::string message);  // an issue with `note` set

  std::string path_;
  LogFormat format_;
  SensorConfig sensor_;
  std::vector<SensorConfig> rig_;  // several sensors, the first also in sensor_; else empty
  RigConfig rig_vehicle_;
  bool cuts_by_elevation_ = false;

 private:
  std::vector<LogIssue> issues_;
};

// Opens a log, detecting the format from the content when options.format is kAuto (a
// directory is a KITTI sequence folder: velodyne/NNNNNN.bin, poses.txt, calib.txt, times.txt).
// Throws InputError when the file cannot be opened or holds nothing recognisable, when a
// sequence folder has no frames or no poses.txt, or when the KITTI layer cut is not valid.
std::unique_ptr<LogReader> OpenLog(const std::string& path, const LogOptions& options = {});

// Throws InputError unless `path` is a regular file or a folder (symbolic links followed): a
// log is read more than once (its format, then its scans), which a pipe, a socket or a device
// such as /dev/stdin does not allow. OpenLog() checks it before anything is opened.
void RequireLogPath(const std::string& path);

const char* ToString(LogFormat format);

// Groups a log's scans into the cycles of a rig (Estimator::ProcessCycle): consecutive scans
// form one cycle until the next scan's sensor is already in it or every sensor of the rig has
// a scan in it. A log of one sensor gives one scan a cycle.
class CycleReader {
 public:
  // `reader` must outlive this; `sensors` is the rig's size (>= 1).
  CycleReader(LogReader& reader, int sensors) : reader_(reader), sensors_(sensors) {}
  // The next cycle into `cycle` (at least one scan); false at the end of the log.
  bool Next(std::vector<Scan>* cycle);
  // The log line where the cycle's first scan started, and where its last one did.
  std::size_t line() const { return line_; }
  std::size_t last_line() const { return last_line_; }
  // The line where the cycle's scan k started (k < the cycle's size; else last_line()).
  std::size_t line_of(std::size_t k) const { return k < lines_.size() ? lines_[k] : last_line_; }

 private:
  LogReader& reader_;
  int sensors_;
  Scan pending_;
  bool has_pending_ = false;
  std::size_t pending_line_ = 0;
  std::size_t line_ = 0;
  std::size_t last_line_ = 0;
  std::vector<std::size_t> lines_;  // each scan's of the cycle
};

// Writes the project's own multi-layer log format (docs/formats.md): version 1 for one sensor,
// version 2 (named sensors, a sensor index per scan) for a rig.
class NativeLogWriter {
 public:
  // Throws OutputError when the file cannot be created; Write and Close throw it when a write
  // fails.
  NativeLogWriter(const std::string& path, const SensorConfig& sensor);
  // A rig's log with its reference point and footprint; one sensor writes version 1. Throws
  // std::invalid_argument for no sensor.
  NativeLogWriter(const std::string& path, const std::vector<SensorConfig>& sensors,
                  const RigConfig& rig = {});
  // Throws std::invalid_argument for a scan of a sensor the log does not hold (Scan::sensor
  // outside 0 .. its sensors - 1).
  void Write(const Scan& scan);
  void Close();

 private:
  std::string path_;
  std::ofstream out_;
  int version_ = 1;
  int sensors_ = 1;
};

// Writes scans as CARMEN ROBOTLASER1 lines, one line per layer with the scan's timestamp,
// for tools that read CARMEN logs. No-echo beams are written at the sensor's max range.
class RobotLaserWriter {
 public:
  RobotLaserWriter(const std::string& path, const SensorConfig& sensor);
  void Write(const Scan& scan);
  void Close();

 private:
  std::string path_;
  SensorConfig sensor_;
  std::ofstream out_;
  std::vector<float> ranges_;
};

}  // namespace freespace
