// The polygon stage and the pipeline of the road setup (configs/scala.yaml: the conservative
// polygon with its margin) against the paper's polygon, on simulated drives (urban, highway,
// parking), per map size, TBB backend. One scan per iteration, replayed in order from the drive's
// start (the first scans of a pass, while the map fills, untimed). The reported time is the
// stage's own (Result::times, UseManualTime): BM_DrivePolygon times the polygon stage alone (the
// host's work after the border rays), BM_DrivePipeline the whole Estimator::Process(); counters:
// the mean mask (stage 3b) and border-ray (stage 4) times. BM_DrivePair times both setups in
// turn in one loop, for their ratios; BM_DriveLayers the road setup with and without each of its
// layers, for what each costs.
#include <map>
#include <memory>

#include "bench_util.hpp"
#include "sim/simulator.hpp"

namespace freespace::bench {
namespace {

constexpr const char* kScenarios[] = {"urban", "highway", "parking"};
constexpr int kScans = 400;  // of each drive
constexpr int kWarmUp = 25;  // untimed scans at the start of each pass

// The first kScans scans of a scenario's drive (seed 1), simulated once.
const std::vector<Scan>& DriveScans(int scenario, SensorConfig* sensor) {
  static std::map<int, std::pair<std::vector<Scan>, SensorConfig>> drives;
  auto& drive = drives[scenario];
  if (drive.first.empty()) {
    sim::SimulationOptions options;
    options.scenario = kScenarios[scenario];
    options.seed = 1;
    sim::Simulation simulation(options);
    Scan scan;
    while (int(drive.first.size()) < kScans && simulation.Next(&scan)) drive.first.push_back(scan);
    drive.second = simulation.truth().scanner.EngineSensor();
  }
  *sensor = drive.second;
  return drive.first;
}

// `estimator` from a fresh map through the drive's first kWarmUp scans (untimed).
void WarmUp(Estimator* estimator, const std::vector<Scan>& scans) {
  estimator->Reset();
  for (int i = 0; i < kWarmUp; ++i) estimator->Process(scans[std::size_t(i)]);
}

// The road setup (configs/scala.yaml) or, with `paper`, its paper-shape polygon without margin,
// face or mover layer, for `sensor` on a map of `cells` x `cells`.
Config DriveConfig(bool paper, const SensorConfig& sensor, int cells) {
  Config config = LoadProjectConfig("scala.yaml");
  config.sensor = sensor;
  config.map.width_cells = config.map.height_cells = cells;
  if (paper) {
    config.polygon.shape = PolygonShape::kPaper;
    config.polygon.margin_cells = 0;
    config.polygon.face_tolerance_m = 0.0;
    config.polygon.mover_memory_s = 0.0;
  }
  return config;
}

// Args: shape (0 paper, 1 the road setup's conservative polygon), scenario, map side.
void RunDrive(benchmark::State& state, bool polygon_only) {
  SensorConfig sensor;
  const std::vector<Scan>& scans = DriveScans(int(state.range(1)), &sensor);
  const Config config = DriveConfig(state.range(0) == 0, sensor, int(state.range(2)));
  Estimator estimator(config);
  state.SetLabel(std::string(kScenarios[state.range(1)]) + " " + ToString(config.polygon.shape) +
                 " " + std::to_string(state.range(2)) + "x" + std::to_string(state.range(2)));
  std::size_t next = 0;
  double mask = 0.0, insight = 0.0;
  for (auto _ : state) {
    if (next % scans.size() == 0) {
      WarmUp(&estimator, scans);
      next = kWarmUp;
    }
    const Result& r = estimator.Process(scans[next++ % scans.size()]);
    benchmark::DoNotOptimize(r.polygon.data());
    state.SetIterationTime((polygon_only ? r.times.polygon_us : r.times.total_us) * 1e-6);
    mask += r.times.mask_us;
    insight += r.times.insight_us;
  }
  state.counters["mask"] = benchmark::Counter(mask, benchmark::Counter::kAvgIterations);
  state.counters["insight"] = benchmark::Counter(insight, benchmark::Counter::kAvgIterations);
}

void BM_DrivePolygon(benchmark::State& state) { RunDrive(state, true); }
void BM_DrivePipeline(benchmark::State& state) { RunDrive(state, false); }

// Both setups on the same scans in turn, one scan each an iteration (args: scenario, map side):
// counters `paper` and `inside` (pipeline medians, us), `ratio`, and the polygon stage's
// `polygon_paper`, `polygon_inside` and `polygon_ratio`, taken in the same minutes.
void BM_DrivePair(benchmark::State& state) {
  SensorConfig sensor;
  const std::vector<Scan>& scans = DriveScans(int(state.range(0)), &sensor);
  Estimator paper(DriveConfig(true, sensor, int(state.range(1))));
  Estimator inside(DriveConfig(false, sensor, int(state.range(1))));
  Estimator* estimators[2] = {&paper, &inside};
  state.SetLabel(std::string(kScenarios[state.range(0)]) + " " + std::to_string(state.range(1)) +
                 "x" + std::to_string(state.range(1)));
  std::size_t next = 0;
  PairedTimes pipeline, polygon;
  for (auto _ : state) {
    if (next % scans.size() == 0) {
      for (Estimator* e : estimators) WarmUp(e, scans);
      next = kWarmUp;
    }
    const Scan& scan = scans[next++ % scans.size()];
    const Result& a = paper.Process(scan);
    const double a_total = a.times.total_us, a_polygon = a.times.polygon_us;
    const Result& b = inside.Process(scan);
    benchmark::DoNotOptimize(b.polygon.data());
    pipeline.Add(a_total, b.times.total_us);
    polygon.Add(a_polygon, b.times.polygon_us);
    state.SetIterationTime((a_total + b.times.total_us) * 1e-6);
  }
  pipeline.Publish(state, "paper", "inside");
  polygon.Publish(state, "polygon_paper", "polygon_inside", "polygon_ratio");
}

// The road setup less one of its layers (not in the paper): 0 the mover layer, 1 the face
// layer, 2 the margin; 3 less all three.
Config WithoutLayer(Config config, int layer) {
  if (layer == 0 || layer == 3) config.polygon.mover_memory_s = 0.0;
  if (layer == 1 || layer == 3) config.polygon.face_tolerance_m = 0.0;
  if (layer == 2 || layer == 3) config.polygon.margin_cells = 0;
  return config;
}

// What each layer of the road setup costs: the paper setup, the road setup and the road setup
// less each layer and less all three (WithoutLayer()), on the same scans in turn, one scan each
// an iteration (args: scenario, map side). Counters: the pipeline medians (us) `paper`, `road`,
// `no_movers`, `no_faces`, `no_margin` and `no_layers`; `ratio` (road / paper); what each layer
// adds to the road setup's median, `movers`, `faces` and `margin`; and what the conservative
// polygon without them adds to the paper setup's, `polygon`.
void BM_DriveLayers(benchmark::State& state) {
  SensorConfig sensor;
  const std::vector<Scan>& scans = DriveScans(int(state.range(0)), &sensor);
  const int cells = int(state.range(1));
  const Config road = DriveConfig(false, sensor, cells);
  std::vector<std::unique_ptr<Estimator>> setups;
  setups.push_back(std::make_unique<Estimator>(DriveConfig(true, sensor, cells)));
  setups.push_back(std::make_unique<Estimator>(road));
  for (int layer = 0; layer < 4; ++layer)
    setups.push_back(std::make_unique<Estimator>(WithoutLayer(road, layer)));
  state.SetLabel(std::string(kScenarios[state.range(0)]) + " " + std::to_string(cells) + "x" +
                 std::to_string(cells));
  std::vector<std::vector<double>> times(setups.size());
  std::size_t next = 0;
  for (auto _ : state) {
    if (next % scans.size() == 0) {
      for (const auto& e : setups) WarmUp(e.get(), scans);
      next = kWarmUp;
    }
    const Scan& scan = scans[next++ % scans.size()];
    double total = 0.0;
    for (std::size_t k = 0; k < setups.size(); ++k) {
      const Result& r = setups[k]->Process(scan);
      benchmark::DoNotOptimize(r.polygon.data());
      times[k].push_back(r.times.total_us);
      total += r.times.total_us;
    }
    state.SetIterationTime(total * 1e-6);
  }
  const char* names[] = {"paper", "road", "no_movers", "no_faces", "no_margin", "no_layers"};
  const char* layers[] = {"movers", "faces", "margin"};
  std::vector<double> median(setups.size());
  for (std::size_t k = 0; k < setups.size(); ++k) {
    median[k] = Median(times[k]);
    state.counters[names[k]] = median[k];
  }
  state.counters["ratio"] = median[0] > 0 ? median[1] / median[0] : 0.0;
  for (int layer = 0; layer < 3; ++layer)
    state.counters[layers[layer]] = median[1] - median[2 + layer];
  state.counters["polygon"] = median[5] - median[0];
}

void Drives(benchmark::internal::Benchmark* b) {
  for (const int cells : {300, 1500}) {
    for (const int scenario : {0, 1, 2}) {
      for (const int shape : {0, 1}) b->Args({shape, scenario, cells});
    }
  }
  b->ArgNames({"shape", "scenario", "cells"})->UseManualTime()->Unit(benchmark::kMicrosecond);
}

BENCHMARK(BM_DrivePolygon)->Apply(Drives);
BENCHMARK(BM_DrivePipeline)->Apply(Drives);
BENCHMARK(BM_DrivePair)
    ->ArgsProduct({{0, 1, 2}, {300, 1500}})
    ->ArgNames({"scenario", "cells"})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DriveLayers)
    ->ArgsProduct({{0, 1, 2}, {300}})
    ->ArgNames({"scenario", "cells"})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace freespace::bench
