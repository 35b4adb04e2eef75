// The project's own multi-layer log format (docs/formats.md), reader and writer, and the
// ROBOTLASER1 writer for interchange with CARMEN tools.
//
//   FREESPACE_LOG 1
//   SENSOR <layers> <min_angle_deg> <max_angle_deg> <resolution_deg> <min_range_m>
//          <max_range_m> <mount_x_m> <mount_y_m> <mount_yaw_deg> [<sweep_s>]  (one line)
//   SCAN <t_s> <x_m> <y_m> <yaw_rad> <n> then n triples <layer> <angle_deg> <range_m | ->
//
// Version 2 holds a rig: one or more "SENSOR <name> <layers> ..." lines, an optional
// "RIG <reference_x_m> <reference_y_m> <footprint_length_m> <footprint_width_m>" line, and each
// scan names its sensor by index: "SCAN <sensor> <t_s> ...".
//
// One scan a line; '-' is a beam without echo; '#' starts a comment line.
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include "core/stream_error.hpp"
#include "freespace/errors.hpp"
#include "freespace/io.hpp"
#include "readers.hpp"
#include "text.hpp"

namespace freespace {
namespace io {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

class NativeReader final : public LogReader {
 public:
  NativeReader(const std::string& path, const LogOptions&)
      : LogReader(path, LogFormat::kNative), in_(path, std::ios::binary) {
    if (!in_) throw InputError(path + ": cannot open");
    in_.seekg(0, std::ios::end);
    size_ = double(in_.tellg());
    in_.seekg(0);
    std::string line;
    if (!NextLine(&line)) throw InputError(path + ": empty; expected the header 'FREESPACE_LOG 1'");
    ReadHeader(line);
    // SENSOR lines: one in version 1; one or more in version 2, up to the first other record.
    while (NextLine(&line)) {
      SplitFields(line, &fields_);
      if (version_ == 2 && fields_[0] == "RIG") {
        ReadRig();
        continue;
      }
      if (fields_[0] != "SENSOR" && !rig_.empty()) {
        pending_ = line;
        has_pending_ = true;
        break;
      }
      ReadSensor();
      if (version_ == 1) break;
    }
    if (rig_.empty()) throw InputError(path + ": no SENSOR line after the header");
    sensor_ = rig_.front();
    if (rig_.size() == 1) {
      rig_.clear();
      if (has_rig_line_) {
        Note(0, "a RIG line with one SENSOR: a log of one sensor has no rig; the line is not used");
      }
    }
  }

  bool Next(Scan* scan) override {
    std::string line;
    while (TakeLine(&line)) {
      SplitFields(line, &fields_);
      if (fields_[0] != "SCAN") {
        Report(line_no_, "unknown record '" + Excerpt(fields_[0]) + "'; line skipped");
        continue;
      }
      if (Parse(scan)) {
        line_ = line_no_;
        return true;
      }
    }
    return false;
  }

  std::size_t line() const override { return line_; }
  double progress() const override {
    if (size_ <= 0 || in_.eof()) return 1.0;
    return std::min(1.0, double(in_.tellg()) / size_);
  }

 private:
  bool NextLine(std::string* line) {
    while (std::getline(in_, *line)) {
      ++line_no_;
      if (IsCommentOrBlank(*line)) continue;
      if (in_.eof()) Note(line_no_, kNoFinalNewline);
      return true;
    }
    return false;
  }

  // The line the header left over, else the next.
  bool TakeLine(std::string* line) {
    if (has_pending_) {
      has_pending_ = false;
      *line = std::move(pending_);
      return true;
    }
    return NextLine(line);
  }

  std::string Where() const { return path_ + ":" + std::to_string(line_no_) + ": "; }

  void ReadHeader(const std::string& line) {
    SplitFields(line, &fields_);
    long version = 0;
    if (fields_.size() != 2 || fields_[0] != "FREESPACE_LOG" || !ParseInt(fields_[1], &version)) {
      throw InputError(Where() + "expected the header 'FREESPACE_LOG 1' (or 2)");
    }
    if (version != 1 && version != 2) {
      throw InputError(Where() + "log version " + std::to_string(version) +
                       " is not supported (this reader reads 1 and 2)");
    }
    version_ = int(version);
  }

