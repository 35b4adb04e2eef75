// The full pipeline, one Estimator::Process() per iteration, per backend and map size, on real
// logs: the Intel lab (180-beam SICK, replayed in order) and a KITTI frame cut into a
// ScaLa-like 4-layer scan (repeated with advancing time).
#include "bench_util.hpp"

namespace freespace::bench {
namespace {

void RunPipeline(benchmark::State& state, const std::string& log, bool indoor) {
  SensorConfig sensor;
  const std::vector<Scan> scans = LoadScans(log, &sensor);
  if (scans.empty()) {
    state.SkipWithError(("recorded data not found: " + log).c_str());
    return;
  }
  Config config;
  config.backend.kind = BackendKind(state.range(0));
  config.map.width_cells = config.map.height_cells = int(state.range(1));
  config.sensor = sensor;
  if (indoor) config.classify.vehicle_width_m = 0.4;
  std::unique_ptr<Estimator> estimator;
  try {
    estimator = std::make_unique<Estimator>(config);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  state.SetLabel(estimator->backend_name() + " " + std::to_string(state.range(1)) + "x" +
                 std::to_string(state.range(1)));
  std::size_t next = 0;
  double t = 0.0;
  for (auto _ : state) {
    Scan scan = scans[next % scans.size()];
    if (scans.size() == 1) scan.timestamp_s = (t += 0.04);
    if (next > 0 && next % scans.size() == 0 && scans.size() > 1) {
      state.PauseTiming();
      estimator->Reset();  // the log starts over
      state.ResumeTiming();
    }
    benchmark::DoNotOptimize(estimator->Process(scan).polygon.data());
    ++next;
  }
  state.counters["points"] = double(scans[0].points.size());
}

void BM_PipelineIntel(benchmark::State& state) {
  RunPipeline(state, "carmen/intel-corrected.log", true);
}
void BM_PipelineKitti(benchmark::State& state) {
  RunPipeline(state, "kitti/kitti_00_000000.bin", false);
}

void Sizes(benchmark::internal::Benchmark* b) {
  for (const int backend : {0, 1}) {
    for (const int cells : {300, 1500}) b->Args({backend, cells});
  }
  b->ArgNames({"backend", "cells"})->Unit(benchmark::kMicrosecond);
}

BENCHMARK(BM_PipelineIntel)->Apply(Sizes);
BENCHMARK(BM_PipelineKitti)->Apply(Sizes);

}  // namespace
}  // namespace freespace::bench
