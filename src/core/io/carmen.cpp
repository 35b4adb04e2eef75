// CARMEN log reader: FLASER (one single-layer scan a line) and ROBOTLASER1 (explicit
// geometry; consecutive lines with the same timestamp are the layers of one scan). Each scan
// uses the laser pose on its own line. Other messages (ODOM, PARAM, NEFF, ...) are ignored.
// A first pass over the file finds the scanner's geometry and, unless given, its saturation
// range: ranges at or above it are beams without echo (81.83 m in intel.clf).
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
constexpr int kMaxLayer = 255;  // ScanPoint::layer is a uint8

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
      if (fields_[0] == "FLASER") {
        if (ParseFlaser(line_no, scan)) {
          line_ = line_no;
          return true;
        }
      } else if (fields_[0] == "ROBOTLASER1") {
        double t = 0;
        if (!ParseRobotLaser(line_no, 0, scan, &t)) continue;
        line_ = line_no;
        // Further layers: following ROBOTLASER1 lines with the same timestamp.
        int layer = 1;  // a layer index is a uint8: lines past the 256th of a scan are skipped
        std::size_t skipped = 0, skipped_from = 0;
        std::string next;
        std::size_t next_no = 0;
        while (NextLine(&next, &next_no)) {
          SplitFields(next, &fields_);
          double t_next = 0;
          Scan layer_scan;
          if (!fields_.empty() && fields_[0] == "ROBOTLASER1" && PeekTimestamp(&t_next) &&
              t_next == t) {
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
          Report(skipped_from, "ROBOTLASER1: " + std::to_string(skipped) +
                                   " line(s) from here on " + "share the timestamp of the " +
                                   std::to_string(kMaxLayer + 1) +
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
      return true;
    }
    return false;
  }

  // First pass: laser geometry and the largest range (the saturation value).
  void Survey(const LogOptions& options) {
    std::string line;
    double max_range = 0.0;
    bool found = false;
    int group = 0, layers = 1;
    double group_t = NAN;
    while (std::getline(in_, line)) {
      if (IsCommentOrBlank(line)) continue;
      SplitFields(line, &fields_);
      long n = 0;
      if (fields_[0] == "FLASER" && fields_.size() > 2 && ParseInt(fields_[1], &n) && n > 1 &&
          fields_.size() >= std::size_t(n) + 11) {
        if (!found) {
          found = true;
          sensor_.layers = 1;
          sensor_.min_angle_deg = -90.0;
          sensor_.angular_resolution_deg = FlaserResolutionDeg(n);
          sensor_.max_angle_deg = -90.0 + double(n - 1) * sensor_.angular_resolution_deg;
        }
        for (long i = 0; i < n; ++i) {
          double r;
          if (ParseDouble(fields_[2 + i], &r) && std::isfinite(r))
            max_range = std::max(max_range, r);
        }
      } else if (fields_[0] == "ROBOTLASER1" && fields_.size() > 9 && ParseInt(fields_[8], &n) &&
                 n > 1) {
        double start, fov, res, line_max, t;
        if (!ParseDouble(fields_[2], &start) || !ParseDouble(fields_[3], &fov) ||
            !ParseDouble(fields_[4], &res) || !ParseDouble(fields_[5], &line_max) || !(res > 0)) {
          continue;
        }
        if (!found) {
          found = true;
          sensor_.min_angle_deg = start * kRadToDeg;
          sensor_.angular_resolution_deg = res * kRadToDeg;
          sensor_.max_angle_deg = (start + double(n - 1) * res) * kRadToDeg;
        }
        max_range = std::max(max_range, line_max);
        if (PeekTimestamp(&t)) {
          group = (t == group_t) ? group + 1 : 1;
          group_t = t;
          layers = std::max(layers, group);
        }
      }
    }
    if (!found) {
      throw InputError(path_ + ": a CARMEN log without any usable FLASER or ROBOTLASER1 message");
    }
    sensor_.layers = std::min(layers, 255);
    sensor_.mount_x_m = sensor_.mount_y_m = sensor_.mount_yaw_deg = 0.0;  // poses are laser poses
    sensor_.min_range_m = 0.0;
    max_range_ = options.carmen_max_range_m > 0 ? options.carmen_max_range_m : max_range;
    sensor_.max_range_m = std::max(max_range_, 1.0);
    sensor_.no_echo_margin_m = kNoEchoMargin;
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
    if (fields_.size() < expected) {
      Report(line_no, "FLASER: truncated line: " + std::to_string(fields_.size()) +
                          " fields, expected " + std::to_string(expected) + " for " +
                          std::to_string(n) + " beams; line skipped");
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
      if (!ParseNumber(line_no, 2 + i, "range", &r)) return false;
      ScanPoint& p = scan->points[i];
      p.layer = 0;
      p.angle_rad = float(-M_PI / 2 + double(i) * res);
      p.range_m = float(r);
      p.echo = !(r >= max_range_ - kNoEchoMargin);
    }
    scan->timestamp_s = t;
    scan->pose = {x, y, theta};
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
    return true;
  }

  std::ifstream in_;
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