  // "RIG reference_x_m reference_y_m footprint_length_m footprint_width_m" (version 2).
  void ReadRig() {
    if (has_rig_line_) throw InputError(Where() + "a second RIG line (a log has at most one)");
    has_rig_line_ = true;
    double v[4];
    bool ok = fields_.size() == 5;
    for (int i = 0; ok && i < 4; ++i) ok = ParseDouble(fields_[i + 1], &v[i]);
    if (!ok || !(std::abs(v[0]) < 100 && std::abs(v[1]) < 100 && v[2] >= 0 && v[2] <= 50 &&
                 v[3] >= 0 && v[3] <= 50)) {
      throw InputError(Where() +
                       "expected 'RIG reference_x_m reference_y_m footprint_length_m "
                       "footprint_width_m' (|reference| < 100 m, footprint 0 .. 50 m)");
    }
    rig_vehicle_ = {v[0], v[1], v[2], v[3]};
  }

  // A SENSOR line: version 1 "SENSOR layers ...", version 2 "SENSOR name layers ...".
  void ReadSensor() {
    const std::size_t named = version_ == 2 ? 1 : 0;
    // Nine numbers, and sweep_s as a tenth where the sensor sweeps (0 when left out).
    double v[10] = {};
    const int numbers = int(fields_.size()) - 1 - int(named);
    bool ok = (numbers == 9 || numbers == 10) && fields_[0] == "SENSOR";
    for (int i = 0; ok && i < numbers; ++i) ok = ParseDouble(fields_[i + 1 + named], &v[i]);
    if (!ok) {
      throw InputError(Where() + "expected 'SENSOR " + (named ? "name " : "") +
                       "layers min_angle_deg max_angle_deg resolution_deg min_range_m "
                       "max_range_m mount_x_m mount_y_m mount_yaw_deg [sweep_s]'");
    }
    if (!(std::abs(v[9]) <= 1.0)) {
      throw InputError(Where() + "SENSOR sweep_s '" + Excerpt(fields_[10 + named]) +
                       "' is not within -1 .. 1 s");
    }
    if (!(v[0] >= 1 && v[0] <= 255 && v[0] == std::floor(v[0]))) {
      throw InputError(Where() + "SENSOR layer count '" + Excerpt(fields_[1 + named]) +
                       "' is not an integer 1..255");
    }
    if (rig_.size() >= std::size_t(kMaxSensors)) {
      throw InputError(Where() + "more than " + std::to_string(kMaxSensors) + " SENSOR lines");
    }
    SensorConfig s;
    if (named) s.name = std::string(fields_[1]);  // as written: the config checks it
    s.layers = int(v[0]);
    s.min_angle_deg = v[1];
    s.max_angle_deg = v[2];
    s.angular_resolution_deg = v[3];
    s.min_range_m = v[4];
    s.max_range_m = v[5];
    s.mount_x_m = v[6];
    s.mount_y_m = v[7];
    s.mount_yaw_deg = v[8];
    s.sweep_s = v[9];
    // A bad number is the log's, named at its line.
    if (const std::string why = SensorProblem(s); !why.empty()) {
      throw InputError(Where() + "SENSOR: " + why);
    }
    rig_.push_back(s);
  }

