// Config: one field table (VisitFields) gives every field its section, name, unit, valid range and
// one-line doc; YAML reading and writing, validation (messages "field = value: rule") and the
// reference table of docs/configuration.md all come from it. Rules between fields
// (kSensorRelations, kRelations) are a short list beside it.
#include "freespace/config.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "config_table.hpp"
#include "core/config_fields.hpp"
#include "core/preprocess.hpp"
#include "freespace/errors.hpp"
#include "io/text.hpp"

namespace freespace {
using namespace config_table;
namespace {

// The rasterizer's fixed-point arithmetic (1/256 cell in 32-bit vertices, 64-bit products)
// needs every vertex within 16384 cells of the map's corner.
double ScanReachCells(const Config& c) {
  return c.sensor.max_range_m / c.map.resolution_m +
         std::max(c.map.width_cells, c.map.height_cells) +
         std::hypot(c.sensor.mount_x_m, c.sensor.mount_y_m) / c.map.resolution_m;
}

// The beams of a scan, which the preprocessing holds room for, and their bound.
double ScanBeams(const SensorConfig& s) { return double(s.layers) * SensorBins(s); }
constexpr double kMaxScanBeams = 1048576.0;  // 2^20

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

// Rules among one sensor's own fields (a log's SENSOR line is checked by them alone).
const Relation kSensorRelations[] = {
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
    {"sensor.angular_resolution_deg",
     "must leave at most 1048576 beams a scan: layers x ((max_angle_deg - min_angle_deg) / "
     "angular_resolution_deg + 1)",
     [](const Config& c) { return ScanBeams(c.sensor) <= kMaxScanBeams; },
     [](const Config& c) { return " (" + Format(ScanBeams(c.sensor)) + ")"; }},
};

const Relation kRelations[] = {
    {"sensor.max_range_m",
     "must keep the scan within 16384 cells: max_range_m and the mount's offset over "
     "map.resolution_m, plus the map's larger side",
     [](const Config& c) { return ScanReachCells(c) < 16384; },
     [](const Config& c) {
       // As a number of cells however far it reaches (a cast to int would overflow).
       std::ostringstream reach;
       reach << std::setprecision(std::numeric_limits<double>::digits10)
             << std::floor(ScanReachCells(c));
       return "; with this map.resolution_m the scan reaches " + reach.str() +
              " cells (raise the resolution or lower the range)";
     }},
    {"sensor_model.p_free", "must be > sensor_model.p_min",
     [](const Config& c) { return c.sensor_model.p_free > c.sensor_model.p_min; }, nullptr},
    {"sensor_model.p_occupied", "must be < sensor_model.p_max",
     [](const Config& c) { return c.sensor_model.p_occupied < c.sensor_model.p_max; }, nullptr},
    {"sensor_model.free_on_outline",
     "false needs sensor_model.kind enhanced (the conventional model draws no outline)",
     [](const Config& c) {
       return c.sensor_model.free_on_outline || c.sensor_model.kind == SensorModelKind::kEnhanced;
     },
     nullptr},
    {"alignment.margin_m",
     "must leave room for the vehicle: margin_m / map.resolution_m + 1 <= half the map's "
     "smaller side",
     [](const Config& c) {
       return c.alignment.margin_m / c.map.resolution_m + 1 <= HalfSmallerSideCells(c);
     },
     [](const Config& c) { return " (" + Format(HalfSmallerSideCells(c)) + " cells)"; }},
    {"alignment.scan_match",
     "needs alignment.kind circle and one sensor (a rig's cycle is not matched)",
     [](const Config& c) {
       return !c.alignment.scan_match ||
              (c.alignment.kind == AlignmentKind::kCircle && !c.is_rig());
     },
     nullptr},
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
    {"polygon.mover_memory_s", "needs polygon.shape inside (0 with the paper's polygon)",
     [](const Config& c) {
       return c.polygon.mover_memory_s == 0 || c.polygon.shape == PolygonShape::kInside;
     },
     nullptr},
    {"polygon.face_tolerance_m",
     "needs polygon.shape inside and sensor_model.kind enhanced (0 with the paper's polygon or "
     "the conventional model, which draws no outline)",
     [](const Config& c) {
       return c.polygon.face_tolerance_m == 0 ||
              (c.polygon.shape == PolygonShape::kInside &&
               c.sensor_model.kind == SensorModelKind::kEnhanced);
     },
     nullptr},
};

class YamlWriter {
 public:
  // Leaves out section `skip` (the single sensor when a rig replaces it).
  explicit YamlWriter(std::string skip = "") : skip_(std::move(skip)) {}
  void Section(const char* name) {
    skipping_ = name == skip_;
    if (!skipping_) out_ << name << ":\n";
  }
  // Starts item `i` of a list section (`sensors:` then "  - " before the item's first field).
  void ListItem(const char* list, std::size_t i) {
    if (i == 0) out_ << list << ":\n";
    skipping_ = false;
    item_start_ = true;
  }
  void operator()(const char* name, int v, const Spec&) { Line(name, Format(v)); }
  void operator()(const char* name, double v, const Spec&) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    Line(name, s.str());
  }
  void operator()(const char* name, bool v, const Spec&) { Line(name, Format(v)); }
  void operator()(const char* name, const std::string& v, const Spec&) {
    Line(name, io::YamlQuoted(v));
  }
  template <class E, std::size_t N>
  void Enum(const char* name, E v, const EnumName<E> (&names)[N], const Spec&) {
    Line(name, NameOf(names, v));
  }
  std::string str() const { return out_.str(); }

