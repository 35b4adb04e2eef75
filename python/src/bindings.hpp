// The Python module's pieces: each Bind* function adds one group of classes to the module
// (module.cpp calls them in order), and the small wrapper types they share.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "freespace/config.hpp"
#include "freespace/result.hpp"
#include "freespace/scan.hpp"

namespace freespace::python {

namespace py = pybind11;

// A scan as Python sees it (freespace.Scan): owned by Python, handed to Estimator.process
// without conversion.
struct PyScan {
  Scan scan;
};

// freespace.Config: the engine's Config, plain data, validated whenever Python makes one.
struct PyConfig {
  Config config;
};

// freespace.Result: a copy of the estimator's Result of one scan.
struct PyResult {
  Result r;
};

// freespace.Map: the map of one Estimator.map() call; log_odds and free are (height, width)
// arrays, views of the estimator's buffers or copies.
struct PyMap {
  int width = 0, height = 0;
  double resolution_m = 0.0, map_yaw = 0.0;
  Vec2 origin;
  py::array log_odds, free;
  py::object occupancy_cache;

  // The engine's view of these arrays (for the scorer); valid while this PyMap lives.
  MapView View() const;
};

void BindConfig(py::module_& m);     // config_py.cpp
void BindEstimator(py::module_& m);  // estimator_py.cpp: Scan, Result, Map, Estimator
void BindIo(py::module_& m);         // io_py.cpp: the log readers
void BindSim(py::module_& m);        // sim_py.cpp: simulator, scorer, drive evaluation

}  // namespace freespace::python
