// The config's field table (src/core/config.cpp) as data: every field's type, unit, default,
// valid range and one-line doc, for the reference table of docs/configuration.md and the tests
// that keep it and configs/*.yaml in step with the code.
#pragma once

#include <string>
#include <vector>

namespace freespace {

struct ConfigFieldDoc {
  std::string name;           // "section.field", as in YAML
  std::string type;           // integer, number, boolean, string or enum
  std::string unit;           // empty when the field has none
  std::string default_value;  // of Config{}, as YAML spells it
  std::string range;          // the valid values: bounds, enum names, rules between fields
  std::string doc;            // one line
};

// Every field, in the table's order (the order of Config::ToYaml).
std::vector<ConfigFieldDoc> ConfigFieldDocs();

// Every field's "section.field", in the table's order.
std::vector<std::string> ConfigFieldNames();

// The reference table of docs/configuration.md: a Markdown header row, its rule and one row per
// field (field, type, unit, default, range, meaning), each line ending in '\n'.
std::string ConfigFieldsMarkdown();

}  // namespace freespace
