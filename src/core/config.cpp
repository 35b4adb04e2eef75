// Config: one field table (VisitFields) gives every field its section, name, unit, valid range and
// one-line doc; YAML reading and writing, validation (messages "field = value: rule") and the
// reference table of docs/configuration.md all come from it. Rules between fields (kRelations)
// are a short list beside it.
#include "freespace/config.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "core/config_fields.hpp"
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

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The valid values of a numeric field: an interval whose bounds may be open, closed or absent
// (infinite). Every number must also be finite.
struct Range {
  double lo = -kInfinity;
  double hi = kInfinity;
  bool lo_open = false;
  bool hi_open = false;

  bool Contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  // "[1, 8192]", "(0, 10]", ">= 0", "> 0"; empty when unbounded.
  std::string Text() const;
};

constexpr Range Closed(double lo, double hi) { return {lo, hi, false, false}; }
constexpr Range Open(double lo, double hi) { return {lo, hi, true, true}; }
constexpr Range OpenClosed(double lo, double hi) { return {lo, hi, true, false}; }
constexpr Range ClosedOpen(double lo, double hi) { return {lo, hi, false, true}; }
constexpr Range AtLeast(double lo) { return {lo, kInfinity, false, false}; }
constexpr Range Above(double lo) { return {lo, kInfinity, true, false}; }
constexpr Range Finite() { return {}; }

// What the table says about a field besides its name and type.
struct Spec {
  const char* unit;  // "" when none
  Range range;       // numeric fields only
  const char* doc;   // one line
};

std::string Format(int v) { return std::to_string(v); }
std::string Format(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
std::string Format(bool v) { return v ? "true" : "false"; }
std::string Format(const std::string& v) { return "\"" + v + "\""; }

std::string Range::Text() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) {
    return (lo_open ? "(" : "[") + Format(lo) + ", " + Format(hi) + (hi_open ? ")" : "]");
  }
  if (has_lo) return (lo_open ? "> " : ">= ") + Format(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + Format(hi);
  return "";
}

template <class Enum, std::size_t N>
std::string AllowedNames(const EnumName<Enum> (&names)[N], const char* separator) {
  std::string allowed;
  for (const auto& n : names) allowed += (allowed.empty() ? "" : separator) + std::string(n.name);
  return allowed;
}

// The field table, a section at a time. Visits every field with its name, the member and its
// Spec; the one place that lists them, so that reading, writing, the unknown-key check,
// validation and the documentation cannot drift apart. `C` is Config or const Config.
template <class C, class Visitor>
void VisitMap(C& m, Visitor& v) {
  v("width_cells", m.width_cells, {"cells", Closed(1, 8192), "map columns, along world x"});
  v("height_cells", m.height_cells, {"cells", Closed(1, 8192), "map rows, along world y"});
  v("resolution_m", m.resolution_m, {"m", OpenClosed(0, 10), "edge of a square cell"});
}

template <class C, class Visitor>
void VisitSensor(C& s, Visitor& v) {
  v("layers", s.layers, {"", Closed(1, 255), "points of layer >= layers are dropped"});
  v("min_angle_deg", s.min_angle_deg,
    {"deg", Closed(-360, 360), "start of the horizontal aperture, sensor frame, CCW"});
  v("max_angle_deg", s.max_angle_deg, {"deg", Finite(), "end of the horizontal aperture"});
  v("angular_resolution_deg", s.angular_resolution_deg,
    {"deg", OpenClosed(0, 10), "beam spacing; beams (and the polygon's bins) are grouped by it"});
  v("min_range_m", s.min_range_m,
    {"m", AtLeast(0), "echoes closer than this are invalid (no echo)"});
  v("max_range_m", s.max_range_m,
    {"m", Finite(), "echoes at or beyond max_range_m - no_echo_margin_m are \"no echo\""});
  v("no_echo_margin_m", s.no_echo_margin_m, {"m", AtLeast(0), "see max_range_m"});
  v("mount_x_m", s.mount_x_m, {"m", Open(-100, 100), "sensor x in the vehicle (odometry) frame"});
  v("mount_y_m", s.mount_y_m, {"m", Open(-100, 100), "sensor y in the vehicle (odometry) frame"});
  v("mount_yaw_deg", s.mount_yaw_deg,
    {"deg", Closed(-360, 360), "sensor heading relative to the vehicle's"});
}

