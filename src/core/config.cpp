// Config: YAML reading and writing through one field table, and validation with messages that
// name the field and the bad value.
#include "freespace/config.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "freespace/errors.hpp"

namespace freespace {
namespace {

template <class Enum>
struct EnumName {
  Enum value;
  const char* name;
};

constexpr EnumName<SensorModelKind> kSensorModelNames[] = {
    {SensorModelKind::kEnhanced, "enhanced"}, {SensorModelKind::kConventional, "conventional"}};
constexpr EnumName<AlignmentKind> kAlignmentNames[] = {{AlignmentKind::kCircle, "circle"},
                                                       {AlignmentKind::kRotate, "rotate"}};
constexpr EnumName<PolygonShape> kPolygonShapeNames[] = {{PolygonShape::kPaper, "paper"},
                                                         {PolygonShape::kInside, "inside"}};
constexpr EnumName<BackendKind> kBackendNames[] = {
    {BackendKind::kTbb, "tbb"}, {BackendKind::kOpenCl, "opencl"}, {BackendKind::kAuto, "auto"}};
constexpr EnumName<OpenClWait> kOpenClWaitNames[] = {
    {OpenClWait::kAuto, "auto"}, {OpenClWait::kBlock, "block"}, {OpenClWait::kSpin, "spin"}};

template <class Enum, std::size_t N>
const char* NameOf(const EnumName<Enum> (&names)[N], Enum value) {
  for (const auto& n : names) {
    if (n.value == value) return n.name;
  }
  return "?";
}

// Visits every field of a Config with its section and name. The one place that lists them,
// so reading, writing and the unknown-key check cannot drift apart.
template <class Visitor>
void VisitFields(Config& c, Visitor&& v) {
  v.Section("map");
  v("width_cells", c.map.width_cells);
  v("height_cells", c.map.height_cells);
  v("resolution_m", c.map.resolution_m);
  v.Section("sensor");
  v("layers", c.sensor.layers);
  v("min_angle_deg", c.sensor.min_angle_deg);
  v("max_angle_deg", c.sensor.max_angle_deg);
  v("angular_resolution_deg", c.sensor.angular_resolution_deg);
  v("min_range_m", c.sensor.min_range_m);
  v("max_range_m", c.sensor.max_range_m);
  v("no_echo_margin_m", c.sensor.no_echo_margin_m);
  v("mount_x_m", c.sensor.mount_x_m);
  v("mount_y_m", c.sensor.mount_y_m);
  v("mount_yaw_deg", c.sensor.mount_yaw_deg);
  v.Section("clutter");
  v("enabled", c.clutter.enabled);
  v("eps_m", c.clutter.eps_m);
  v("eps_per_m", c.clutter.eps_per_m);
  v("min_points", c.clutter.min_points);
  v("min_cluster_size", c.clutter.min_cluster_size);
  v.Section("sensor_model");
  v.Enum("kind", c.sensor_model.kind, kSensorModelNames);
  v("p_free", c.sensor_model.p_free);
  v("p_occupied", c.sensor_model.p_occupied);
  v("p_min", c.sensor_model.p_min);
  v("p_max", c.sensor_model.p_max);
  v.Section("alignment");
  v.Enum("kind", c.alignment.kind, kAlignmentNames);
  v("speed_window", c.alignment.speed_window);
  v("gain_s", c.alignment.gain_s);
  v("margin_m", c.alignment.margin_m);
  v("max_speed_mps", c.alignment.max_speed_mps);
  v("jump_slack_m", c.alignment.jump_slack_m);
  v("reset_after_jumps", c.alignment.reset_after_jumps);
  v("time_jitter_s", c.alignment.time_jitter_s);
  v.Section("classify");
  v("t_low", c.classify.t_low);
  v("t_high", c.classify.t_high);
  v("vehicle_width_m", c.classify.vehicle_width_m);
  v.Section("polygon");
  v.Enum("shape", c.polygon.shape, kPolygonShapeNames);
  v("max_vertices", c.polygon.max_vertices);
  v("epsilon_m", c.polygon.epsilon_m);
  v("margin_cells", c.polygon.margin_cells);
  v("margin_cone_deg", c.polygon.margin_cone_deg);
  v.Section("backend");
  v.Enum("kind", c.backend.kind, kBackendNames);
  v("threads", c.backend.threads);
  v("opencl_platform", c.backend.opencl_platform);
  v("opencl_device", c.backend.opencl_device);
  v.Enum("opencl_wait", c.backend.opencl_wait, kOpenClWaitNames);
  v("opencl_spin_us", c.backend.opencl_spin_us);
  v("opencl_devices", c.backend.opencl_devices);
}

class YamlReader {
 public:
  YamlReader(const YAML::Node& root, std::string source)
      : root_(root), source_(std::move(source)) {}

