// freespace.open_log and freespace.LogReader: the engine's log readers (CARMEN, KITTI frames,
// the project's own format; docs/formats.md) as Python iterators of freespace.Scan.
#include <pybind11/stl.h>

#include <memory>

#include "bindings.hpp"
#include "convert.hpp"
#include "freespace/io.hpp"

namespace freespace::python {
namespace {

struct PyLogReader {
  std::unique_ptr<LogReader> reader;
};

LogFormat ParseFormat(const std::string& name) {
  for (LogFormat f :
       {LogFormat::kAuto, LogFormat::kCarmen, LogFormat::kKitti, LogFormat::kNative}) {
    if (name == ToString(f)) return f;
  }
  throw py::value_error("format = '" + name + "': must be one of " + ToString(LogFormat::kAuto) +
                        ", " + ToString(LogFormat::kCarmen) + ", " + ToString(LogFormat::kKitti) +
                        ", " + ToString(LogFormat::kNative));
}

}  // namespace

void BindIo(py::module_& m) {
  py::class_<PyLogReader>(m, "LogReader",
                          "An open log: iterate it for its scans. Lines that cannot be used are "
                          "skipped and reported by issues().")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__",
           [](PyLogReader& r) {
             PyScan s;
             bool more = false;
             {
               py::gil_scoped_release release;
               more = r.reader->Next(&s.scan);
             }
             if (!more) throw py::stop_iteration();
             return s;
           })
      .def(
          "issues",
          [](PyLogReader& r) {
            std::vector<std::string> out;
            for (const LogIssue& i : r.reader->TakeIssues()) {
              out.push_back((i.note ? "note: " : "") + i.ToString());
            }
            return out;
          },
          "The issues (\"file:line: message\") found since the last call; what the reader "
          "assumed for a part the input lacks starts with \"note: \".")
      .def_property_readonly(
          "sensor",
          [](const PyLogReader& r) -> py::object {
            Config c;
            c.sensor = r.reader->sensor();
            return ConfigToDict(c)["sensor"];
          },
          "The sensor geometry the log implies, as a config section: "
          "config.with_overrides({'sensor': reader.sensor}).")
      .def_property_readonly("path", [](const PyLogReader& r) { return r.reader->path(); })
      .def_property_readonly(
          "line", [](const PyLogReader& r) { return r.reader->line(); },
          "the line where the last scan started")
      .def_property_readonly("progress", [](const PyLogReader& r) { return r.reader->progress(); });

  m.def(
      "open_log",
      [](const std::string& path, const std::string& format, double carmen_max_range_m) {
        LogOptions options;
        options.format = ParseFormat(format);
        options.carmen_max_range_m = carmen_max_range_m;
        return PyLogReader{OpenLog(path, options)};
      },
      py::arg("path"), py::arg("format") = "auto", py::arg("carmen_max_range_m") = 0.0,
      "Opens a log (format auto, carmen, kitti or native). Raises InputError when the file "
      "cannot be opened or holds nothing recognisable.");
}

}  // namespace freespace::python