template <class C, class Visitor>
void VisitClutter(C& k, Visitor& v) {
  v("enabled", k.enabled, {"", {}, "DBSCAN clutter filter on or off (paper II)"});
  v("eps_m", k.eps_m,
    {"m", OpenClosed(0, 100), "neighbour distance: eps_m + eps_per_m * the larger range"});
  v("eps_per_m", k.eps_per_m,
    {"m/m", ClosedOpen(0, 1), "growth of the neighbour distance with range"});
  v("min_points", k.min_points,
    {"points", AtLeast(1), "DBSCAN core-point threshold, the point itself included"});
  v("min_cluster_size", k.min_cluster_size,
    {"points", AtLeast(1), "smaller clusters are clutter (paper: 5)"});
}

template <class C, class Visitor>
void VisitSensorModel(C& m, Visitor& v) {
  v.Enum("kind", m.kind, kSensorModelNames,
         {"", {}, "inverse sensor model: the full-scan polygon (paper II) or a ray per point"});
  v("p_free", m.p_free, {"", Open(0, 0.5), "probability of a free cell (paper V.B)"});
  v("p_occupied", m.p_occupied,
    {"", Open(0.5, 1), "probability of a cell holding a kept echo (paper V.B)"});
  v("p_min", m.p_min, {"", Open(0, 0.5), "lower clamp of a cell's probability in the map"});
  v("p_max", m.p_max, {"", Open(0.5, 1), "upper clamp of a cell's probability in the map"});
}

template <class C, class Visitor>
void VisitAlignment(C& a, Visitor& v) {
  v.Enum("kind", a.kind, kAlignmentNames,
         {"", {}, "vehicle on a circle, integer shifts (paper III), or the rotated-map baseline"});
  v("speed_window", a.speed_window,
    {"scans", Closed(1, 1000), "n of eq. (1): moving average of the last n speeds"});
  v("gain_s", a.gain_s, {"s", AtLeast(0), "circle radius per m/s of filtered speed"});
  v("margin_m", a.margin_m, {"m", AtLeast(0), "the vehicle stays this far inside the map"});
  v("max_speed_mps", a.max_speed_mps,
    {"m/s", Above(0), "a pose moving faster than this (plus jump_slack_m) is a jump"});
  v("jump_slack_m", a.jump_slack_m, {"m", AtLeast(0), "allowed extra displacement per scan"});
  v("reset_after_jumps", a.reset_after_jumps,
    {"scans", AtLeast(1), "jumps in a row after which the map restarts at the new pose"});
  v("time_jitter_s", a.time_jitter_s,
    {"s", AtLeast(0), "a timestamp this much before the last is jitter: no speed sample"});
}

template <class C, class Visitor>
void VisitClassify(C& t, Visitor& v) {
  v("t_low", t.t_low, {"", Open(0, 0.5), "free if p <= t_low (paper IV.A)"});
  v("t_high", t.t_high,
    {"", Open(0, 0.5), "also free if p <= t_high next to a t_low cell; unknown is never free"});
  v("vehicle_width_m", t.vehicle_width_m,
    {"m", AtLeast(0), "opening element: an odd square of about this width"});
  v("veto_current_echoes", t.veto_current_echoes,
    {"", {}, "this scan's echo cells are not free this scan, whatever the map holds"});
}

template <class C, class Visitor>
void VisitPolygon(C& p, Visitor& v) {
  v.Enum("shape", p.shape, kPolygonShapeNames,
         {"", {}, "C_Edge cell centres (paper IV.B) or conservative: free cells only"});
  v("max_vertices", p.max_vertices, {"", Closed(3, 4096), "N: most vertices of the polygon"});
  v("epsilon_m", p.epsilon_m, {"m", AtLeast(0), "Douglas-Peucker tolerance"});
  v("margin_cells", p.margin_cells,
    {"cells", Closed(0, 32),
     "safety margin in front of occupied and unknown cells (not in the paper; 0 = none)"});
  v("margin_cone_deg", p.margin_cone_deg,
    {"deg", OpenClosed(0, 180), "the margin's cone around the line of sight (180: all around)"});
}