  void Section(const char* name) {
    section_ = name;
    node_ = root_[name];
    if (node_ && !node_.IsMap() && !node_.IsNull()) {
      throw ConfigError(source_ + ": '" + section_ + "' must be a mapping of fields");
    }
  }

  template <class T>
  void operator()(const char* name, T& field) {
    if (!node_ || !node_.IsMap()) return;
    const YAML::Node value = node_[name];
    if (!value) return;
    try {
      field = value.as<T>();
    } catch (const YAML::Exception&) {
      throw ConfigError(source_ + ": " + section_ + "." + name + " = '" + Text(value) +
                        "': not a valid " + TypeName(field));
    }
  }

  template <class E, std::size_t N>
  void Enum(const char* name, E& field, const EnumName<E> (&names)[N]) {
    if (!node_ || !node_.IsMap()) return;
    const YAML::Node value = node_[name];
    if (!value) return;
    const std::string text = Text(value);
    std::string allowed;
    for (const auto& n : names) {
      if (text == n.name) {
        field = n.value;
        return;
      }
      allowed += allowed.empty() ? n.name : std::string(" | ") + n.name;
    }
    throw ConfigError(source_ + ": " + section_ + "." + name + " = '" + text +
                      "': must be one of " + allowed);
  }

 private:
  static std::string Text(const YAML::Node& n) {
    if (n.IsScalar()) return n.Scalar();
    std::ostringstream s;
    s << n;
    return s.str();
  }
  static const char* TypeName(int) { return "integer"; }
  static const char* TypeName(double) { return "number"; }
  static const char* TypeName(bool) { return "boolean (true/false)"; }
  static const char* TypeName(const std::string&) { return "string"; }

  YAML::Node root_;
  YAML::Node node_;
  std::string source_;
  std::string section_;
};

// Collects the known field names per section, for the unknown-key check.
class KeyCollector {
 public:
  void Section(const char* name) {
    section_ = name;
    keys_[section_];
  }
  template <class T>
  void operator()(const char* name, T&) {
    keys_[section_].insert(name);
  }
  template <class E, std::size_t N>
  void Enum(const char* name, E&, const EnumName<E> (&)[N]) {
    keys_[section_].insert(name);
  }
  const std::map<std::string, std::set<std::string>>& keys() const { return keys_; }

 private:
  std::string section_;
  std::map<std::string, std::set<std::string>> keys_;
};

class YamlWriter {
 public:
  void Section(const char* name) { out_ << name << ":\n"; }
  void operator()(const char* name, int v) { out_ << "  " << name << ": " << v << "\n"; }
  void operator()(const char* name, double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    out_ << "  " << name << ": " << s.str() << "\n";
  }
  void operator()(const char* name, bool v) {
    out_ << "  " << name << ": " << (v ? "true" : "false") << "\n";
  }
  void operator()(const char* name, const std::string& v) {
    out_ << "  " << name << ": \"" << v << "\"\n";
  }
  template <class E, std::size_t N>
  void Enum(const char* name, E v, const EnumName<E> (&names)[N]) {
    out_ << "  " << name << ": " << NameOf(names, v) << "\n";
  }
  std::string str() const { return out_.str(); }