 private:
  void Line(const char* name, const std::string& value) {
    if (skipping_) return;
    out_ << (item_start_ ? "  - " : item_indent_) << name << ": " << value << "\n";
    if (item_start_) item_indent_ = "    ";
    item_start_ = false;
  }
  std::ostringstream out_;
  std::string skip_;
  bool skipping_ = false;
  bool item_start_ = false;
  std::string item_indent_ = "  ";
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

namespace {

template <std::size_t N>
void CheckRelations(const Config& c, const Relation (&relations)[N]) {
  for (const Relation& r : relations) {
    if (r.holds(c)) continue;
    throw ConfigError("config: " + std::string(r.field) + " = " + ValueText(c, r.field) + ": " +
                      r.rule + (r.detail ? r.detail(c) : ""));
  }
}

void ValidateFields(const Config& c) {
  VisitFields(c, RangeCheck());
  CheckRelations(c, kSensorRelations);
  CheckRelations(c, kRelations);
}

// `text` with every "sensor." (a field of the single sensor) read as one of the rig's.
std::string RigSensorText(std::string text, const std::string& label) {
  const std::string from = "sensor.";
  for (std::size_t at = text.find(from); at != std::string::npos;
       at = text.find(from, at + label.size())) {
    const bool word =
        at == 0 || !(std::isalnum(static_cast<unsigned char>(text[at - 1])) || text[at - 1] == '_');
    if (word) {
      text.replace(at, from.size() - 1, label);
    } else {
      at += 1;
    }
  }
  return text;
}

// A sensor's name: one word (it names the sensor in messages and in a log's SENSOR line): no
// space and no control character; bytes of UTF-8 letters are taken.
void CheckSensorName(const std::string& label, const std::string& name) {
  for (const char ch : name) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c <= 0x20 || c == 0x7f) {
      throw ConfigError("config: " + label + ".name = \"" + io::Excerpt(name, 40) +
                        "\": must be one word, without spaces or control characters");
    }
  }
}

// Each sensor of a rig as the single sensor would be checked, messages naming it; names
// distinct and not empty.
void ValidateRig(const Config& c) {
  if (c.alignment.scan_match) {
    throw ConfigError(
        "config: alignment.scan_match = true: needs one sensor (a rig's cycle is not matched)");
  }
  if (c.sensors.size() > std::size_t(kMaxSensors)) {
    throw ConfigError("config: sensors has " + std::to_string(c.sensors.size()) +
                      " sensors: at most " + std::to_string(kMaxSensors));
  }
  std::set<std::string> names;
  for (std::size_t i = 0; i < c.sensors.size(); ++i) {
    const SensorConfig& s = c.sensors[i];
    const std::string label =
        "sensors[" + (s.name.empty() ? std::to_string(i) : io::Excerpt(s.name, 40)) + "]";
    if (s.name.empty()) throw ConfigError("config: " + label + ".name is empty: name each sensor");
    CheckSensorName(label, s.name);
    if (!names.insert(s.name).second) {
      throw ConfigError("config: " + label + ".name = \"" + io::Excerpt(s.name, 40) +
                        "\": two sensors of the rig have this name");
    }
    Config one = c;
    one.sensors.clear();
    one.sensor = s;
    try {
      ValidateFields(one);
    } catch (const ConfigError& e) {
      throw ConfigError(RigSensorText(e.what(), label));
    }
  }
}

}  // namespace

void Config::Validate() const {
  if (!is_rig()) {
    if (sensor.name.empty()) throw ConfigError("config: sensor.name is empty: name the sensor");
    CheckSensorName("sensor", sensor.name);
  }
  if (is_rig()) {
    Config base = *this;
    base.sensor = SensorConfig{};
    base.sensors.clear();
    ValidateFields(base);
    ValidateRig(*this);
    return;
  }
  ValidateFields(*this);
}

void ValidateSensor(const SensorConfig& sensor) {
  RangeCheck check;
  check.Section("sensor");
  VisitSensor(sensor, check);
  Config c;
  c.sensor = sensor;
  CheckRelations(c, kSensorRelations);
}

std::vector<ConfigFieldDoc> ConfigFieldDocs() {
  const Config defaults;
  DocCollector collector;
  VisitFields(defaults, collector);
  std::vector<ConfigFieldDoc> docs = std::move(collector.docs());
  const auto add_rules = [&docs](const auto& relations) {
    for (const Relation& r : relations) {
      std::string rule = r.rule;  // "must be > x" reads "> x" in a range column
      if (rule.rfind("must be ", 0) == 0) rule.erase(0, 8);
      for (ConfigFieldDoc& d : docs) {
        if (d.name == r.field) d.range += (d.range.empty() ? "" : "; ") + rule;
      }
    }
  };
  add_rules(kSensorRelations);
  add_rules(kRelations);
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

std::string Config::ToYaml() const {
  YamlWriter writer(is_rig() ? "sensor" : "");
  VisitFields(*this, writer);
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    writer.ListItem("sensors", i);
    SensorConfig s = sensors[i];
    VisitSensor(s, writer);
  }
  return writer.str();
}

const char* ToString(SensorModelKind kind) { return NameOf(kSensorModelNames, kind); }
const char* ToString(AlignmentKind kind) { return NameOf(kAlignmentNames, kind); }
const char* ToString(BackendKind kind) { return NameOf(kBackendNames, kind); }
const char* ToString(OpenClWait wait) { return NameOf(kOpenClWaitNames, wait); }
const char* ToString(PolygonShape shape) { return NameOf(kPolygonShapeNames, shape); }

}  // namespace freespace