template <class C, class Visitor>
void VisitBackend(C& b, Visitor& v) {
  v.Enum("kind", b.kind, kBackendNames, {"", {}, "compute backend"});
  v("threads", b.threads, {"", Closed(0, 1024), "TBB worker threads; 0 = all cores"});
  v("opencl_platform", b.opencl_platform,
    {"", {}, "substring of the OpenCL platform's name; empty = the first with a device"});
  v("opencl_device", b.opencl_device,
    {"", {}, "substring of the OpenCL device's name; empty = the first"});
  v.Enum("opencl_wait", b.opencl_wait, kOpenClWaitNames,
         {"", {}, "how the host waits for a scan's OpenCL result"});
  v("opencl_spin_us", b.opencl_spin_us,
    {"us", Closed(0, 100000), "auto's longest spin before it sleeps; 0 never spins"});
  v("opencl_devices", b.opencl_devices,
    {"", Closed(1, 16), "CPU devices to split the OpenCL backend's passes over"});
}

template <class C, class Visitor>
void VisitFields(C& c, Visitor&& v) {
  v.Section("map");
  VisitMap(c.map, v);
  v.Section("sensor");
  VisitSensor(c.sensor, v);
  v.Section("clutter");
  VisitClutter(c.clutter, v);
  v.Section("sensor_model");
  VisitSensorModel(c.sensor_model, v);
  v.Section("alignment");
  VisitAlignment(c.alignment, v);
  v.Section("classify");
  VisitClassify(c.classify, v);
  v.Section("polygon");
  VisitPolygon(c.polygon, v);
  v.Section("backend");
  VisitBackend(c.backend, v);
}

// The rasterizer's fixed-point arithmetic (1/256 cell in 32-bit vertices, 64-bit products)
// needs every vertex within 16384 cells of the map's corner.
double ScanReachCells(const Config& c) {
  return c.sensor.max_range_m / c.map.resolution_m +
         std::max(c.map.width_cells, c.map.height_cells) +
         std::hypot(c.sensor.mount_x_m, c.sensor.mount_y_m) / c.map.resolution_m;
}

double HalfSmallerSideCells(const Config& c) {
  return 0.5 * std::min(c.map.width_cells, c.map.height_cells);
}

// A rule between fields, checked once every field is within its own range. `rule` reads after
// "field = value: " in messages and in the documentation's range column.
struct Relation {
  const char* field;
  const char* rule;
  bool (*holds)(const Config&);
  std::string (*detail)(const Config&);  // appended to the message; may be null
};