  bool Parse(Scan* scan) {
    scan->sensor = 0;
    if (version_ == 2) {
      // "SCAN sensor t x y yaw n ...": the index read, the rest parsed as version 1's.
      long sensor = -1;
      const std::size_t sensors = rig_.empty() ? 1 : rig_.size();
      if (fields_.size() < 2 || !ParseInt(fields_[1], &sensor) || sensor < 0 ||
          std::size_t(sensor) >= sensors) {
        Report(line_no_, "SCAN: sensor index '" + (fields_.size() < 2 ? "" : Excerpt(fields_[1])) +
                             "' is not one of the " + std::to_string(sensors) +
                             " SENSOR lines (0 ..); line skipped");
        return false;
      }
      scan->sensor = int(sensor);
      fields_.erase(fields_.begin() + 1);
    }
    double head[4];
    long n = 0;
    if (fields_.size() < 6) {
      Report(line_no_, "SCAN: truncated line: " + std::to_string(fields_.size()) +
                           " fields, expected at least 6; line skipped");
      return false;
    }
    for (int i = 0; i < 4; ++i) {
      if (!ParseDouble(fields_[i + 1], &head[i])) {
        Report(line_no_, "SCAN: field " + std::to_string(i + 2) + " ('" + Excerpt(fields_[i + 1]) +
                             "') is not a number; line skipped");
        return false;
      }
    }
    if (!ParseInt(fields_[5], &n) || n < 0) {
      Report(line_no_, "SCAN: point count '" + Excerpt(fields_[5]) +
                           "' is not a non-negative integer; line skipped");
      return false;
    }
    // n is compared with the fields there are, never multiplied: a huge count cannot overflow.
    const std::size_t triples = (fields_.size() - 6) / 3;
    if ((fields_.size() - 6) % 3 != 0 || std::size_t(n) != triples) {
      const std::string expected = std::size_t(n) <= fields_.size()
                                       ? std::to_string(6 + 3 * std::size_t(n))
                                       : "6 + 3 per point";
      Report(line_no_, "SCAN: " + std::to_string(fields_.size()) + " fields, expected " + expected +
                           " for " + std::to_string(n) +
                           " points (truncated or extra data); line skipped");
      return false;
    }
    scan->timestamp_s = head[0];
    scan->pose = {head[1], head[2], head[3]};
    scan->points.resize(n);
    for (long i = 0; i < n; ++i) {
      const std::size_t f = 6 + 3 * std::size_t(i);
      long layer = 0;
      double angle = 0, range = 0;
      ScanPoint& p = scan->points[i];
      if (!ParseInt(fields_[f], &layer) || layer < 0 || layer > 255 ||
          !ParseDouble(fields_[f + 1], &angle)) {
        Report(line_no_, "SCAN: point " + std::to_string(i) + " ('" + Excerpt(fields_[f]) + " " +
                             Excerpt(fields_[f + 1]) +
                             "') needs a layer 0..255 and an angle; line skipped");
        return false;
      }
      p.layer = std::uint8_t(layer);
      p.angle_rad = float(angle * kDegToRad);
      if (fields_[f + 2] == "-") {
        p.echo = false;
        p.range_m = 0.0f;
      } else if (ParseDouble(fields_[f + 2], &range)) {
        p.echo = true;
        p.range_m = float(range);
      } else {
        Report(line_no_, "SCAN: point " + std::to_string(i) + " range '" + Excerpt(fields_[f + 2]) +
                             "' is not a number or '-'; line skipped");
        return false;
      }
    }
    return true;
  }

  mutable std::ifstream in_;
  int version_ = 1;
  std::string pending_;
  bool has_pending_ = false;
  bool has_rig_line_ = false;
  double size_ = 0;
  std::vector<std::string_view> fields_;
  std::size_t line_no_ = 0;
  std::size_t line_ = 0;
};

}  // namespace

std::unique_ptr<LogReader> OpenNative(const std::string& path, const LogOptions& options) {
  return std::make_unique<NativeReader>(path, options);
}

}  // namespace io

namespace {
// A SENSOR line's optional tenth number: the sweep, where the sensor has one.
std::string SweepField(const SensorConfig& s) {
  if (s.sweep_s == 0.0) return "";
  char field[32];
  std::snprintf(field, sizeof field, " %.9g", s.sweep_s);
  return field;
}
}  // namespace

