// Conversions between the engine's C++ values and Python objects shared by the module's
// files: JSON documents to Python dicts and lists, Python dicts to config YAML, numpy point
// arrays to scans, and the engine's exceptions to Python ones.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>
#include <string>

#include "freespace/config.hpp"
#include "freespace/scan.hpp"

namespace freespace::python {

namespace py = pybind11;

// A JSON value as the Python object json.loads would give (NaN stays a float NaN).
py::object ToPython(const nlohmann::json& value);

// `config` with the fields of `overrides` replaced: a dict of sections ({"polygon":
// {"margin_cells": 1}}) or of dotted names ({"polygon.margin_cells": 1}), values bool, int,
// float or str. The result is read back through Config::FromYaml (source names it in messages)
// and validated, so unknown fields and bad values raise ConfigError with the engine's message.
Config WithOverrides(const Config& config, const py::dict& overrides, const std::string& source);

// The config as a dict of sections of fields (bool, int, float or str values).
py::dict ConfigToDict(const Config& config);

// Fills `points` from an (n, 4) array of (layer, angle rad, range m, echo 0/1) or a structured
// array with fields layer, angle, range and echo. Raises ValueError naming the row for a layer
// that is not an integer 0..255 or an echo that is not 0 or 1.
void FillPoints(const py::array& array, std::vector<ScanPoint>* points);

// The points of a scan as an (n, 4) float64 array (layer, angle, range, echo).
py::array_t<double> PointsArray(const std::vector<ScanPoint>& points);

// A pose from an (x, y, yaw) sequence; raises ValueError otherwise.
Pose2D ToPose(const py::handle& pose);

}  // namespace freespace::python