const Relation kRelations[] = {
    {"sensor.max_angle_deg", "must be in (sensor.min_angle_deg, sensor.min_angle_deg + 360]",
     [](const Config& c) {
       return c.sensor.max_angle_deg > c.sensor.min_angle_deg &&
              c.sensor.max_angle_deg <= c.sensor.min_angle_deg + 360;
     },
     nullptr},
    {"sensor.max_range_m", "must be > sensor.min_range_m",
     [](const Config& c) { return c.sensor.max_range_m > c.sensor.min_range_m; }, nullptr},
    {"sensor.no_echo_margin_m", "must be below the range span, max_range_m - min_range_m",
     [](const Config& c) {
       return c.sensor.no_echo_margin_m < c.sensor.max_range_m - c.sensor.min_range_m;
     },
     nullptr},
    {"sensor.max_range_m",
     "must keep the scan within 16384 cells: max_range_m and the mount's offset over "
     "map.resolution_m, plus the map's larger side",
     [](const Config& c) { return ScanReachCells(c) < 16384; },
     [](const Config& c) {
       return "; with this map.resolution_m the scan reaches " +
              std::to_string(int(ScanReachCells(c))) +
              " cells (raise the resolution or lower the range)";
     }},
    {"sensor_model.p_free", "must be > sensor_model.p_min",
     [](const Config& c) { return c.sensor_model.p_free > c.sensor_model.p_min; }, nullptr},
    {"sensor_model.p_occupied", "must be < sensor_model.p_max",
     [](const Config& c) { return c.sensor_model.p_occupied < c.sensor_model.p_max; }, nullptr},
    {"alignment.margin_m",
     "must leave room for the vehicle: margin_m / map.resolution_m + 1 <= half the map's "
     "smaller side",
     [](const Config& c) {
       return c.alignment.margin_m / c.map.resolution_m + 1 <= HalfSmallerSideCells(c);
     },
     [](const Config& c) { return " (" + Format(HalfSmallerSideCells(c)) + " cells)"; }},
    {"classify.t_high", "must be >= classify.t_low",
     [](const Config& c) { return c.classify.t_high >= c.classify.t_low; }, nullptr},
    {"classify.vehicle_width_m", "must be at most 255 cells of map.resolution_m",
     [](const Config& c) { return c.classify.vehicle_width_m / c.map.resolution_m <= 255; },
     nullptr},
    {"polygon.margin_cells", "needs polygon.shape inside (0 with the paper's polygon)",
     [](const Config& c) {
       return c.polygon.margin_cells == 0 || c.polygon.shape == PolygonShape::kInside;
     },
     nullptr},
};

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
  void operator()(const char* name, T& field, const Spec&) {
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
  void Enum(const char* name, E& field, const EnumName<E> (&names)[N], const Spec&) {
    if (!node_ || !node_.IsMap()) return;
    const YAML::Node value = node_[name];
    if (!value) return;
    const std::string text = Text(value);
    for (const auto& n : names) {
      if (text == n.name) {
        field = n.value;
        return;
      }
    }
    throw ConfigError(source_ + ": " + section_ + "." + name + " = '" + text +
                      "': must be one of " + AllowedNames(names, " | "));
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
  void operator()(const char* name, const T&, const Spec&) {
    keys_[section_].insert(name);
  }
  template <class E, std::size_t N>
  void Enum(const char* name, E, const EnumName<E> (&)[N], const Spec&) {
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
  void operator()(const char* name, int v, const Spec&) { Line(name, Format(v)); }
  void operator()(const char* name, double v, const Spec&) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    Line(name, s.str());
  }
  void operator()(const char* name, bool v, const Spec&) { Line(name, Format(v)); }
  void operator()(const char* name, const std::string& v, const Spec&) { Line(name, Format(v)); }
  template <class E, std::size_t N>
  void Enum(const char* name, E v, const EnumName<E> (&names)[N], const Spec&) {
    Line(name, NameOf(names, v));
  }
  std::string str() const { return out_.str(); }

 private:
  void Line(const char* name, const std::string& value) {
    out_ << "  " << name << ": " << value << "\n";
  }
  std::ostringstream out_;
};

// Throws "config: <section>.<name> = <value>: <rule>" for the first field outside its own range
// (numbers must also be finite, enums one of their names).
class RangeCheck {
 public:
  void Section(const char* name) { section_ = name; }
  void operator()(const char* name, int v, const Spec& spec) {
    if (!spec.range.Contains(v)) Fail(name, Format(v), "must be " + Rule(spec.range));
  }
  void operator()(const char* name, double v, const Spec& spec) {
    if (std::isfinite(v) && spec.range.Contains(v)) return;
    const std::string rule = Rule(spec.range);
    if (std::isfinite(v)) Fail(name, Format(v), "must be " + rule);
    Fail(name, Format(v), rule.empty() ? "must be finite" : "must be finite and " + rule);
  }
  void operator()(const char*, bool, const Spec&) {}
  void operator()(const char*, const std::string&, const Spec&) {}
  template <class E, std::size_t N>
  void Enum(const char* name, E v, const EnumName<E> (&names)[N], const Spec&) {
    for (const auto& n : names) {
      if (n.value == v) return;
    }
    Fail(name, Format(int(v)), "must be one of " + AllowedNames(names, " | "));
  }

 private:
  // "in [1, 8192]" or ">= 0".
  static std::string Rule(const Range& range) {
    const std::string text = range.Text();
    return !text.empty() && (text[0] == '[' || text[0] == '(') ? "in " + text : text;
  }
  void Fail(const char* name, const std::string& value, const std::string& rule) const {
    throw ConfigError("config: " + section_ + "." + name + " = " + value + ": " + rule);
  }
  std::string section_;
};

// One row of the documentation per field.
class DocCollector {
 public:
  void Section(const char* name) { section_ = name; }
  void operator()(const char* name, int v, const Spec& s) {
    Add(name, "integer", s, Format(v), s.range.Text());
  }
  void operator()(const char* name, double v, const Spec& s) {
    Add(name, "number", s, Format(v), s.range.Text());
  }
  void operator()(const char* name, bool v, const Spec& s) {
    Add(name, "boolean", s, Format(v), "");
  }
  void operator()(const char* name, const std::string& v, const Spec& s) {
    Add(name, "string", s, Format(v), "");
  }
  template <class E, std::size_t N>
  void Enum(const char* name, E v, const EnumName<E> (&names)[N], const Spec& s) {
    Add(name, "enum", s, NameOf(names, v), AllowedNames(names, ", "));
  }
  std::vector<ConfigFieldDoc>& docs() { return docs_; }

 private:
  void Add(const char* name, const char* type, const Spec& s, std::string value,
           std::string range) {
    docs_.push_back(
        {section_ + "." + name, type, s.unit, std::move(value), std::move(range), s.doc});
  }
  std::string section_;
  std::vector<ConfigFieldDoc> docs_;
};

// The value of the field "section.name" of `c`, as messages write it (the collector's
// default_value is the value of the config it visits).
std::string ValueText(const Config& c, const std::string& field) {
  DocCollector values;
  VisitFields(c, values);
  for (const ConfigFieldDoc& d : values.docs()) {
    if (d.name == field) return d.default_value;
  }
  return "?";
}

}  // namespace

