// The full pipeline, one Estimator::Process() per iteration, per backend and map size, on real
// logs: the Intel lab (180-beam SICK, replayed in order) and a KITTI frame cut into a
// ScaLa-like 4-layer scan (repeated with advancing time).
#include <cstdlib>

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
  // FREESPACE_BENCH_THREADS: TBB worker threads (backend.threads; unset or 0 = all cores).
  if (const char* env = std::getenv("FREESPACE_BENCH_THREADS")) {
    config.backend.threads = std::atoi(env);
  }
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
  StageTimes sum;
  for (auto _ : state) {
    Scan scan = scans[next % scans.size()];
    if (scans.size() == 1) scan.timestamp_s = (t += 0.04);
    if (next > 0 && next % scans.size() == 0 && scans.size() > 1) {
      state.PauseTiming();
      estimator->Reset();  // the log starts over
      state.ResumeTiming();
    }
    const Result& r = estimator->Process(scan);
    benchmark::DoNotOptimize(r.polygon.data());
    sum.preprocess_us += r.times.preprocess_us;
    sum.align_us += r.times.align_us;
    sum.rasterize_us += r.times.rasterize_us;
    sum.fuse_us += r.times.fuse_us;
    sum.classify_us += r.times.classify_us;
    sum.insight_us += r.times.insight_us;
    sum.polygon_us += r.times.polygon_us;
    ++next;
  }
  state.counters["points"] = double(scans[0].points.size());
  // Mean time of each stage per scan (Result::times), microseconds.
  const auto mean = [&](double us) {
    return benchmark::Counter(us, benchmark::Counter::kAvgIterations);
  };
  state.counters["pre"] = mean(sum.preprocess_us);
  state.counters["align"] = mean(sum.align_us);
  state.counters["raster"] = mean(sum.rasterize_us);
  state.counters["fuse"] = mean(sum.fuse_us);
  state.counters["classify"] = mean(sum.classify_us);
  state.counters["insight"] = mean(sum.insight_us);
  state.counters["poly"] = mean(sum.polygon_us);
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