namespace {
// Appends printf-style text to `out`, however long the numbers make it (a huge but finite yaw
// in %.9f is 300 digits).
__attribute__((format(printf, 2, 3))) void AppendF(std::string* out, const char* format, ...) {
  char buffer[128];
  va_list args;
  va_start(args, format);
  va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(buffer, sizeof buffer, format, args);
  va_end(args);
  if (n >= 0 && std::size_t(n) < sizeof buffer) {
    out->append(buffer, std::size_t(n));
  } else if (n >= 0) {
    const std::size_t at = out->size();
    out->resize(at + std::size_t(n) + 1);
    std::vsnprintf(&(*out)[at], std::size_t(n) + 1, format, again);
    out->resize(at + std::size_t(n));
  }
  va_end(again);
}

// Appends " " and `v` with `decimals` decimals, or, where that would pass the readers' 63
// characters a field (|v| >= 1e15), in 17 significant digits: every finite double reads back.
void AppendNumber(std::string* out, double v, int decimals) {
  if (std::abs(v) < 1e15 || !std::isfinite(v)) {
    AppendF(out, " %.*f", decimals, v);
  } else {
    AppendF(out, " %.17g", v);
  }
}
}  // namespace

NativeLogWriter::NativeLogWriter(const std::string& path, const SensorConfig& s) : path_(path) {
  errno = 0;
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) throw StreamError(path, "cannot create");
  char line[512];
  std::snprintf(line, sizeof line,
                "FREESPACE_LOG 1\n# SENSOR layers min_angle_deg max_angle_deg resolution_deg "
                "min_range_m max_range_m mount_x_m mount_y_m mount_yaw_deg [sweep_s]\n"
                "SENSOR %d %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g%s\n"
                "# SCAN t_s x_m y_m yaw_rad n (layer angle_deg range_m|-)*n\n",
                s.layers, s.min_angle_deg, s.max_angle_deg, s.angular_resolution_deg, s.min_range_m,
                s.max_range_m, s.mount_x_m, s.mount_y_m, s.mount_yaw_deg, SweepField(s).c_str());
  out_ << line;
}

NativeLogWriter::NativeLogWriter(const std::string& path, const std::vector<SensorConfig>& sensors,
                                 const RigConfig& rig)
    : path_(path) {
  if (sensors.empty()) throw std::invalid_argument("NativeLogWriter: no sensor");
  if (sensors.size() == 1) {
    *this = NativeLogWriter(path, sensors.front());
    return;
  }
  errno = 0;
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) throw StreamError(path, "cannot create");
  version_ = 2;
  sensors_ = int(sensors.size());
  out_ << "FREESPACE_LOG 2\n# SENSOR name layers min_angle_deg max_angle_deg resolution_deg "
          "min_range_m max_range_m mount_x_m mount_y_m mount_yaw_deg [sweep_s]\n";
  for (const SensorConfig& s : sensors) {
    std::string line;  // the name has no bound on its length
    AppendF(&line, "SENSOR %s %d %.9g %.9g %.9g %.9g %.9g %.9g %.9g %.9g%s\n", s.name.c_str(),
            s.layers, s.min_angle_deg, s.max_angle_deg, s.angular_resolution_deg, s.min_range_m,
            s.max_range_m, s.mount_x_m, s.mount_y_m, s.mount_yaw_deg, SweepField(s).c_str());
    out_ << line;
  }
  char line[512];
  std::snprintf(line, sizeof line,
                "# RIG reference_x_m reference_y_m footprint_length_m footprint_width_m\n"
                "RIG %.9g %.9g %.9g %.9g\n",
                rig.reference_x_m, rig.reference_y_m, rig.footprint_length_m,
                rig.footprint_width_m);
  out_ << line;
  out_ << "# SCAN sensor t_s x_m y_m yaw_rad n (layer angle_deg range_m|-)*n\n";
  if (!out_) throw StreamError(path_, "write failed");
}

