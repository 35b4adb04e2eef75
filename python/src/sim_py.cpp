// The simulator, its truth, the scorer and the drive evaluation of `freespace demo` and
// `freespace eval` (docs/metrics.md) for Python: freespace.Simulation (an iterator of scans),
// freespace.TruthScorer, ScanMetrics, MetricsSeries, StageSeries, evaluate_drive and
// seed_summary.
#include <pybind11/stl.h>

#include <cmath>
#include <memory>

#include "bindings.hpp"
#include "convert.hpp"
#include "eval/drive_eval.hpp"
#include "eval/scorer.hpp"
#include "sim/simulator.hpp"

namespace freespace::python {
namespace {

struct PySimulation {
  std::shared_ptr<sim::Simulation> sim;
};

// A drive's truth: read from a file, or a simulation's (which it keeps alive).
struct PyTruth {
  std::shared_ptr<const sim::Truth> truth;
};

struct PyScorer {
  std::shared_ptr<const sim::Truth> truth;  // outlives scorer
  std::unique_ptr<sim::TruthScorer> scorer;
};

sim::SimulationOptions SimOptions(const std::string& scenario, std::uint64_t seed,
                                  double duration_s, const std::string& odometry_noise,
                                  const py::object& rain, const py::object& ground) {
  sim::SimulationOptions o;
  o.scenario = scenario;
  o.seed = seed;
  o.duration_s = duration_s;
  o.odometry = sim::OdometryNoise::Preset(odometry_noise);
  if (!rain.is_none()) o.scanner.rain_probability = rain.cast<double>();
  if (!ground.is_none()) o.scanner.ground_echo_probability = ground.cast<double>();
  return o;
}

py::object SensorDict(const SensorConfig& sensor) {
  Config c;
  c.sensor = sensor;
  return ConfigToDict(c)["sensor"];
}

void BindSimulation(py::module_& m) {
  m.def("scenario_names", &sim::ScenarioNames, "The built-in scenarios: urban, highway, parking.");
  py::class_<PyTruth>(m, "Truth", "The exact truth of a simulated drive (docs/formats.md).")
      .def_property_readonly("scenario", [](const PyTruth& t) { return t.truth->scenario; })
      .def_property_readonly("seed", [](const PyTruth& t) { return t.truth->seed; })
      .def_property_readonly("scans", [](const PyTruth& t) { return t.truth->scans.size(); })
      .def_property_readonly(
          "sensor", [](const PyTruth& t) { return SensorDict(t.truth->scanner.EngineSensor()); });
  m.def(
      "read_truth",
      [](const std::string& path) {
        return PyTruth{std::make_shared<const sim::Truth>(sim::ReadTruth(path))};
      },
      py::arg("path"), "Reads a truth file (truth.json). Raises InputError.");

  py::class_<PySimulation>(m, "Simulation",
                           "A simulated drive of a built-in scenario: iterate it for its scans "
                           "(pose = the odometry); its truth grows scan by scan.")
      .def(py::init([](const std::string& scenario, std::uint64_t seed, double duration_s,
                       const std::string& odometry_noise, const py::object& rain,
                       const py::object& ground) {
             return PySimulation{std::make_shared<sim::Simulation>(
                 SimOptions(scenario, seed, duration_s, odometry_noise, rain, ground))};
           }),
           py::arg("scenario") = "urban", py::arg("seed") = 1, py::arg("duration_s") = 0.0,
           py::arg("odometry_noise") = "none", py::arg("rain_probability") = py::none(),
           py::arg("ground_echo_probability") = py::none(),
           "duration_s 0: the scenario's own; odometry_noise none, typical or poor. Raises "
           "ValueError for an unknown scenario or option.")
      .def("__iter__", [](py::object self) { return self; })
      .def("__next__",
           [](PySimulation& s) {
             PyScan scan;
             bool more = false;
             {
               py::gil_scoped_release release;
               more = s.sim->Next(&scan.scan);
             }
             if (!more) throw py::stop_iteration();
             return scan;
           })
      .def("__len__", [](const PySimulation& s) { return s.sim->scan_count(); })
      .def_property_readonly("scenario",
                             [](const PySimulation& s) { return s.sim->scenario().name; })
      .def_property_readonly("description",
                             [](const PySimulation& s) { return s.sim->scenario().description; })
      .def_property_readonly(
          "sensor",
          [](const PySimulation& s) { return SensorDict(s.sim->truth().scanner.EngineSensor()); },
          "The simulated scanner as a config section: config.with_overrides({'sensor': "
          "sim.sensor}).")
      .def_property_readonly("truth", [](const PySimulation& s) {
        return PyTruth{std::shared_ptr<const sim::Truth>(s.sim, &s.sim->truth())};
      });
}

void BindMetrics(py::module_& m) {
  py::class_<ScanMetrics>(m, "ScanMetrics", "The scores of one scan (docs/metrics.md).")
      .def_readonly("scan", &ScanMetrics::scan)
      .def_readonly("t", &ScanMetrics::t)
      .def_readonly("accuracy", &ScanMetrics::accuracy)
      .def_readonly("false_free_rate", &ScanMetrics::false_free_rate)
      .def_readonly("polygon_area_m2", &ScanMetrics::polygon_area_m2)
      .def_readonly("intrusion_m2", &ScanMetrics::intrusion_m2)
      .def_readonly("intrusion_moving_m2", &ScanMetrics::intrusion_moving_m2)
      .def_readonly("coverage", &ScanMetrics::coverage)
      .def_readonly("coverage_seen", &ScanMetrics::coverage_seen)
      .def(
          "to_dict", [](const ScanMetrics& s) { return ToPython(s.ToJson()); }, "Every field.");

  py::class_<MetricsSeries>(m, "MetricsSeries", "The scores of many scans and their summary.")
      .def(py::init<>())
      .def("add", &MetricsSeries::Add, py::arg("metrics"))
      .def("__len__", &MetricsSeries::size)
      .def(
          "summary", [](const MetricsSeries& s) { return ToPython(s.Summary()); },
          "{'accuracy': {'mean', 'min', 'pooled'}, 'intrusion_m2': {'mean', 'median', 'p95', "
          "'max'}, ...} (docs/metrics.md, Summary)");

  py::class_<StageSeries>(m, "StageSeries", "The stage times of many scans.")
      .def(py::init<>())
      .def(
          "add", [](StageSeries& s, const PyResult& r) { s.Add(r.r.times); }, py::arg("result"))
      .def("__len__", &StageSeries::size)
      .def(
          "summary", [](const StageSeries& s) { return ToPython(s.Summary()); },
          "{stage: {'median', 'p99'}} in microseconds")
      .def("quantile", &StageSeries::Quantile, py::arg("stage"), py::arg("q"));

  py::class_<PyScorer>(m, "TruthScorer", "Scores each scan of a drive against its truth.")
      .def(py::init([](const PyTruth& t) {
             PyScorer s;
             s.truth = t.truth;
             s.scorer = std::make_unique<sim::TruthScorer>(*s.truth);
             return s;
           }),
           py::arg("truth"))
      .def(
          "score",
          [](PyScorer& s, const PyMap& map, const PyResult& result) {
            const MapView view = map.View();
            py::gil_scoped_release release;
            return s.scorer->Score(s.scorer->Find(result.r.timestamp_s), view, result.r);
          },
          py::arg("map"), py::arg("result"),
          "Scores one scan: the estimator's map() and Result right after process(). Scans "
          "come in order. Raises InputError when the truth has no scan at the result's time.");
}

void BindDrives(py::module_& m) {
  py::class_<DriveEvaluation>(m, "DriveEvaluation", "One simulated drive's scores and stage times.")
      .def_readonly("scenario", &DriveEvaluation::scenario)
      .def_readonly("seed", &DriveEvaluation::seed)
      .def_readonly("rejected", &DriveEvaluation::rejected)
      .def_readonly("metrics", &DriveEvaluation::metrics)
      .def_readonly("times", &DriveEvaluation::times)
      .def_property_readonly("scans", [](const DriveEvaluation& d) { return d.metrics.size(); });

  m.def(
      "evaluate_drive",
      [](const PyConfig& config, const std::string& scenario, std::uint64_t seed, double duration_s,
         const std::string& odometry_noise, bool keep_sensor) {
        const sim::SimulationOptions o =
            SimOptions(scenario, seed, duration_s, odometry_noise, py::none(), py::none());
        py::gil_scoped_release release;
        return EvaluateDrive(o, config.config, keep_sensor);
      },
      py::arg("config"), py::arg("scenario") = "urban", py::arg("seed") = 1,
      py::arg("duration_s") = 0.0, py::arg("odometry_noise") = "none",
      py::arg("keep_sensor") = false,
      "Simulates a drive, runs an estimator of `config` on every scan and scores each against "
      "the truth (what `freespace eval --seeds` does per drive). The sensor comes from the "
      "drive's scanner unless keep_sensor. The GIL is released meanwhile.");
  m.def(
      "seed_summary",
      [](const std::vector<DriveEvaluation>& drives) { return ToPython(SeedSummary(drives)); },
      py::arg("drives"),
      "Per scenario: the means over seeds, the worst seed, the pooled figures and the aims "
      "(the table of `freespace eval --seeds`, docs/metrics.md).");
}

}  // namespace

void BindSim(py::module_& m) {
  BindSimulation(m);
  BindMetrics(m);
  BindDrives(m);
}

}  // namespace freespace::python