 private:
  std::ostringstream out_;
};

// Throws "config: <field> = <value>: <rule>" when `ok` is false.
template <class T>
void Check(bool ok, const char* field, T value, const std::string& rule) {
  if (ok) return;
  std::ostringstream s;
  s << "config: " << field << " = " << value << ": " << rule;
  throw ConfigError(s.str());
}

}  // namespace

void Config::Validate() const {
  const Config& c = *this;
  Check(c.map.width_cells >= 1 && c.map.width_cells <= 8192, "map.width_cells", c.map.width_cells,
        "must be in [1, 8192]");
  Check(c.map.height_cells >= 1 && c.map.height_cells <= 8192, "map.height_cells",
        c.map.height_cells, "must be in [1, 8192]");
  Check(std::isfinite(c.map.resolution_m) && c.map.resolution_m > 0 && c.map.resolution_m <= 10,
        "map.resolution_m", c.map.resolution_m, "must be in (0, 10]");

  const SensorConfig& s = c.sensor;
  Check(s.layers >= 1 && s.layers <= 255, "sensor.layers", s.layers, "must be in [1, 255]");
  Check(std::isfinite(s.min_angle_deg) && s.min_angle_deg >= -360 && s.min_angle_deg <= 360,
        "sensor.min_angle_deg", s.min_angle_deg, "must be in [-360, 360]");
  Check(std::isfinite(s.max_angle_deg) && s.max_angle_deg > s.min_angle_deg &&
            s.max_angle_deg <= s.min_angle_deg + 360,
        "sensor.max_angle_deg", s.max_angle_deg,
        "must be in (sensor.min_angle_deg, sensor.min_angle_deg + 360]");
  Check(std::isfinite(s.angular_resolution_deg) && s.angular_resolution_deg > 0 &&
            s.angular_resolution_deg <= 10,
        "sensor.angular_resolution_deg", s.angular_resolution_deg, "must be in (0, 10]");
  Check(std::isfinite(s.min_range_m) && s.min_range_m >= 0, "sensor.min_range_m", s.min_range_m,
        "must be >= 0");
  Check(std::isfinite(s.max_range_m) && s.max_range_m > s.min_range_m, "sensor.max_range_m",
        s.max_range_m, "must be finite and > sensor.min_range_m");
  Check(std::isfinite(s.no_echo_margin_m) && s.no_echo_margin_m >= 0 &&
            s.no_echo_margin_m < s.max_range_m - s.min_range_m,
        "sensor.no_echo_margin_m", s.no_echo_margin_m,
        "must be >= 0 and below the sensor's range span");
  Check(std::isfinite(s.mount_x_m) && std::abs(s.mount_x_m) < 100, "sensor.mount_x_m", s.mount_x_m,
        "must be finite, |x| < 100");
  Check(std::isfinite(s.mount_y_m) && std::abs(s.mount_y_m) < 100, "sensor.mount_y_m", s.mount_y_m,
        "must be finite, |y| < 100");
  Check(std::isfinite(s.mount_yaw_deg) && std::abs(s.mount_yaw_deg) <= 360, "sensor.mount_yaw_deg",
        s.mount_yaw_deg, "must be in [-360, 360]");
  // The rasterizer's fixed-point arithmetic (1/256 cell in 32-bit vertices, 64-bit products)
  // needs every vertex within 16384 cells of the map's corner.
  const double reach_cells = s.max_range_m / c.map.resolution_m +
                             std::max(c.map.width_cells, c.map.height_cells) +
                             std::hypot(s.mount_x_m, s.mount_y_m) / c.map.resolution_m;
  Check(reach_cells < 16384, "sensor.max_range_m", s.max_range_m,
        "with this map.resolution_m the scan reaches " + std::to_string(int(reach_cells)) +
            " cells; it must stay below 16384 (raise the resolution or lower the range)");

  const ClutterConfig& k = c.clutter;
  Check(std::isfinite(k.eps_m) && k.eps_m > 0 && k.eps_m <= 100, "clutter.eps_m", k.eps_m,
        "must be in (0, 100]");
  Check(std::isfinite(k.eps_per_m) && k.eps_per_m >= 0 && k.eps_per_m < 1, "clutter.eps_per_m",
        k.eps_per_m, "must be in [0, 1)");
  Check(k.min_points >= 1, "clutter.min_points", k.min_points, "must be >= 1");
  Check(k.min_cluster_size >= 1, "clutter.min_cluster_size", k.min_cluster_size, "must be >= 1");

  const SensorModelConfig& m = c.sensor_model;
  Check(m.p_min > 0 && m.p_min < 0.5, "sensor_model.p_min", m.p_min, "must be in (0, 0.5)");
  Check(m.p_max > 0.5 && m.p_max < 1, "sensor_model.p_max", m.p_max, "must be in (0.5, 1)");
  Check(m.p_free > m.p_min && m.p_free < 0.5, "sensor_model.p_free", m.p_free,
        "must be in (sensor_model.p_min, 0.5)");
  Check(m.p_occupied > 0.5 && m.p_occupied < m.p_max, "sensor_model.p_occupied", m.p_occupied,
        "must be in (0.5, sensor_model.p_max)");

  const AlignmentConfig& a = c.alignment;
  Check(a.speed_window >= 1 && a.speed_window <= 1000, "alignment.speed_window", a.speed_window,
        "must be in [1, 1000]");
  Check(std::isfinite(a.gain_s) && a.gain_s >= 0, "alignment.gain_s", a.gain_s, "must be >= 0");
  const double half_cells = 0.5 * std::min(c.map.width_cells, c.map.height_cells);
  Check(std::isfinite(a.margin_m) && a.margin_m >= 0 &&
            a.margin_m / c.map.resolution_m + 1 <= half_cells,
        "alignment.margin_m", a.margin_m,
        "must be >= 0 and leave room for the vehicle: margin / resolution + 1 <= half the "
        "map's smaller side (" +
            std::to_string(half_cells) + " cells)");
  Check(std::isfinite(a.max_speed_mps) && a.max_speed_mps > 0, "alignment.max_speed_mps",
        a.max_speed_mps, "must be > 0");
  Check(std::isfinite(a.jump_slack_m) && a.jump_slack_m >= 0, "alignment.jump_slack_m",
        a.jump_slack_m, "must be >= 0");
  Check(a.reset_after_jumps >= 1, "alignment.reset_after_jumps", a.reset_after_jumps,
        "must be >= 1");
  Check(std::isfinite(a.time_jitter_s) && a.time_jitter_s >= 0, "alignment.time_jitter_s",
        a.time_jitter_s, "must be >= 0");

  const ClassifyConfig& t = c.classify;
  Check(t.t_low > 0 && t.t_low < 0.5, "classify.t_low", t.t_low, "must be in (0, 0.5)");
  Check(t.t_high >= t.t_low && t.t_high < 0.5, "classify.t_high", t.t_high,
        "must be in [classify.t_low, 0.5): unknown (0.5) is never free");
  Check(std::isfinite(t.vehicle_width_m) && t.vehicle_width_m >= 0 &&
            t.vehicle_width_m / c.map.resolution_m <= 255,
        "classify.vehicle_width_m", t.vehicle_width_m, "must be in [0, 255 cells]");

  Check(c.polygon.shape == PolygonShape::kPaper || c.polygon.shape == PolygonShape::kInside,
        "polygon.shape", int(c.polygon.shape), "must be paper or inside");
  Check(c.polygon.max_vertices >= 3 && c.polygon.max_vertices <= 4096, "polygon.max_vertices",
        c.polygon.max_vertices, "must be in [3, 4096]");
  Check(std::isfinite(c.polygon.epsilon_m) && c.polygon.epsilon_m >= 0, "polygon.epsilon_m",
        c.polygon.epsilon_m, "must be >= 0");
  Check(c.polygon.margin_cells >= 0 && c.polygon.margin_cells <= 32, "polygon.margin_cells",
        c.polygon.margin_cells, "must be in [0, 32]");
  Check(c.polygon.margin_cells == 0 || c.polygon.shape == PolygonShape::kInside,
        "polygon.margin_cells", c.polygon.margin_cells,
        "needs polygon.shape inside (the paper's polygon follows C_Edge and has no margin)");
  Check(std::isfinite(c.polygon.margin_cone_deg) && c.polygon.margin_cone_deg > 0 &&
            c.polygon.margin_cone_deg <= 180,
        "polygon.margin_cone_deg", c.polygon.margin_cone_deg, "must be in (0, 180]");

  Check(c.backend.threads >= 0 && c.backend.threads <= 1024, "backend.threads", c.backend.threads,
        "must be in [0, 1024] (0 = all cores)");
  Check(c.backend.opencl_spin_us >= 0 && c.backend.opencl_spin_us <= 100000,
        "backend.opencl_spin_us", c.backend.opencl_spin_us, "must be in [0, 100000]");
  Check(c.backend.opencl_devices >= 1 && c.backend.opencl_devices <= 16, "backend.opencl_devices",
        c.backend.opencl_devices, "must be in [1, 16]");
}

Config Config::FromYaml(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(source + ": line " + std::to_string(e.mark.line + 1) +
                      ": not valid YAML: " + e.msg);
  }
  Config config;
  if (!root || root.IsNull()) return config;
  if (!root.IsMap()) throw ConfigError(source + ": the top level must be a mapping of sections");