void Config::Validate() const {
  VisitFields(*this, RangeCheck());
  for (const Relation& r : kRelations) {
    if (r.holds(*this)) continue;
    throw ConfigError("config: " + std::string(r.field) + " = " + ValueText(*this, r.field) + ": " +
                      r.rule + (r.detail ? r.detail(*this) : ""));
  }
}

std::vector<ConfigFieldDoc> ConfigFieldDocs() {
  const Config defaults;
  DocCollector collector;
  VisitFields(defaults, collector);
  std::vector<ConfigFieldDoc> docs = std::move(collector.docs());
  for (const Relation& r : kRelations) {
    std::string rule = r.rule;  // "must be > x" reads "> x" in a range column
    if (rule.rfind("must be ", 0) == 0) rule.erase(0, 8);
    for (ConfigFieldDoc& d : docs) {
      if (d.name == r.field) d.range += (d.range.empty() ? "" : "; ") + rule;
    }
  }
  return docs;
}

std::vector<std::string> ConfigFieldNames() {
  std::vector<std::string> names;
  for (const ConfigFieldDoc& d : ConfigFieldDocs()) names.push_back(d.name);
  return names;
}

std::string ConfigFieldsMarkdown() {
  // A '|' inside a cell would end it.
  const auto cell = [](std::string text) {
    for (std::size_t i = text.find('|'); i != std::string::npos; i = text.find('|', i + 2)) {
      text.insert(i, "\\");
    }
    return text;
  };
  std::string out =
      "| field | type | unit | default | range | meaning |\n"
      "|---|---|---|---|---|---|\n";
  for (const ConfigFieldDoc& d : ConfigFieldDocs()) {
    out += "| `" + d.name + "` | " + d.type + " | " + cell(d.unit) + " | " + cell(d.default_value) +
           " | " + cell(d.range) + " | " + cell(d.doc) + " |\n";
  }
  return out;
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
  YamlWriter writer;
  VisitFields(*this, writer);
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
