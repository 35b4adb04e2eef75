// A rig's cycle against one sensor's scan: Estimator::ProcessCycle() on the first cycles of a
// simulated drive (seed 1) with the front rig (one scanner) and the surround rig (four), the road
// setup (configs/scala.yaml), host backend. The time of each cycle is the estimator's own
// (Result::times.total_us, UseManualTime); the cycles are simulated once, before timing.
// BM_RigPair times both rigs in turn in one loop, for their ratio.
#include <algorithm>
#include <map>
#include <memory>
#include <vector>

#include "bench_util.hpp"
#include "sim/rig.hpp"
#include "sim/simulator.hpp"

namespace freespace::bench {
namespace {

constexpr const char* kScenarios[] = {"urban", "highway", "parking"};
constexpr const char* kRigs[] = {"front", "surround"};
constexpr int kCycles = 300;  // of each drive
constexpr int kWarmUp = 25;   // untimed cycles at the start of each pass

struct Drive {
  std::vector<std::vector<Scan>> cycles;
  sim::Rig rig;
};

const Drive& DriveCycles(int rig, int scenario) {
  static std::map<std::pair<int, int>, Drive> drives;
  Drive& drive = drives[{rig, scenario}];
  if (drive.cycles.empty()) {
    sim::SimulationOptions options;
    options.scenario = kScenarios[scenario];
    options.seed = 1;
    options.rig = kRigs[rig];
    sim::Simulation simulation(options);
    std::vector<Scan> cycle;
    while (int(drive.cycles.size()) < kCycles && simulation.NextCycle(&cycle)) {
      drive.cycles.push_back(cycle);
    }
    drive.rig = simulation.rig();
  }
  return drive;
}

// Args: rig (0 front, 1 surround), scenario, map side.
void BM_RigCycle(benchmark::State& state) {
  const Drive& drive = DriveCycles(int(state.range(0)), int(state.range(1)));
  Config config = sim::WithRig(LoadProjectConfig("scala.yaml"), drive.rig);
  config.backend = BenchBackend(0);
  config.map.width_cells = config.map.height_cells = int(state.range(2));
  Estimator estimator(config);
  state.SetLabel(std::string(kRigs[state.range(0)]) + " " + kScenarios[state.range(1)] + " " +
                 std::to_string(state.range(2)) + "x" + std::to_string(state.range(2)) + " " +
                 estimator.backend_name());
  const std::size_t n = drive.cycles.size();
  std::size_t next = 0;
  double preprocess = 0.0, update = 0.0;
  for (auto _ : state) {
    if (next % n == 0) {
      estimator.Reset();
      for (next = 0; next < kWarmUp; ++next) estimator.ProcessCycle(drive.cycles[next]);
    }
    const Result& r = estimator.ProcessCycle(drive.cycles[next++ % n]);
    benchmark::DoNotOptimize(r.polygon.data());
    state.SetIterationTime(r.times.total_us * 1e-6);
    preprocess += r.times.preprocess_us;
    update += r.times.rasterize_us + r.times.fuse_us;
  }
  state.counters["preprocess"] = benchmark::Counter(preprocess, benchmark::Counter::kAvgIterations);
  state.counters["update"] = benchmark::Counter(update, benchmark::Counter::kAvgIterations);
}

// The front and the surround rig's cycles of one scenario in turn, one of each an iteration:
// counters `front` and `surround` (medians, us) and `ratio`, taken in the same minutes.
void BM_RigPair(benchmark::State& state) {
  const int scenario = int(state.range(0));
  const Drive* drives[2] = {&DriveCycles(0, scenario), &DriveCycles(1, scenario)};
  std::vector<std::unique_ptr<Estimator>> estimators;
  for (const Drive* drive : drives) {
    Config config = sim::WithRig(LoadProjectConfig("scala.yaml"), drive->rig);
    config.backend = BenchBackend(0);
    estimators.push_back(std::make_unique<Estimator>(config));
  }
  state.SetLabel(std::string(kScenarios[scenario]) + " 300x300 " + estimators[0]->backend_name());
  const std::size_t n = std::min(drives[0]->cycles.size(), drives[1]->cycles.size());
  std::size_t next = 0;
  PairedTimes times;
  for (auto _ : state) {
    if (next % n == 0) {
      for (int k = 0; k < 2; ++k) {
        estimators[k]->Reset();
        for (int i = 0; i < kWarmUp; ++i) estimators[k]->ProcessCycle(drives[k]->cycles[i]);
      }
      next = kWarmUp;
    }
    double us[2];
    for (int k = 0; k < 2; ++k) {
      const Result& r = estimators[k]->ProcessCycle(drives[k]->cycles[next % n]);
      benchmark::DoNotOptimize(r.polygon.data());
      us[k] = r.times.total_us;
    }
    ++next;
    times.Add(us[0], us[1]);
    state.SetIterationTime((us[0] + us[1]) * 1e-6);
  }
  times.Publish(state, "front", "surround");
}

void Rigs(benchmark::internal::Benchmark* b) {
  for (const int scenario : {0, 2}) {
    for (const int rig : {0, 1}) b->Args({rig, scenario, 300});
  }
  b->ArgNames({"rig", "scenario", "cells"})->UseManualTime()->Unit(benchmark::kMicrosecond);
}

BENCHMARK(BM_RigCycle)->Apply(Rigs);
BENCHMARK(BM_RigPair)
    ->Arg(0)
    ->Arg(2)
    ->ArgName("scenario")
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace freespace::bench
