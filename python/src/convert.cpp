// Conversions between the engine's values and Python objects: see convert.hpp.
#include "convert.hpp"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>

#include "core/config_fields.hpp"
#include "freespace/errors.hpp"

namespace freespace::python {
namespace {

// A YAML scalar of the config as the Python value of its field's type (ConfigFieldDocs): a
// string field stays a str whatever its text ("007", "true").
py::object ScalarToPython(const std::string& text, const std::string& type) {
  if (type == "boolean") return py::bool_(text == "true");
  if (type == "integer") return py::int_(std::stoll(text));
  if (type == "number") return py::float_(std::stod(text));
  return py::str(text);  // string, enum
}

// The fields of one section (or one sensor of a rig's list) as a dict, by their types.
py::dict SectionToDict(const YAML::Node& section, const std::string& name,
                       const std::map<std::string, std::string>& types) {
  py::dict fields;
  for (const auto& field : section) {
    const std::string key = field.first.as<std::string>();
    fields[py::str(key)] = field.second.IsNull() ? py::none()
                                                 : ScalarToPython(field.second.as<std::string>(),
                                                                  types.at(name + "." + key));
  }
  return fields;
}

// A Python value of an override as YAML scalar text; raises TypeError for other types.
std::string OverrideText(const std::string& name, const py::handle& value) {
  static const py::object numpy_bool = py::module_::import("numpy").attr("bool_");
  static const py::object numpy_floating = py::module_::import("numpy").attr("floating");
  if (py::isinstance<py::bool_>(value) || py::isinstance(value, numpy_bool)) {
    return value.cast<bool>() ? "true" : "false";
  }
  if (PyIndex_Check(value.ptr()))
    return py::str(py::int_(py::reinterpret_borrow<py::object>(value)));
  if (PyFloat_Check(value.ptr()) || py::isinstance(value, numpy_floating)) {
    return py::repr(py::float_(value.cast<double>()));
  }
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  throw py::type_error("config override " + name + " = " + std::string(py::repr(value)) +
                       ": must be a bool, int, float or str");
}

void SetField(YAML::Node& root, const std::string& section, const std::string& field,
              const py::handle& value) {
  if (py::isinstance<py::dict>(value)) {
    throw py::type_error("config override " + section + "." + field + ": a field, not a section");
  }
  root[section][field] = OverrideText(section + "." + field, value);
}

// A rig's `sensors` list from a list of dicts of sensor fields.
YAML::Node SensorList(const py::list& sensors) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    const std::string label = "sensors[" + std::to_string(i) + "]";
    if (!py::isinstance<py::dict>(sensors[i])) {
      throw py::type_error("config override " + label + ": a dict of sensor fields");
    }
    YAML::Node sensor(YAML::NodeType::Map);
    for (const auto& [field, v] : sensors[i].cast<py::dict>()) {
      const std::string name = py::str(field);
      sensor[name] = OverrideText(label + "." + name, v);
    }
    list.push_back(sensor);
  }
  return list;
}

}  // namespace

