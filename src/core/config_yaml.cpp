// Config::FromYaml and the YAML helpers: reading a config file through the field table
// (config_table.hpp). Every error is a ConfigError naming the file, the line and the field; a
// section or field given twice is an error, not a silent choice of one.
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>

#include "config_table.hpp"
#include "freespace/config.hpp"
#include "freespace/errors.hpp"
#include "io/text.hpp"

namespace freespace {
using namespace config_table;
namespace {

// Appends a compact flow form of `n` ("[1, 2]", "{x: 1}") to `out`, stopping at a depth of 4 or
// past 80 bytes: a node may be huge or, through an alias, contain itself.
void Describe(const YAML::Node& n, std::string* out, int depth) {
  if (depth > 4 || out->size() > 80) {
    *out += "...";
    return;
  }
  if (n.IsScalar()) {
    *out += n.Scalar().substr(0, 81);
  } else if (n.IsSequence() || n.IsMap()) {
    *out += n.IsMap() ? "{" : "[";
    bool first = true;
    for (const auto& item : n) {
      if (out->size() > 80) {
        *out += ", ...";
        break;
      }
      if (!first) *out += ", ";
      first = false;
      if (n.IsMap()) {
        Describe(item.first, out, depth + 1);
        *out += ": ";
        Describe(item.second, out, depth + 1);
      } else {
        Describe(item, out, depth + 1);
      }
    }
    *out += n.IsMap() ? "}" : "]";
  } else {
    *out += "null";
  }
}

// A node's text for a message: a short printable excerpt of its scalar or its flow form.
std::string ValueExcerpt(const YAML::Node& n) {
  if (n.IsScalar()) return io::Excerpt(n.Scalar(), 60);
  std::string text;
  Describe(n, &text, 0);
  return io::Excerpt(text, 60);
}

class YamlReader {
 public:
  YamlReader(const YAML::Node& root, std::string source)
      : root_(root), source_(std::move(source)) {}

  void Section(const char* name) { Read(name, root_[name]); }

  // Reads the fields of `node` (a mapping, or null) as section `label`.
  void Read(const std::string& label, const YAML::Node& node) {
    section_ = label;
    node_ = node;
    if (node_ && !node_.IsMap() && !node_.IsNull()) {
      throw ConfigError(Where(node_) + "'" + section_ + "' must be a mapping of fields");
    }
  }

  template <class T>
  void operator()(const char* name, T& field, const Spec&) {
    if (!node_ || !node_.IsMap()) return;
    const YAML::Node value = node_[name];
    if (!value) return;
    if (value.IsNull()) {  // yaml-cpp would read "null" as a string's text
      throw ConfigError(Where(KeyOf(name)) + section_ + "." + name + ": no value" +
                        (std::is_same_v<T, std::string> ? " (write '' for an empty string)" : ""));
    }
    // An integer in decimal digits only: yaml-cpp reads 010 as octal 8 and 0x40 as 64.
    const bool decimal =
        !std::is_same_v<T, int> || !value.IsScalar() || DecimalInteger(value.Scalar());
    bool ok = decimal;
    const bool other_base = !decimal && LeadingZero(value.Scalar());
    try {
      if (ok) field = value.as<T>();
    } catch (const YAML::Exception&) {
      ok = false;
    }
    if (!ok) {
      throw ConfigError(Where(value) + section_ + "." + name + " = '" + ValueExcerpt(value) +
                        "': not a valid " + TypeName(field) +
                        (other_base ? " (decimal digits, no leading zero)" : ""));
    }
  }

  template <class E, std::size_t N>
  void Enum(const char* name, E& field, const EnumName<E> (&names)[N], const Spec&) {
    if (!node_ || !node_.IsMap()) return;
    const YAML::Node value = node_[name];
    if (!value) return;
    if (value.IsScalar()) {
      for (const auto& n : names) {
        if (value.Scalar() == n.name) {
          field = n.value;
          return;
        }
      }
    }
    throw ConfigError(Where(value) + section_ + "." + name + " = '" + ValueExcerpt(value) +
                      "': must be one of " + AllowedNames(names, " | "));
  }

