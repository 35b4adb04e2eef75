// The extension module freespace._freespace (the package freespace re-exports it): the
// engine's exceptions as Python ones carrying the C++ message, then every class.
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "engine/backend_factory.hpp"
#include "freespace/errors.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_freespace, m) {
  m.doc() =
      "freespace: static free-space detection from laser scans on occupancy grid maps "
      "(docs/python.md)";
  // Registered before the classes so that every binding's C++ exception maps to these.
  py::register_exception<freespace::ConfigError>(m, "ConfigError", PyExc_ValueError);
  py::register_exception<freespace::InputError>(m, "InputError", PyExc_OSError);
  py::register_exception<freespace::BackendError>(m, "BackendError", PyExc_RuntimeError);
  // Whether `backend.kind: opencl` can work at all in this build (a device is still needed).
  m.attr("opencl_compiled_in") = freespace::OpenClCompiledIn();
  freespace::python::BindConfig(m);
  freespace::python::BindEstimator(m);
  freespace::python::BindIo(m);
  freespace::python::BindSim(m);
}