void NativeLogWriter::Write(const Scan& scan) {
  std::string text;
  text.reserve(32 + scan.points.size() * 22);
  // A scan of a sensor the log does not hold (in a log of one: any but 0) would be written as
  // another's.
  if (scan.sensor < 0 || scan.sensor >= sensors_) {
    throw std::invalid_argument("NativeLogWriter: scan of sensor " + std::to_string(scan.sensor) +
                                " in a log of " + std::to_string(sensors_) + " sensor(s)");
  }
  if (version_ == 2) {
    AppendF(&text, "SCAN %d", scan.sensor);
  } else {
    text += "SCAN";
  }
  AppendNumber(&text, scan.timestamp_s, 6);
  AppendNumber(&text, scan.pose.x, 6);
  AppendNumber(&text, scan.pose.y, 6);
  AppendNumber(&text, scan.pose.yaw, 9);
  AppendF(&text, " %zu", scan.points.size());
  for (const ScanPoint& p : scan.points) {
    AppendF(&text, " %u", unsigned(p.layer));
    AppendNumber(&text, double(p.angle_rad) * 180.0 / M_PI, 4);
    if (p.echo) {
      AppendNumber(&text, double(p.range_m), 3);
    } else {
      text += " -";
    }
  }
  text += '\n';
  errno = 0;
  out_ << text;
  if (!out_) throw StreamError(path_, "write failed");
}

void NativeLogWriter::Close() {
  errno = 0;
  out_.close();
  if (out_.fail()) throw StreamError(path_, "write failed");
}

RobotLaserWriter::RobotLaserWriter(const std::string& path, const SensorConfig& sensor)
    : path_(path), sensor_(sensor) {
  errno = 0;
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) throw StreamError(path, "cannot create");
  out_ << "# ROBOTLASER1 type start_angle fov angular_res max_range accuracy remission_mode n "
          "ranges m remissions laser_x laser_y laser_theta robot_x robot_y robot_theta tv rv "
          "forward_safety side_safety turn_axis ipc_timestamp ipc_hostname logger_timestamp\n"
          "# one line per layer; the layers of one scan share the timestamp\n";
}

void RobotLaserWriter::Write(const Scan& scan) {
  const int bins =
      int(std::floor(
          (sensor_.max_angle_deg - sensor_.min_angle_deg) / sensor_.angular_resolution_deg + 0.5)) +
      1;
  const double start = sensor_.min_angle_deg * io::kDegToRad;
  const double res = sensor_.angular_resolution_deg * io::kDegToRad;
  const double c = std::cos(scan.pose.yaw), s = std::sin(scan.pose.yaw);
  const double lx = scan.pose.x + c * sensor_.mount_x_m - s * sensor_.mount_y_m;
  const double ly = scan.pose.y + s * sensor_.mount_x_m + c * sensor_.mount_y_m;
  const double lt = scan.pose.yaw + sensor_.mount_yaw_deg * io::kDegToRad;
  std::string text;
  for (int layer = 0; layer < sensor_.layers; ++layer) {
    ranges_.assign(bins, float(sensor_.max_range_m));
    for (const ScanPoint& p : scan.points) {
      if (p.layer != layer || !p.echo) continue;
      const long b = std::lround((double(p.angle_rad) - start) / res);
      if (b >= 0 && b < bins) ranges_[b] = std::min(ranges_[b], p.range_m);
    }
    text.clear();
    AppendF(&text, "ROBOTLASER1 0 %.9f %.9f %.9f %.3f 0.01 0 %d", start, (bins - 1) * res, res,
            sensor_.max_range_m, bins);
    for (const float r : ranges_) AppendF(&text, " %.3f", double(r));
    text += " 0";  // no remissions; the laser's pose, the robot's, five zeros, the times
    for (const auto& [v, decimals] :
         {std::pair{lx, 6}, std::pair{ly, 6}, std::pair{lt, 9}, std::pair{scan.pose.x, 6},
          std::pair{scan.pose.y, 6}, std::pair{scan.pose.yaw, 9}}) {
      AppendNumber(&text, v, decimals);
    }
    text += " 0 0 0 0 0";
    AppendNumber(&text, scan.timestamp_s, 6);
    text += " freespace";
    AppendNumber(&text, scan.timestamp_s, 6);
    text += '\n';
    errno = 0;
    out_ << text;
    if (!out_) throw StreamError(path_, "write failed");  // errno of this layer's write
  }
}

void RobotLaserWriter::Close() {
  errno = 0;
  out_.close();
  if (out_.fail()) throw StreamError(path_, "write failed");
}

}  // namespace freespace
