// freespace.Config: the engine's configuration from a YAML file, a YAML string or a dict, with
// the engine's validation and its messages (ConfigError names the field and the value).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "convert.hpp"

namespace freespace::python {
namespace {

PyConfig Validated(Config config) {
  config.Validate();
  return PyConfig{std::move(config)};
}

}  // namespace

void BindConfig(py::module_& m) {
  py::class_<PyConfig>(m, "Config",
                       "Every parameter of every stage (docs/configuration.md). Plain data: a "
                       "Config is validated when made; with_overrides() makes a changed copy.")
      .def(py::init([] { return PyConfig{}; }), "The defaults (the paper's values).")
      .def_static(
          "from_yaml",
          [](const std::string& text, const std::string& source) {
            return Validated(Config::FromYaml(text, source));
          },
          py::arg("text"), py::arg("source") = "yaml",
          "Reads a YAML document of sections (map, sensor, ...); missing fields keep their "
          "defaults. `source` names the text in error messages. Raises ConfigError.")
      .def_static(
          "from_yaml_file",
          [](const std::string& path) { return Validated(Config::FromYamlFile(path)); },
          py::arg("path"), "Reads a YAML config file. Raises ConfigError.")
      .def_static(
          "from_dict",
          [](const py::dict& d) { return PyConfig{WithOverrides(Config(), d, "dict")}; },
          py::arg("fields"),
          "The defaults with these fields: {'polygon': {'margin_cells': 1}} or "
          "{'polygon.margin_cells': 1}. Raises ConfigError (unknown field, bad value) or "
          "TypeError (a value that is not bool, int, float or str).")
      .def(
          "with_overrides",
          [](const PyConfig& c, const py::dict& d) {
            return PyConfig{WithOverrides(c.config, d, "overrides")};
          },
          py::arg("fields"), "A copy with these fields changed (as from_dict).")
      .def(
          "to_yaml", [](const PyConfig& c) { return c.config.ToYaml(); },
          "Every field as YAML (round-trips through from_yaml).")
      .def(
          "to_dict", [](const PyConfig& c) { return ConfigToDict(c.config); },
          "Every field as a dict of sections.")
      .def("__eq__", [](const PyConfig& a,
                        const PyConfig& b) { return a.config.ToYaml() == b.config.ToYaml(); })
      .def("__repr__",
           [](const PyConfig& c) {
             return "freespace.Config.from_yaml('''" + c.config.ToYaml() + "''')";
           })
      .def(py::pickle(
          [](const PyConfig& c) { return c.config.ToYaml(); },
          [](const std::string& yaml) { return Validated(Config::FromYaml(yaml, "pickle")); }));
}

}  // namespace freespace::python
