// freespace.Scan, freespace.Result, freespace.Map and freespace.Estimator: one call per scan
// from numpy points to the free-space polygon as a numpy array, and the map as numpy arrays
// that view the estimator's memory (docs/python.md says which ones are copies).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>

#include "bindings.hpp"
#include "convert.hpp"
#include "freespace/estimator.hpp"

namespace freespace::python {
namespace {

using Clock = std::chrono::steady_clock;

py::tuple PoseTuple(const Pose2D& p) { return py::make_tuple(p.x, p.y, p.yaw); }

// An (m, 2) float64 array of points (Vec2 is two packed doubles).
py::array_t<double> Points2(const std::vector<Vec2>& v) {
  py::array_t<double> out({py::ssize_t(v.size()), py::ssize_t(2)});
  double* d = out.mutable_data();
  for (const Vec2& p : v) {
    *d++ = p.x();
    *d++ = p.y();
  }
  return out;
}

py::array_t<std::int32_t> Cells(const std::vector<CellIndex>& v) {
  py::array_t<std::int32_t> out({py::ssize_t(v.size()), py::ssize_t(2)});
  std::int32_t* d = out.mutable_data();
  for (const CellIndex& c : v) {
    *d++ = c.row;
    *d++ = c.col;
  }
  return out;
}

py::dict StatsDict(const ScanStats& s) {
  py::dict d;
  d["points"] = s.points;
  d["echoes"] = s.echoes;
  d["no_echo"] = s.no_echo;
  d["invalid_range"] = s.invalid_range;
  d["out_of_aperture"] = s.out_of_aperture;
  d["bad_layer"] = s.bad_layer;
  d["clutter"] = s.clutter;
  d["kept"] = s.kept;
  d["beams"] = s.beams;
  d["virtual_points"] = s.virtual_points;
  return d;
}

py::dict TimesDict(const StageTimes& t) {
  py::dict d;
  d["preprocess_us"] = t.preprocess_us;
  d["align_us"] = t.align_us;
  d["rasterize_us"] = t.rasterize_us;
  d["fuse_us"] = t.fuse_us;
  d["classify_us"] = t.classify_us;
  d["mask_us"] = t.mask_us;
  d["insight_us"] = t.insight_us;
  d["polygon_us"] = t.polygon_us;
  d["total_us"] = t.total_us;
  return d;
}

// A read-only (height, width) view of `data`, kept alive by `owner`.
template <typename T>
py::array View(const T* data, int height, int width, const py::object& owner) {
  py::array_t<T> a({py::ssize_t(height), py::ssize_t(width)},
                   {py::ssize_t(width * sizeof(T)), py::ssize_t(sizeof(T))}, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return std::move(a);
}

void BindScanAndResult(py::module_& m) {
  py::class_<PyScan>(m, "Scan", "One full scan: time (s), vehicle pose (x, y, yaw) and points.")
      .def(py::init([](const py::array& points, const py::object& pose, double t, int sensor) {
             PyScan s;
             FillPoints(points, &s.scan.points);
             s.scan.pose = ToPose(pose);
             s.scan.timestamp_s = t;
             s.scan.sensor = sensor;
             return s;
           }),
           py::arg("points"), py::arg("pose"), py::arg("t"), py::arg("sensor") = 0)
      .def_property_readonly("t", [](const PyScan& s) { return s.scan.timestamp_s; })
      .def_property_readonly(
          "sensor", [](const PyScan& s) { return s.scan.sensor; },
          "the sensor of a rig that took it (index into the config's sensors list); 0 for one")
      .def_property_readonly("pose", [](const PyScan& s) { return PoseTuple(s.scan.pose); })
      .def_property_readonly(
          "points", [](const PyScan& s) { return PointsArray(s.scan.points); },
          "(n, 4) float64: layer, angle (rad), range (m), echo (0/1); a copy")
      .def("__len__", [](const PyScan& s) { return s.scan.points.size(); })
      .def("__repr__", [](const PyScan& s) {
        return "<freespace.Scan t=" + std::to_string(s.scan.timestamp_s) + " with " +
               std::to_string(s.scan.points.size()) + " points>";
      });

  py::class_<PyResult>(m, "Result", "What the estimator returned for one scan (a copy).")
      .def_property_readonly("scan_index", [](const PyResult& p) { return p.r.scan_index; })
      .def_property_readonly("timestamp", [](const PyResult& p) { return p.r.timestamp_s; })
      .def_property_readonly(
          "status", [](const PyResult& p) { return ToString(p.r.status); },
          "'ok', 'no_sensor_update' or 'rejected'")
      .def_property_readonly("reject_reason",
                             [](const PyResult& p) { return ToString(p.r.reject_reason); })
      .def_property_readonly("message", [](const PyResult& p) { return p.r.message; })
      .def_property_readonly("map_reset", [](const PyResult& p) { return p.r.map_reset; })
      .def_property_readonly(
          "timestamp_jitter", [](const PyResult& p) { return p.r.timestamp_jitter; },
          "a timestamp at or before the latest accepted one, within alignment.time_jitter_s: "
          "used, and said in message")
      .def_property_readonly(
          "clock_stalled", [](const PyResult& p) { return p.r.clock_stalled; },
          "the timestamps have stopped advancing: used without a jump test or a speed sample")
      .def_property_readonly(
          "cycle_silent_sensors", [](const PyResult& p) { return p.r.cycle_silent_sensors; },
          "a rig's cycle: the sensors that added nothing (no scan, or no usable echo); "
          "message names them")
      .def_property_readonly(
          "sweep_corrected", [](const PyResult& p) { return p.r.sweep_corrected; },
          "every scan placed from the sensor's motion during its sweep (sensor.sweep_s)")
      .def_property_readonly("pose", [](const PyResult& p) { return PoseTuple(p.r.pose); })
      .def_property_readonly(
          "pose_correction", [](const PyResult& p) { return PoseTuple(p.r.pose_correction); },
          "alignment.scan_match: (x, y, yaw) from the input poses' frame to the map's")
      .def_property_readonly(
          "pose_matched", [](const PyResult& p) { return p.r.pose_matched; },
          "this scan's echoes corrected the heading (alignment.scan_match)")
      .def_property_readonly("sensor_pose",
                             [](const PyResult& p) { return PoseTuple(p.r.sensor_pose); })
      .def_property_readonly(
          "vehicle_cell",
          [](const PyResult& p) {
            return py::make_tuple(p.r.vehicle_cell.row, p.r.vehicle_cell.col);
          },
          "(row, col) of the sensor's cell")
      .def_property_readonly(
          "origin",
          [](const PyResult& p) { return py::make_tuple(p.r.origin.x(), p.r.origin.y()); },
          "world position (m) of the corner of cell (0, 0)")
      .def_property_readonly("filtered_speed_mps",
                             [](const PyResult& p) { return p.r.filtered_speed_mps; })
      .def_property_readonly(
          "polygon_status", [](const PyResult& p) { return ToString(p.r.polygon_status); },
          "'ok', 'no_free_space' or 'none'")
      .def_property_readonly(
          "polygon", [](const PyResult& p) { return Points2(p.r.polygon); },
          "(m, 2) float64, world metres, counter-clockwise; (0, 2) unless ok")
      .def_property_readonly(
          "polygon_cells", [](const PyResult& p) { return Points2(p.r.polygon_cells); },
          "(m, 2) float64, map cells (x = column, y = row)")
      .def_property_readonly(
          "edge_cells", [](const PyResult& p) { return Cells(p.r.edge_cells); },
          "(k, 2) int32 (row, col): C_Edge in label order")
      .def_property_readonly("simplification_error_m",
                             [](const PyResult& p) { return p.r.simplification_error_m; })
      .def_property_readonly("polygon_contains_vehicle",
                             [](const PyResult& p) { return p.r.polygon_contains_vehicle; })
      .def_property_readonly("stats", [](const PyResult& p) { return StatsDict(p.r.stats); })
      .def_property_readonly(
          "times", [](const PyResult& p) { return TimesDict(p.r.times); }, "microseconds per stage")
      .def("__repr__", [](const PyResult& p) {
        return "<freespace.Result scan " + std::to_string(p.r.scan_index) + ": " +
               ToString(p.r.status) + ", polygon " + ToString(p.r.polygon_status) + " with " +
               std::to_string(p.r.polygon.size()) + " vertices>";
      });
}

}  // namespace

// The estimator as Python holds it: the engine's Estimator, the scan buffer the points are
// converted into (allocated once), a lock for callers on several threads, and the occupancy
// table.
class PyEstimator {
 public:
  explicit PyEstimator(const Config& config) : estimator_(std::make_unique<Estimator>(config)) {}