  KeyCollector known;
  VisitFields(config, known);
  for (const auto& section : root) {
    const std::string name = section.first.as<std::string>();
    const auto it = known.keys().find(name);
    if (it == known.keys().end()) {
      throw ConfigError(source + ": unknown section '" + name + "'");
    }
    if (!section.second.IsMap()) continue;
    for (const auto& field : section.second) {
      const std::string key = field.first.as<std::string>();
      if (!it->second.count(key)) {
        throw ConfigError(source + ": unknown field '" + name + "." + key + "'");
      }
    }
  }
  YamlReader reader(root, source);
  VisitFields(config, reader);
  return config;
}

Config Config::FromYamlFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError("config: cannot open '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  return FromYaml(text.str(), path);
}

std::string Config::ToYaml() const {
  Config copy = *this;
  YamlWriter writer;
  VisitFields(copy, writer);
  return writer.str();
}

std::vector<std::string> YamlSections(const std::string& yaml_text) {
  std::vector<std::string> sections;
  try {
    const YAML::Node root = YAML::Load(yaml_text);
    if (root && root.IsMap()) {
      for (const auto& s : root) sections.push_back(s.first.as<std::string>());
    }
  } catch (const YAML::Exception&) {
    // FromYaml reports the syntax error with its line.
  }
  return sections;
}

const char* ToString(SensorModelKind kind) { return NameOf(kSensorModelNames, kind); }
const char* ToString(AlignmentKind kind) { return NameOf(kAlignmentNames, kind); }
const char* ToString(BackendKind kind) { return NameOf(kBackendNames, kind); }
const char* ToString(OpenClWait wait) { return NameOf(kOpenClWaitNames, wait); }
const char* ToString(PolygonShape shape) { return NameOf(kPolygonShapeNames, shape); }

}  // namespace freespace
