// CARMEN log reader: FLASER (one single-layer scan a line) and ROBOTLASER1 (explicit
// geometry; consecutive lines with the same timestamp are the layers of one scan). Each scan
// uses the laser pose on its own line. Other messages (ODOM, PARAM, NEFF, ...) are ignored.
// A first pass over the file finds the scanner's geometry and, unless given, its saturation
// range: ranges at or above it are beams without echo (81.83 m in intel.clf).
// A log with a second laser (RLASER, the rear laser in FLASER's layout, or ROBOTLASER2) is a
// rig of two sensors: sensor 0 the front laser (FLASER / ROBOTLASER1), sensor 1 the second;
// each scan then carries the robot's odometry pose from its line, and each sensor's mount is
// its laser pose relative to that odometry pose on its first line.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "freespace/errors.hpp"
#include "readers.hpp"
#include "text.hpp"

namespace freespace::io {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr double kNoEchoMargin = 0.01;
constexpr int kMaxLayer = 254;  // a scan holds layers 0..254: SensorConfig::layers is at most 255

bool IsMessageName(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

// FLASER n covers 180 deg from -90 deg: odd n includes +90 deg (181, 361), even n stops one
// step short (180, 360).
double FlaserResolutionDeg(long n) { return n % 2 == 1 ? 180.0 / double(n - 1) : 180.0 / n; }

class CarmenReader final : public LogReader {
 public:
  CarmenReader(const std::string& path, const LogOptions& options)
      : LogReader(path, LogFormat::kCarmen), in_(path, std::ios::binary) {
    if (!in_) throw InputError(path + ": cannot open");
    if (!(options.carmen_max_range_m >= 0.0 && std::isfinite(options.carmen_max_range_m))) {
      throw InputError(path +
                       ": carmen_max_range_m = " + std::to_string(options.carmen_max_range_m) +
                       ": must be a finite range >= 0 (0: the log's largest)");
    }
    in_.seekg(0, std::ios::end);
    size_ = double(in_.tellg());
    in_.seekg(0);
    Survey(options);
    in_.clear();
    in_.seekg(0);
  }

  bool Next(Scan* scan) override {
    scan->points.clear();
    std::string line;
    std::size_t line_no = 0;
    while (NextLine(&line, &line_no)) {
      SplitFields(line, &fields_);
      if (fields_.empty()) continue;
      const int flaser = FlaserSensor(fields_[0]), robot = RobotLaserSensor(fields_[0]);
      if (flaser >= 0) {
        if (ParseFlaser(line_no, scan)) {
          scan->sensor = flaser;
          line_ = line_no;
          return true;
        }
      } else if (robot >= 0) {
        const std::string kind(fields_[0]);
        double t = 0;
        scan->points.clear();  // layer 0 starts the scan
        const std::string pose = PeekLaserPose();
        if (!ParseRobotLaser(line_no, 0, scan, &t)) continue;
        scan->sensor = robot;
        line_ = line_no;
        // Further layers: following lines of the same laser with the same timestamp.
        int layer = 1;  // lines past the 255th of a scan are reported and skipped
        std::size_t skipped = 0, skipped_from = 0;
        std::string next;
        std::size_t next_no = 0;
        while (NextLine(&next, &next_no)) {
          SplitFields(next, &fields_);
          double t_next = 0;
          Scan layer_scan;
          if (!fields_.empty() && fields_[0] == kind && PeekTimestamp(&t_next) && t_next == t) {
            if (PeekLaserPose() != pose) {
              Report(next_no, kind + ": the timestamp of the line before, another laser pose: " +
                                  "no layer of that scan; line skipped");
              continue;
            }
            if (layer > kMaxLayer) {
              if (skipped++ == 0) skipped_from = next_no;
            } else if (ParseRobotLaser(next_no, std::uint8_t(layer), &layer_scan, &t_next)) {
              scan->points.insert(scan->points.end(), layer_scan.points.begin(),
                                  layer_scan.points.end());
            }
            ++layer;
            continue;
          }
          pending_ = std::move(next);
          pending_no_ = next_no;
          has_pending_ = true;
          break;
        }
        if (skipped > 0) {
          Report(skipped_from, kind + ": " + std::to_string(skipped) + " line(s) from here on " +
                                   "share the timestamp of the " + std::to_string(kMaxLayer + 1) +
                                   " before them, more layers than a scan holds; skipped");
        }
        return true;
      } else if (!IsMessageName(fields_[0])) {
        Report(line_no, "not a CARMEN message (starts with '" + Excerpt(fields_[0]) + "')");
      }
      // Any other message is ignored.
    }
    return false;
  }

  std::size_t line() const override { return line_; }
  double progress() const override {
    if (size_ <= 0) return 1.0;
    const double at = in_.eof() ? size_ : double(const_cast<std::ifstream&>(in_).tellg());
    return std::clamp(at / size_, 0.0, 1.0);
  }

 private:
  // The sensor of a FLASER-layout message (FLASER 0, RLASER 1 in a rig), else -1.
  int FlaserSensor(std::string_view name) const {
    if (name == "FLASER") return 0;
    return name == "RLASER" && second_ == kSecondRlaser ? 1 : -1;
  }
  // The sensor of a ROBOTLASER message (ROBOTLASER1 0, ROBOTLASER2 1 in a rig), else -1.
  int RobotLaserSensor(std::string_view name) const {
    if (name == "ROBOTLASER1") return 0;
    return name == "ROBOTLASER2" && second_ == kSecondRobotLaser ? 1 : -1;
  }

  bool NextLine(std::string* line, std::size_t* line_no) {
    if (has_pending_) {
      has_pending_ = false;
      *line = std::move(pending_);
      *line_no = pending_no_;
      return true;
    }
    while (std::getline(in_, *line)) {
      ++lines_read_;
      if (IsCommentOrBlank(*line)) continue;
      *line_no = lines_read_;
      if (in_.eof()) Note(lines_read_, kNoFinalNewline);
      return true;
    }
    return false;
  }

  // What the first pass learns of one laser.
  struct Surveyed {
    bool found = false;
    SensorConfig sensor;
    int layers = 1, group = 0;
    double group_t = NAN;
    std::string group_pose;  // the laser pose's fields on the group's first line
    Pose2D laser, odometry;  // on its first line
  };

  // The laser and odometry poses of the FLASER-layout line in fields_ with n beams.
  bool FlaserPoses(long n, Pose2D* laser, Pose2D* odometry) const {
    double v[6];
    for (int i = 0; i < 6; ++i) {
      if (!ParseDouble(fields_[std::size_t(n) + 2 + i], &v[i])) return false;
    }
    *laser = {v[0], v[1], v[2]};
    *odometry = {v[3], v[4], v[5]};
    return true;
  }

  // A FLASER-layout line the second pass reads: its field count, poses, timestamp and ranges
  // (what ParseFlaser() checks). Only such a line tells the laser and the saturation range.
  void SurveyFlaser(Surveyed* laser, double* max_range) {
    long n = 0;
    double t;
    if (fields_.size() <= 2 || !ParseInt(fields_[1], &n) || n <= 1 || n > 100000 ||
        fields_.size() != std::size_t(n) + 11 || !ParseDouble(fields_[std::size_t(n) + 8], &t)) {
      return;
    }
    Pose2D laser_pose, odometry;
    if (!FlaserPoses(n, &laser_pose, &odometry)) return;
    double line_max = 0.0;
    for (long i = 0; i < n; ++i) {
      double r;
      if (!ParseDouble(fields_[2 + i], &r)) return;
      if (std::isfinite(r)) line_max = std::max(line_max, r);
    }
    *max_range = std::max(*max_range, line_max);
    if (!laser->found) {
      laser->laser = laser_pose;
      laser->odometry = odometry;
      laser->found = true;
      laser->sensor.layers = 1;
      laser->sensor.min_angle_deg = -90.0;
      laser->sensor.angular_resolution_deg = FlaserResolutionDeg(n);
      laser->sensor.max_angle_deg = -90.0 + double(n - 1) * laser->sensor.angular_resolution_deg;
    }
  }

  // The first ROBOTLASER line of a laser gives its aperture: one the engine cannot use (an angle
  // that is not a number, a resolution over 10 deg) refuses the log at that line.
  void SurveyRobotLaser(Surveyed* laser, double* max_range, std::size_t line_no) {
    long n = 0, m = 0;
    if (fields_.size() <= 9 || !ParseInt(fields_[8], &n) || n <= 1) return;
    double start, fov, res, line_max, t, v[6];
    if (!ParseDouble(fields_[2], &start) || !ParseDouble(fields_[3], &fov) ||
        !ParseDouble(fields_[4], &res) || !ParseDouble(fields_[5], &line_max) || !(res > 0)) {
      return;
    }
    if (!laser->found) {
      const bool poses = fields_.size() >= std::size_t(n) + 10 && ParseInt(fields_[9 + n], &m) &&
                         m >= 0 && std::size_t(m) <= fields_.size() &&
                         fields_.size() >= std::size_t(n) + std::size_t(m) + 24;
      if (!poses) return;
      const std::size_t base = std::size_t(n) + std::size_t(m) + 10;
      for (int i = 0; i < 6; ++i) {
        if (!ParseDouble(fields_[base + i], &v[i])) return;
      }
      laser->found = true;
      laser->sensor.min_angle_deg = start * kRadToDeg;
      laser->sensor.angular_resolution_deg = res * kRadToDeg;
      laser->sensor.max_angle_deg = (start + double(n - 1) * res) * kRadToDeg;
      if (const std::string why = SensorProblem(laser->sensor); !why.empty()) {
        throw InputError(path_ + ":" + std::to_string(line_no) + ": " + std::string(fields_[0]) +
                         ": the laser's aperture from this line: " + why);
      }
      laser->laser = {v[0], v[1], v[2]};
      laser->odometry = {v[3], v[4], v[5]};
    }
    *max_range = std::max(*max_range, line_max);
    if (PeekTimestamp(&t)) {
      const std::string pose = PeekLaserPose();
      if (t == laser->group_t && pose != laser->group_pose) return;  // skipped when read
      laser->group = (t == laser->group_t) ? laser->group + 1 : 1;
      laser->group_t = t;
      laser->group_pose = pose;
      laser->layers = std::max(laser->layers, laser->group);
    }
  }

  // First pass: laser geometry and the largest range (the saturation value); a second laser
  // makes the log a rig.
  void Survey(const LogOptions& options) {
    std::string line;
    double max_range = 0.0;
    Surveyed lasers[2];
    std::size_t line_no = 0, second_line = 0;
    while (std::getline(in_, line)) {
      ++line_no;
      if (IsCommentOrBlank(line)) continue;
      SplitFields(line, &fields_);
      const std::string_view name = fields_[0];
      if (second_ == kNoSecond && (name == "RLASER" || name == "ROBOTLASER2")) {
        second_ = name == "RLASER" ? kSecondRlaser : kSecondRobotLaser;
        second_line = line_no;
      }
      const int flaser = FlaserSensor(name), robot = RobotLaserSensor(name);
      if (flaser >= 0) SurveyFlaser(&lasers[flaser], &max_range);
      if (robot >= 0) SurveyRobotLaser(&lasers[robot], &max_range, line_no);
    }
    if (!lasers[0].found) {
      throw InputError(path_ + ": a CARMEN log without any usable FLASER or ROBOTLASER1 message");
    }
    max_range_ = options.carmen_max_range_m > 0 ? options.carmen_max_range_m : max_range;
    for (Surveyed& l : lasers) {
      l.sensor.layers = std::min(l.layers, kMaxLayer + 1);
      l.sensor.min_range_m = 0.0;
      // The range the lines are read with (no echo from max_range_ - kNoEchoMargin on), kept
      // above the margin a sensor needs (a log whose ranges are all 0).
      l.sensor.max_range_m = std::max(max_range_, 2 * kNoEchoMargin);
      l.sensor.no_echo_margin_m = kNoEchoMargin;
    }
    if (second_ != kNoSecond && lasers[1].found) {
      // A rig: poses are the odometry's, each laser at its mount.
      for (int k = 0; k < 2; ++k) {
        const Pose2D& o = lasers[k].odometry;
        const Pose2D& l = lasers[k].laser;
        const double c = std::cos(o.yaw), sn = std::sin(o.yaw);
        SensorConfig s = lasers[k].sensor;
        s.name = k == 0 ? "front" : "rear";
        s.mount_x_m = c * (l.x - o.x) + sn * (l.y - o.y);
        s.mount_y_m = -sn * (l.x - o.x) + c * (l.y - o.y);
        s.mount_yaw_deg = std::remainder(l.yaw - o.yaw, 2 * M_PI) * kRadToDeg;
        rig_.push_back(s);
      }
      sensor_ = rig_.front();
      return;
    }
    if (second_ != kNoSecond) {
      const char* name = second_ == kSecondRlaser ? "RLASER" : "ROBOTLASER2";
      Report(second_line, std::string(name) +
                              ": no line of the second laser is usable (from here " +
                              "on); the log is read as one laser, without its " + name + " lines");
    }
    second_ = kNoSecond;
    sensor_ = lasers[0].sensor;
    sensor_.mount_x_m = sensor_.mount_y_m = sensor_.mount_yaw_deg = 0.0;  // laser poses
  }

  // The laser pose's three fields of the ROBOTLASER1 line in fields_, as written ("" when the
  // line is too short): the layers of one scan share them.
  std::string PeekLaserPose() const {
    long n = 0, m = 0;
    if (fields_.size() < 10 || !ParseInt(fields_[8], &n) || n < 0 ||
        fields_.size() < std::size_t(n) + 10 || !ParseInt(fields_[9 + n], &m) || m < 0 ||
        std::size_t(m) > fields_.size()) {
      return "";
    }
    const std::size_t at = std::size_t(n + m) + 10;
    if (fields_.size() < at + 3) return "";
    return std::string(fields_[at]) + ' ' + std::string(fields_[at + 1]) + ' ' +
           std::string(fields_[at + 2]);
  }

  // The ipc timestamp of the ROBOTLASER1 line in fields_.
  bool PeekTimestamp(double* t) const {
    long n = 0, m = 0;
    if (fields_.size() < 10 || !ParseInt(fields_[8], &n) || n < 0 ||
        fields_.size() < std::size_t(n) + 10 || !ParseInt(fields_[9 + n], &m) || m < 0 ||
        std::size_t(m) > fields_.size()) {
      return false;
    }
    const std::size_t at = std::size_t(n + m) + 21;
    return fields_.size() > at && ParseDouble(fields_[at], t);
  }

  bool ParseNumber(std::size_t line_no, std::size_t index, const char* what, double* value) {
    if (ParseDouble(fields_[index], value)) return true;
    Report(line_no, Excerpt(fields_[0]) + ": " + what + " (field " + std::to_string(index + 1) +
                        ", '" + Excerpt(fields_[index]) + "') is not a number; line skipped");
    return false;
  }

  bool ParseFlaser(std::size_t line_no, Scan* scan) {
    long n = 0;
    if (fields_.size() < 2 || !ParseInt(fields_[1], &n) || n <= 0 || n > 100000) {
      Report(line_no, "FLASER: beam count '" + (fields_.size() > 1 ? Excerpt(fields_[1]) : "") +
                          "' is not a positive integer; line skipped");
      return false;
    }
    const std::size_t expected = std::size_t(n) + 11;
    if (fields_.size() != expected) {
      Report(line_no, Excerpt(fields_[0]) + ": " +
                          (fields_.size() < expected ? "truncated line: " : "too many fields: ") +
                          std::to_string(fields_.size()) + " fields, expected " +
                          std::to_string(expected) + " for " + std::to_string(n) +
                          " beams (the ranges, two poses, ipc timestamp, host, logger " +
                          "timestamp); line skipped");
      return false;
    }
    double x, y, theta, t;
    if (!ParseNumber(line_no, n + 2, "laser x", &x) ||
        !ParseNumber(line_no, n + 3, "laser y", &y) ||
        !ParseNumber(line_no, n + 4, "laser theta", &theta) ||
        !ParseNumber(line_no, n + 8, "ipc timestamp", &t)) {
      return false;
    }
    const double res = FlaserResolutionDeg(n) * M_PI / 180.0;
    scan->points.resize(n);
    for (long i = 0; i < n; ++i) {
      double r;
      if (!ParseNumber(line_no, 2 + i, "range", &r)) {
        scan->points.clear();  // a skipped line leaves nothing for the next one
        return false;
      }
      ScanPoint& p = scan->points[i];
      p.layer = 0;
      p.angle_rad = float(-M_PI / 2 + double(i) * res);
      p.range_m = float(r);
      p.echo = !(r >= max_range_ - kNoEchoMargin);
    }
    scan->timestamp_s = t;
    scan->pose = {x, y, theta};
    if (second_ != kNoSecond) {
      double odometry[3];
      if (!ParseNumber(line_no, n + 5, "odom_x", &odometry[0]) ||
          !ParseNumber(line_no, n + 6, "odom_y", &odometry[1]) ||
          !ParseNumber(line_no, n + 7, "odom_theta", &odometry[2])) {
        scan->points.clear();
        return false;
      }
      scan->pose = {odometry[0], odometry[1], odometry[2]};
    }
    return true;
  }

  bool ParseRobotLaser(std::size_t line_no, std::uint8_t layer, Scan* scan, double* t) {
    long n = 0, m = 0;
    if (fields_.size() < 10 || !ParseInt(fields_[8], &n) || n <= 0 || n > 100000) {
      Report(line_no, "ROBOTLASER1: beam count is not a positive integer; line skipped");
      return false;
    }
    if (fields_.size() < std::size_t(n) + 10 || !ParseInt(fields_[9 + n], &m) || m < 0 ||
        std::size_t(m) > fields_.size() || fields_.size() < std::size_t(n + m) + 24) {
      Report(line_no, "ROBOTLASER1: truncated line: " + std::to_string(fields_.size()) +
                          " fields for " + std::to_string(n) + " beams; line skipped");
      return false;
    }
    double start, fov, res, line_max;
    if (!ParseNumber(line_no, 2, "start_angle", &start) || !ParseNumber(line_no, 3, "fov", &fov) ||
        !ParseNumber(line_no, 4, "angular_res", &res) ||
        !ParseNumber(line_no, 5, "max_range", &line_max)) {
      return false;
    }
    const std::size_t base = std::size_t(n + m) + 10;
    double x, y, theta;
    if (!ParseNumber(line_no, base, "laser_x", &x) ||
        !ParseNumber(line_no, base + 1, "laser_y", &y) ||
        !ParseNumber(line_no, base + 2, "laser_theta", &theta) ||
        !ParseNumber(line_no, base + 11, "ipc timestamp", t)) {
      return false;
    }
    const double limit = std::min(line_max, max_range_) - kNoEchoMargin;
    const std::size_t first = scan->points.size();
    scan->points.resize(first + n);
    for (long i = 0; i < n; ++i) {
      double r;
      if (!ParseNumber(line_no, 9 + i, "range", &r)) {
        scan->points.resize(first);
        return false;
      }
      ScanPoint& p = scan->points[first + i];
      p.layer = layer;
      p.angle_rad = float(start + double(i) * res);
      p.range_m = float(r);
      p.echo = !(r >= limit);
    }
    scan->timestamp_s = *t;
    scan->pose = {x, y, theta};
    if (second_ != kNoSecond) {
      double robot[3];
      if (!ParseNumber(line_no, base + 3, "robot_x", &robot[0]) ||
          !ParseNumber(line_no, base + 4, "robot_y", &robot[1]) ||
          !ParseNumber(line_no, base + 5, "robot_theta", &robot[2])) {
        scan->points.resize(first);
        return false;
      }
      scan->pose = {robot[0], robot[1], robot[2]};
    }
    return true;
  }

  // The second laser's message, when the log is a rig.
  enum Second { kNoSecond, kSecondRlaser, kSecondRobotLaser };

  std::ifstream in_;
  Second second_ = kNoSecond;
  double size_ = 0;
  double max_range_ = 0;
  std::vector<std::string_view> fields_;
  std::size_t lines_read_ = 0;
  std::size_t line_ = 0;
  std::string pending_;
  std::size_t pending_no_ = 0;
  bool has_pending_ = false;
};

}  // namespace

std::unique_ptr<LogReader> OpenCarmen(const std::string& path, const LogOptions& options) {
  return std::make_unique<CarmenReader>(path, options);
}

}  // namespace freespace::io