  PyResult ProcessScan(const Scan& scan) {
    std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
    PyResult out;
    py::gil_scoped_release release;
    lock.lock();
    Run(scan, &out);
    return out;
  }

  PyResult ProcessCycle(const std::vector<Scan>& cycle) {
    std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
    PyResult out;
    py::gil_scoped_release release;
    lock.lock();
    const Clock::time_point a = Clock::now();
    const Result& r = estimator_->ProcessCycle(cycle);
    last_call_us_ = std::chrono::duration<double, std::micro>(Clock::now() - a).count();
    out.r = r;
    return out;
  }

  PyResult ProcessPoints(const py::array& points, const py::object& pose, double t) {
    std::unique_lock<std::mutex> lock(mutex_, std::defer_lock);
    {
      py::gil_scoped_release release;
      lock.lock();
    }
    FillPoints(points, &scan_.points);
    scan_.pose = ToPose(pose);
    scan_.timestamp_s = t;
    PyResult out;
    py::gil_scoped_release release;
    Run(scan_, &out);
    return out;
  }

  PyMap Map(const py::object& self, bool copy) {
    MapView v;
    {
      py::gil_scoped_release release;
      std::lock_guard<std::mutex> lock(mutex_);
      v = estimator_->map();
    }
    PyMap m;
    m.width = v.width;
    m.height = v.height;
    m.resolution_m = v.resolution_m;
    m.map_yaw = v.map_yaw;
    m.origin = v.origin;
    m.log_odds = View(v.log_odds, v.height, v.width, self);
    m.free = View(v.free, v.height, v.width, self);
    if (copy) {
      m.log_odds = m.log_odds.attr("copy")();
      m.free = m.free.attr("copy")();
    }
    return m;
  }

