// The full pipeline, one Estimator::Process() per iteration, per backend and map size, on real
// logs: the Intel lab (180-beam SICK, replayed in order) and a KITTI frame cut into a
// ScaLa-like 4-layer scan (repeated with advancing time). BM_OpenClWait*: the OpenCL backend
// with each backend.opencl_wait. BM_Paced*: as BM_Pipeline*, but the scans come gap_ms apart, as
// from a sensor, instead of back to back (the gap is not timed).
#include <chrono>
#include <cstdlib>
#include <thread>

#include "bench_util.hpp"

namespace freespace::bench {
namespace {

void RunPipeline(benchmark::State& state, const std::string& log, bool indoor, std::int64_t backend,
                 OpenClWait wait, int gap_ms = 0) {
  SensorConfig sensor;
  const std::vector<Scan> scans = LoadScans(log, &sensor);
  if (scans.empty()) {
    state.SkipWithError(("recorded data not found: " + log).c_str());
    return;
  }
  // The indoor logs with the indoor settings (configs/indoor.yaml), the rest with the defaults.
  Config config = indoor ? LoadProjectConfig("indoor.yaml") : Config();
  config.backend = BenchBackend(backend);
  config.backend.opencl_wait = wait;
  // FREESPACE_BENCH_THREADS: TBB worker threads (backend.threads; unset or 0 = all cores).
  if (const char* env = std::getenv("FREESPACE_BENCH_THREADS")) {
    config.backend.threads = std::atoi(env);
  }
  const int cells = int(state.range(1));
  config.map.width_cells = config.map.height_cells = cells;
  config.sensor = sensor;
  std::unique_ptr<Estimator> estimator;
  try {
    estimator = std::make_unique<Estimator>(config);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  std::string label =
      estimator->backend_name() + " " + std::to_string(cells) + "x" + std::to_string(cells);
  if (config.backend.kind == BackendKind::kOpenCl) label += std::string(" wait ") + ToString(wait);
  state.SetLabel(label);
  std::size_t next = 0;
  double t = 0.0;
  StageTimes sum;
  // A paced run times few scans: the first ones (buffers sized, the device's first commands)
  // run before it, untimed.
  for (; gap_ms > 0 && next < 3 && next < scans.size(); ++next) {
    Scan scan = scans[next];
    if (scans.size() == 1) scan.timestamp_s = (t += 0.04);
    estimator->Process(scan);
  }
  for (auto _ : state) {
    Scan scan = scans[next % scans.size()];
    if (scans.size() == 1) scan.timestamp_s = (t += 0.04);
    if (next > 0 && next % scans.size() == 0 && scans.size() > 1) {
      state.PauseTiming();
      estimator->Reset();  // the log starts over
      state.ResumeTiming();
    }
    if (gap_ms > 0) {
      // Between two scans of a sensor the backend's threads go idle (TBB's workers stop
      // spinning, PoCL's go to sleep), and the caches serve whatever else runs.
      state.PauseTiming();
      std::this_thread::sleep_for(std::chrono::milliseconds(gap_ms));
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

constexpr const char* kIntel = "carmen/intel-corrected.log";
constexpr const char* kKitti = "kitti/kitti_00_000000.bin";

// The default config (OpenCL waits as `auto` does); backend 0 TBB, 1 OpenCL, 2 OpenCL on PoCL's
// basic device, 3 split over two basic devices (BenchBackend).
void BM_PipelineIntel(benchmark::State& state) {
  RunPipeline(state, kIntel, true, state.range(0), OpenClWait::kAuto);
}
void BM_PipelineKitti(benchmark::State& state) {
  RunPipeline(state, kKitti, false, state.range(0), OpenClWait::kAuto);
}

// Scans gap_ms apart (arg 2), backend as above.
void BM_PacedIntel(benchmark::State& state) {
  RunPipeline(state, kIntel, true, state.range(0), OpenClWait::kAuto, int(state.range(2)));
}
void BM_PacedKitti(benchmark::State& state) {
  RunPipeline(state, kKitti, false, state.range(0), OpenClWait::kAuto, int(state.range(2)));
}

// The OpenCL backend (BenchBackend 1) per backend.opencl_wait: 0 auto, 1 block, 2 spin.
void BM_OpenClWaitIntel(benchmark::State& state) {
  RunPipeline(state, kIntel, true, 1, OpenClWait(state.range(0)));
}
void BM_OpenClWaitKitti(benchmark::State& state) {
  RunPipeline(state, kKitti, false, 1, OpenClWait(state.range(0)));
}

void Sizes(benchmark::internal::Benchmark* b) {
  for (const int backend : {0, 1, 2, 3}) {
    for (const int cells : {300, 1500}) b->Args({backend, cells});
  }
  b->ArgNames({"backend", "cells"})->Unit(benchmark::kMicrosecond);
}

// 10 ms apart: a scanner at up to 100 Hz. A fixed number of scans, since the untimed gaps
// would otherwise stretch a run to minutes.
void PacedSizes(benchmark::internal::Benchmark* b) {
  for (const int backend : {0, 1, 2, 3}) {
    for (const int cells : {300, 1500}) b->Args({backend, cells, 10});
  }
  b->ArgNames({"backend", "cells", "gap_ms"})->Unit(benchmark::kMicrosecond)->Iterations(100);
}

void Waits(benchmark::internal::Benchmark* b) {
  for (const int wait : {0, 1, 2}) {
    for (const int cells : {300, 1500}) b->Args({wait, cells});
  }
  b->ArgNames({"wait", "cells"})->Unit(benchmark::kMicrosecond);
}

BENCHMARK(BM_PipelineIntel)->Apply(Sizes);
BENCHMARK(BM_PipelineKitti)->Apply(Sizes);
BENCHMARK(BM_PacedIntel)->Apply(PacedSizes);
BENCHMARK(BM_PacedKitti)->Apply(PacedSizes);
BENCHMARK(BM_OpenClWaitIntel)->Apply(Waits);
BENCHMARK(BM_OpenClWaitKitti)->Apply(Waits);

}  // namespace
}  // namespace freespace::bench