 private:
  // "source:line: " of a value.
  std::string Where(const YAML::Node& value) const {
    const int line = value.Mark().line;
    return line >= 0 ? source_ + ":" + std::to_string(line + 1) + ": " : source_ + ": ";
  }
  // The key `name` of the section's mapping (an empty value's mark is where the next token is).
  YAML::Node KeyOf(const char* name) const {
    for (const auto& field : node_) {
      if (field.first.IsScalar() && field.first.Scalar() == name) return field.first;
    }
    return node_;
  }
  // A number written with a leading zero (010, 0x40, 0o7), which YAML reads in another base.
  static bool LeadingZero(const std::string& text) {
    const std::size_t start = !text.empty() && (text[0] == '-' || text[0] == '+') ? 1 : 0;
    return text.size() > start + 1 && text[start] == '0' && text[start + 1] != '.';
  }
  // An optional sign and decimal digits, without a leading zero (0 itself aside).
  static bool DecimalInteger(const std::string& text) {
    const std::size_t start = !text.empty() && (text[0] == '-' || text[0] == '+') ? 1 : 0;
    if (start >= text.size() || (text[start] == '0' && text.size() > start + 1)) return false;
    return std::all_of(text.begin() + std::ptrdiff_t(start), text.end(),
                       [](char c) { return c >= '0' && c <= '9'; });
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

// "source:line N" of a node, for messages (yaml-cpp counts lines from 0).
std::string Where(const std::string& source, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.line >= 0 ? source + ":" + std::to_string(mark.line + 1) : source;
}

// The text of a section or field name; a key that is not a plain scalar (`? [a, b]`) is a
// ConfigError naming where it is.
std::string KeyName(const YAML::Node& key, const std::string& source, const char* what) {
  if (!key.IsScalar()) {
    throw ConfigError(Where(source, key) + ": a " + what + " name must be a plain word, not '" +
                      ValueExcerpt(key) + "'");
  }
  return key.Scalar();
}

// Checks the field names of a mapping `node` read as section `label` against `known`: each
// known, none twice (yaml-cpp would silently read the first of two).
void CheckFields(const YAML::Node& node, const std::string& label,
                 const std::set<std::string>& known, const std::string& source) {
  std::map<std::string, int> fields;
  for (const auto& field : node) {
    const std::string key = KeyName(field.first, source, "field");
    if (!known.count(key)) {
      throw ConfigError(Where(source, field.first) + ": unknown field '" + label + "." +
                        io::Excerpt(key) + "'");
    }
    const auto [seen, new_field] = fields.emplace(key, field.first.Mark().line + 1);
    if (!new_field) {
      throw ConfigError(Where(source, field.first) + ": field '" + label + "." + key +
                        "' appears twice (first on line " + std::to_string(seen->second) + ")");
    }
  }
}

// The `sensors` list of a rig: a sequence of 1 .. kMaxSensors mappings of sensor fields.
void CheckSensorList(const YAML::Node& list, const YAML::Node& key,
                     const std::set<std::string>& known, const std::string& source) {
  if (!list.IsSequence() || list.size() == 0 || list.size() > std::size_t(kMaxSensors)) {
    throw ConfigError(Where(source, key) + ": 'sensors' must be a list of 1 to " +
                      std::to_string(kMaxSensors) + " sensors, each a mapping of sensor fields");
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node item = list[i];
    const std::string label = "sensors[" + std::to_string(i) + "]";
    if (!item.IsMap()) {
      throw ConfigError(Where(source, item) + ": '" + label + "' must be a mapping of fields");
    }
    CheckFields(item, label, known, source);
  }
}

// Checks the names of the sections and of their fields: each known, none twice (yaml-cpp
// would silently read the first of two).
void CheckKeys(const YAML::Node& root, const std::string& source) {
  KeyCollector known;
  Config defaults;
  VisitFields(defaults, known);
  std::map<std::string, int> sections;  // name -> line of its first appearance
  for (const auto& section : root) {
    const std::string name = KeyName(section.first, source, "section");
    if (name == "sensors") {
      CheckSensorList(section.second, section.first, known.keys().at("sensor"), source);
    }
    const auto it = name == "sensors" ? known.keys().find("sensor") : known.keys().find(name);
    if (it == known.keys().end()) {
      throw ConfigError(Where(source, section.first) + ": unknown section '" + io::Excerpt(name) +
                        "'");
    }
    const auto [first, fresh] = sections.emplace(name, section.first.Mark().line + 1);
    if (!fresh) {
      throw ConfigError(Where(source, section.first) + ": section '" + name +
                        "' appears twice (first on line " + std::to_string(first->second) +
                        "): merge the two");
    }
    if (!section.second.IsMap()) continue;
    CheckFields(section.second, name, it->second, source);
  }
  if (sections.count("sensor") && sections.count("sensors")) {
    throw ConfigError(source + ":" + std::to_string(sections.at("sensors")) +
                      ": give one 'sensor' section or a 'sensors' list, not both (the 'sensor' "
                      "section is on line " +
                      std::to_string(sections.at("sensor")) + ")");
  }
}

// The rig's sensors, each read like the `sensor` section; a sensor without a name is
// "sensor<i>".
void ReadSensorList(const YAML::Node& list, YamlReader* reader, Config* config) {
  if (!list) return;
  for (std::size_t i = 0; i < list.size(); ++i) {
    SensorConfig s;
    s.name = "sensor" + std::to_string(i);
    reader->Read("sensors[" + std::to_string(i) + "]", list[i]);
    VisitSensor(s, *reader);
    config->sensors.push_back(s);
  }
}

// Whether a YAML document holds anything (a value other than null), and where that starts.
class DocumentContent final : public YAML::EventHandler {
 public:
  bool any = false;
  YAML::Mark mark;
  void OnDocumentStart(const YAML::Mark&) override { any = false; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark& at, YAML::anchor_t) override { Content(at); }
  void OnScalar(const YAML::Mark& at, const std::string&, YAML::anchor_t,
                const std::string&) override {
    Content(at);
  }
  void OnSequenceStart(const YAML::Mark& at, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    Content(at);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& at, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {
    Content(at);
  }
  void OnMapEnd() override {}

 private:
  void Content(const YAML::Mark& at) {
    if (!any) mark = at;
    any = true;
  }
};

// YAML::Load reads the first document and drops any after a `---` or `...`: the config must be
// that first one, and those after it empty (a stray marker). The parser is asked for a bounded
// number of documents: on some malformed texts yaml-cpp's parser reports empty documents
// forever (YAML::LoadAll never returns there; found by tests/fuzz/fuzz_config).
void CheckOneDocument(const std::string& yaml_text, const std::string& source) {
  constexpr int kMaxDocuments = 64;
  std::istringstream in(yaml_text);
  YAML::Parser parser(in);
  DocumentContent content;
  for (int i = 0; i < kMaxDocuments && parser.HandleNextDocument(content); ++i) {
    if (i == 0 || !content.any) continue;
    throw ConfigError(source + ":" + std::to_string(content.mark.line + 1) +
                      ": a second YAML document: a config is one document (merge the two)");
  }
}

}  // namespace

Config Config::FromYaml(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
    CheckOneDocument(yaml_text, source);
  } catch (const YAML::Exception& e) {
    throw ConfigError(source + ":" + std::to_string(e.mark.line + 1) +
                      ": not valid YAML: " + io::Excerpt(e.msg, 200));
  }
  Config config;
  if (!root || root.IsNull()) return config;
  if (!root.IsMap()) throw ConfigError(source + ": the top level must be a mapping of sections");
  CheckKeys(root, source);
  YamlReader reader(root, source);
  VisitFields(config, reader);
  ReadSensorList(root["sensors"], &reader, &config);
  return config;
}

Config Config::FromYamlFile(const std::string& path) {
  // A directory opens as a stream on Linux and reads as nothing, which is a valid empty config:
  // refused, as is a read that fails part way.
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw ConfigError("config: '" + path + "' is a directory, not a config file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError("config: cannot open '" + path + "'");
  // istream::read marks a failed read bad (operator<< of the rdbuf would swallow it).
  std::string text;
  char block[4096];
  while (in.read(block, sizeof block) || in.gcount() > 0) {
    text.append(block, std::size_t(in.gcount()));
    if (!in) break;
  }
  if (in.bad()) throw ConfigError("config: cannot read '" + path + "'");
  return FromYaml(text, path);
}

namespace {

// `message` of a ConfigError from FromYaml(..., source) without the line number after `source`:
// the line is that of a document the user never wrote.
std::string WithoutLine(const std::string& message, const std::string& source) {
  const std::string prefix = source + ":";
  if (message.compare(0, prefix.size(), prefix) != 0) return message;
  std::size_t end = prefix.size();
  while (end < message.size() && std::isdigit(static_cast<unsigned char>(message[end]))) ++end;
  if (end == prefix.size() || end >= message.size() || message[end] != ':') return message;
  return source + message.substr(end);
}

// One "section.field=value": its section, field and value as YAML reads a plain value, checked
// alone as a config file's field is (a known name, a value of its type).
void ParseSetting(const std::string& setting, std::string* section, std::string* field,
                  YAML::Node* value) {
  const std::string where = "--set " + io::Excerpt(setting, 80);
  const std::size_t eq = setting.find('='), dot = setting.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 >= eq) {
    throw ConfigError(where + ": expected section.field=value (e.g. polygon.margin_cells=0)");
  }
  *section = setting.substr(0, dot);
  *field = setting.substr(dot + 1, eq - dot - 1);
  if (*section == "sensors") {
    throw ConfigError(where + ": a rig's sensors are set in the config file, not by --set");
  }
  try {
    *value = YAML::Load(setting.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw ConfigError(where + ": not a YAML value: " + io::Excerpt(e.msg, 200));
  }
  if (!value->IsScalar()) {
    throw ConfigError(where + ": the value must be one plain value ('' for an empty string)");
  }
  YAML::Node alone;
  alone[*section][*field] = *value;
  YAML::Emitter out;
  out << alone;
  try {
    Config::FromYaml(out.c_str(), where);
  } catch (const ConfigError& e) {
    throw ConfigError(WithoutLine(e.what(), where));
  }
}

}  // namespace

Config WithSettings(const Config& config, const std::vector<std::string>& settings) {
  if (settings.empty()) return config;
  YAML::Node root = YAML::Load(config.ToYaml());
  for (const std::string& setting : settings) {
    std::string section, field;
    YAML::Node value;
    ParseSetting(setting, &section, &field, &value);
    if (section == "sensor" && config.is_rig()) {
      throw ConfigError("--set " + io::Excerpt(setting, 80) +
                        ": the config is a rig of sensors (from the config file or the log): "
                        "--set does not change a rig's sensors");
    }
    root[section][field] = value;
  }
  YAML::Emitter out;
  out << root;
  Config result = Config::FromYaml(out.c_str(), "--set");
  result.Validate();
  return result;
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

}  // namespace freespace