  Estimator& estimator() { return *estimator_; }
  double last_call_us() const { return last_call_us_; }
  void Reset() {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(mutex_);
    estimator_->Reset();
  }

 private:
  // Runs Process on `scan` and copies its result; the GIL is released, mutex_ held.
  void Run(const Scan& scan, PyResult* out) {
    const Clock::time_point a = Clock::now();
    const Result& r = estimator_->Process(scan);
    last_call_us_ = std::chrono::duration<double, std::micro>(Clock::now() - a).count();
    out->r = r;
  }

  std::unique_ptr<Estimator> estimator_;
  Scan scan_;
  std::mutex mutex_;
  double last_call_us_ = 0.0;
};

namespace {

// 0..100 (percent occupied, rounded) for an observed cell, -1 for an unknown one (log-odds 0).
py::array Occupancy(PyMap& m) {
  static const std::array<std::int8_t, 65536> table = [] {
    std::array<std::int8_t, 65536> t{};
    for (int l = -32768; l <= 32767; ++l) {
      const double p = 1.0 / (1.0 + std::exp(-double(l) / kLogOddsScale));
      t[std::size_t(l + 32768)] = l == 0 ? std::int8_t(-1) : std::int8_t(std::lround(100.0 * p));
    }
    return t;
  }();
  if (m.occupancy_cache) return m.occupancy_cache;
  const auto l = py::array_t<LogOdds, py::array::c_style>::ensure(m.log_odds);
  py::array_t<std::int8_t> out({py::ssize_t(m.height), py::ssize_t(m.width)});
  std::int8_t* o = out.mutable_data();
  const LogOdds* src = l.data();
  const std::size_t n = std::size_t(m.width) * m.height;
  for (std::size_t i = 0; i < n; ++i) o[i] = table[std::size_t(src[i] + 32768)];
  m.occupancy_cache = out;
  return out;
}

}  // namespace

void BindEstimator(py::module_& m) {
  BindScanAndResult(m);
  py::class_<PyMap>(m, "Map",
                    "The map after the last process(): rows run south to north (row 0 at the "
                    "smallest world y), columns west to east.")
      .def_readonly("width", &PyMap::width)
      .def_readonly("height", &PyMap::height)
      .def_readonly("resolution_m", &PyMap::resolution_m)
      .def_readonly("map_yaw", &PyMap::map_yaw)
      .def_property_readonly(
          "origin", [](const PyMap& p) { return py::make_tuple(p.origin.x(), p.origin.y()); },
          "world position (m) of the corner of cell (0, 0)")
      .def_readonly("log_odds", &PyMap::log_odds,
                    "(height, width) int16, value / 256 = ln(p / (1 - p)); read-only")
      .def_readonly("free", &PyMap::free, "(height, width) uint8, 1 where free after opening")
      .def_property_readonly("occupancy", &Occupancy,
                             "(height, width) int8: percent occupied 0..100, -1 unknown (a new "
                             "array computed from log_odds)");

  py::class_<PyEstimator>(m, "Estimator", "The engine: one process() call per full scan.")
      .def(py::init([](const PyConfig& c) { return std::make_unique<PyEstimator>(c.config); }),
           py::arg("config") = PyConfig{},
           "Validates the config (ConfigError) and creates its backend (BackendError).")
      .def(
          "process", [](PyEstimator& e, const PyScan& s) { return e.ProcessScan(s.scan); },
          py::arg("scan"), "Processes a freespace.Scan (from a reader or the simulator).")
      .def(
          "process_cycle",
          [](PyEstimator& e, const std::vector<PyScan>& scans) {
            std::vector<Scan> cycle;
            cycle.reserve(scans.size());
            for (const PyScan& s : scans) cycle.push_back(s.scan);
            return e.ProcessCycle(cycle);
          },
          py::arg("scans"),
          "Processes one cycle of a rig (the config's sensors list): a list of freespace.Scan, "
          "at most one per sensor (Scan.sensor), each at its own time and pose.")
      .def("process", &PyEstimator::ProcessPoints, py::arg("points"), py::arg("pose"), py::arg("t"),
           "Processes one full scan: points (n, 4) (layer, angle rad, range m, echo 0/1) or a "
           "structured array with those fields, the vehicle pose (x, y, yaw) in world metres and "
           "radians, the time in seconds. The GIL is released while the engine runs.")
      .def(
          "map",
          [](py::object self, bool copy) { return self.cast<PyEstimator&>().Map(self, copy); },
          py::arg("copy") = false,
          "The map after the last process(). Without copy, log_odds and free are read-only "
          "views of the estimator's buffers, valid until the next process(), reset() or "
          "map() (docs/python.md: which backend copies what).")
      .def("reset", &PyEstimator::Reset, "Clears the map; the next scan starts a new one.")
      .def_property_readonly("config",
                             [](PyEstimator& e) { return PyConfig{e.estimator().config()}; })
      .def_property_readonly("backend_name",
                             [](PyEstimator& e) { return e.estimator().backend_name(); })
      .def_property_readonly("last_call_us", &PyEstimator::last_call_us,
                             "wall time of the last process()'s C++ Process call, microseconds");
}

}  // namespace freespace::python

namespace freespace::python {

MapView PyMap::View() const {
  MapView v;
  v.width = width;
  v.height = height;
  v.resolution_m = resolution_m;
  v.origin = origin;
  v.map_yaw = map_yaw;
  const auto l = py::array_t<LogOdds, py::array::c_style>::ensure(log_odds);
  const auto f = py::array_t<std::uint8_t, py::array::c_style>::ensure(free);
  // Both are C-contiguous already (views of the estimator's rows, or their copies), so ensure()
  // returns them and the pointers stay valid while this PyMap holds them.
  if (!l || !f || l.ptr() != log_odds.ptr() || f.ptr() != free.ptr()) {
    throw py::value_error("Map: log_odds and free must be C-contiguous int16 and uint8 arrays");
  }
  v.log_odds = l.data();
  v.free = f.data();
  return v;
}

}  // namespace freespace::python