py::object ToPython(const nlohmann::json& value) {
  switch (value.type()) {
    case nlohmann::json::value_t::null:
      return py::none();
    case nlohmann::json::value_t::boolean:
      return py::bool_(value.get<bool>());
    case nlohmann::json::value_t::number_integer:
      return py::int_(value.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned:
      return py::int_(value.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float:
      return py::float_(value.get<double>());
    case nlohmann::json::value_t::string:
      return py::str(value.get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list list;
      for (const nlohmann::json& v : value) list.append(ToPython(v));
      return std::move(list);
    }
    case nlohmann::json::value_t::object: {
      py::dict dict;
      for (const auto& [k, v] : value.items()) dict[py::str(k)] = ToPython(v);
      return std::move(dict);
    }
    default:
      return py::none();
  }
}

Config WithOverrides(const Config& config, const py::dict& overrides, const std::string& source) {
  YAML::Node root = YAML::Load(config.ToYaml());
  std::set<std::string> given;  // a field both dotted and in its section's dict: which one?
  const auto set_field = [&](const std::string& section, const std::string& field,
                             const py::handle& value) {
    if (!given.insert(section + "." + field).second) {
      throw ConfigError(source + ": " + section + "." + field + " is given twice");
    }
    SetField(root, section, field, value);
  };
  for (const auto& [key, value] : overrides) {
    if (!py::isinstance<py::str>(key)) {
      throw py::type_error("config override key " + std::string(py::repr(key)) + ": not a str");
    }
    const std::string name = key.cast<std::string>();
    const std::size_t dot = name.find('.');
    if (name == "sensors" && py::isinstance<py::list>(value)) {  // a rig, as to_dict() gives it
      root.remove("sensor");
      root["sensors"] = SensorList(value.cast<py::list>());
    } else if (dot != std::string::npos) {
      set_field(name.substr(0, dot), name.substr(dot + 1), value);
    } else if (py::isinstance<py::dict>(value)) {
      for (const auto& [field, v] : value.cast<py::dict>()) {
        set_field(name, py::str(field), v);
      }
    } else {
      throw py::type_error("config override " + name +
                           ": give a section's dict of fields or a dotted name (section.field)");
    }
  }
  YAML::Emitter out;
  out << root;
  try {
    Config c = Config::FromYaml(out.c_str(), source);
    c.Validate();
    return c;
  } catch (const ConfigError& e) {
    // The line numbers are those of the YAML made from the dict, which the caller never saw.
    std::string message = e.what();
    const std::string prefix = source + ":";
    if (message.compare(0, prefix.size(), prefix) == 0) {
      std::size_t end = prefix.size();
      while (end < message.size() && std::isdigit(static_cast<unsigned char>(message[end]))) ++end;
      if (end > prefix.size() && end < message.size() && message[end] == ':') {
        message = source + message.substr(end);  // "dict:48: x" -> "dict: x"
      }
    }
    throw ConfigError(message);
  }
}

py::dict ConfigToDict(const Config& config) {
  std::map<std::string, std::string> types;  // "section.field" -> its type
  for (const ConfigFieldDoc& d : ConfigFieldDocs()) types[d.name] = d.type;
  const YAML::Node root = YAML::Load(config.ToYaml());
  py::dict out;
  for (const auto& section : root) {
    const std::string name = section.first.as<std::string>();
    if (name == "sensors") {  // a rig: a list of sensors, each with the sensor's fields
      py::list sensors;
      for (const auto& sensor : section.second)
        sensors.append(SectionToDict(sensor, "sensor", types));
      out[py::str(name)] = sensors;
    } else {
      out[py::str(name)] = SectionToDict(section.second, name, types);
    }
  }
  return out;
}

namespace {

// One row of points into a ScanPoint; raises ValueError naming the row.
void SetPoint(std::size_t i, double layer, double angle, double range, double echo, ScanPoint* p) {
  if (!(layer >= 0.0 && layer <= 255.0 && layer == std::floor(layer))) {
    char text[160];
    std::snprintf(text, sizeof text, "points[%zu]: layer = %g: must be an integer 0..255", i,
                  layer);
    throw py::value_error(text);
  }
  if (echo != 0.0 && echo != 1.0) {
    char text[160];
    std::snprintf(text, sizeof text, "points[%zu]: echo = %g: must be 0 (no echo) or 1", i, echo);
    throw py::value_error(text);
  }
  p->layer = static_cast<std::uint8_t>(layer);
  p->angle_rad = static_cast<float>(angle);
  p->range_m = static_cast<float>(range);
  p->echo = echo != 0.0;
}

using Column = py::array_t<double, py::array::forcecast>;

void FillStructured(const py::array& array, std::vector<ScanPoint>* points) {
  const py::object names = array.dtype().attr("names");
  Column columns[4];
  const char* wanted[4] = {"layer", "angle", "range", "echo"};
  for (int k = 0; k < 4; ++k) {
    if (!names.attr("__contains__")(wanted[k]).cast<bool>()) {
      throw py::value_error(std::string("points: a structured array needs the fields layer, "
                                        "angle, range and echo; it has ") +
                            std::string(py::str(names)) + ", without '" + wanted[k] + "'");
    }
    columns[k] = Column::ensure(array[py::str(wanted[k])]);
    if (!columns[k] || columns[k].ndim() != 1) {
      throw py::value_error(std::string("points: field '") + wanted[k] +
                            "' must be a number per point of a 1-dimensional array");
    }
  }
  const std::size_t n = std::size_t(columns[0].shape(0));
  points->resize(n);
  auto l = columns[0].unchecked<1>(), a = columns[1].unchecked<1>(), r = columns[2].unchecked<1>(),
       e = columns[3].unchecked<1>();
  for (std::size_t i = 0; i < n; ++i) SetPoint(i, l(i), a(i), r(i), e(i), &(*points)[i]);
}

}  // namespace

namespace {

// Converts and checks n rows of (layer, angle, range, echo) in one branch-free pass; only a bad
// array is walked again, by SetPoint, to name the first bad row.
template <typename T>
void FillRows(const T* rows, std::size_t n, std::vector<ScanPoint>* points) {
  points->resize(n);
  ScanPoint* out = points->data();
  bool bad = false;
  const T* v = rows;
  for (std::size_t i = 0; i < n; ++i, v += 4) {
    const T layer = v[0], echo = v[3];
    const bool in_range = layer >= T(0) && layer <= T(255);
    const int whole = int(in_range ? layer : T(0));
    bad |= !in_range | (T(whole) != layer) | ((echo != T(0)) & (echo != T(1)));
    out[i].layer = static_cast<std::uint8_t>(whole);
    out[i].angle_rad = static_cast<float>(v[1]);
    out[i].range_m = static_cast<float>(v[2]);
    out[i].echo = echo != T(0);
  }
  if (bad) {
    v = rows;
    for (std::size_t i = 0; i < n; ++i, v += 4) SetPoint(i, v[0], v[1], v[2], v[3], &out[i]);
  }
}

}  // namespace

void FillPoints(const py::array& array, std::vector<ScanPoint>* points) {
  if (array.dtype().has_fields()) {
    FillStructured(array, points);
    return;
  }
  const bool rows4 = array.ndim() == 2 && array.shape(1) == 4;
  // float32 rows as they are (half the memory of float64); anything else as float64.
  if (rows4 && py::isinstance<py::array_t<float, py::array::c_style>>(array)) {
    FillRows(static_cast<const float*>(array.data()), std::size_t(array.shape(0)), points);
    return;
  }
  const auto rows = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!rows || !rows4) {
    throw py::value_error(
        "points: must be an (n, 4) array of (layer, angle rad, range m, echo) "
        "or a structured array with those fields; got shape " +
        std::string(py::str(array.attr("shape"))));
  }
  FillRows(rows.data(), std::size_t(rows.shape(0)), points);
}

py::array_t<double> PointsArray(const std::vector<ScanPoint>& points) {
  py::array_t<double> out({py::ssize_t(points.size()), py::ssize_t(4)});
  double* v = out.mutable_data();
  for (const ScanPoint& p : points) {
    *v++ = p.layer;
    *v++ = p.angle_rad;
    *v++ = p.range_m;
    *v++ = p.echo ? 1.0 : 0.0;
  }
  return out;
}

Pose2D ToPose(const py::handle& pose) {
  if (!PySequence_Check(pose.ptr()) || py::len(pose) != 3) {
    throw py::value_error("pose: must be (x m, y m, yaw rad); got " + std::string(py::repr(pose)));
  }
  const py::sequence seq = py::reinterpret_borrow<py::sequence>(pose);
  return Pose2D{seq[0].cast<double>(), seq[1].cast<double>(), seq[2].cast<double>()};
}

}  // namespace freespace::python
