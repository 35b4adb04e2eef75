// One benchmark per kernel stage, per backend and map size, on a real ScaLa-like scan (a KITTI
// frame cut to 4 layers and 145 deg). Arguments: backend (0 tbb, 1 opencl, 2 opencl on PoCL's basic
// device: BenchBackend), map side in cells. Each iteration ends with Backend::Finish(), so an
// asynchronous backend is timed to the end of its work, not to the end of enqueueing it; that wall
// time includes its per-call latency (waking the device, the final wait). Where the backend
// measures itself (OpenCL event profiling), the counter device_us is the stage's mean device time,
// outside the timed region.
#include "bench_util.hpp"
#include "core/inside_polygon.hpp"
#include "core/movers.hpp"
#include "core/simplifier.hpp"

namespace freespace::bench {
namespace {

// The recorded scan and map at `cells` x `cells`, or null with the benchmark skipped and why.
std::unique_ptr<StageInput> StageInputOrSkip(benchmark::State& state, int cells) {
  auto input = MakeStageInput(cells);
  if (!input) state.SkipWithError("recorded data not found (set FREESPACE_DATA_DIR)");
  return input;
}

// Sets up the backend with the realistic map; skips the benchmark when it cannot run.
struct Stage {
  std::unique_ptr<StageInput> input;
  std::unique_ptr<Backend> backend;
  bool Ready(benchmark::State& state) {
    input = StageInputOrSkip(state, int(state.range(1)));
    if (!input) return false;
    std::string why;
    backend = MakeBackend(BenchBackend(state.range(0)), input->params, &why);
    if (!backend) {
      state.SkipWithError(("backend unavailable: " + why).c_str());
      return false;
    }
    backend->WriteLogOdds(input->map.data());
    state.SetLabel(backend->name() + " " + std::to_string(state.range(1)) + "x" +
                   std::to_string(state.range(1)));
    return true;
  }

  // Adds the backend's own time of the stage `field` of the last iteration, if it has one.
  void Collect(benchmark::State& state, double StageTimes::*field) {
    if (state.range(0) == 0) return;  // TBB
    state.PauseTiming();
    StageTimes times;
    if (backend->KernelTimes(&times)) {
      device_us += times.*field;
      ++device_n;
    }
    state.ResumeTiming();
  }
  void Report(benchmark::State& state) const {
    if (device_n > 0) state.counters["device_us"] = device_us / device_n;
  }

  double device_us = 0.0;
  int device_n = 0;
};

void BM_Rasterize(benchmark::State& state) {
  Stage s;
  if (!s.Ready(state)) return;
  for (auto _ : state) {
    s.backend->Rasterize(s.input->job);
    s.backend->Finish();
    s.Collect(state, &StageTimes::rasterize_us);
  }
  s.Report(state);
}

// The same scan with sensor_model.free_on_outline off: the outline's cells cleared as well.
void BM_RasterizeOutline(benchmark::State& state) {
  Stage s;
  if (!s.Ready(state)) return;
  RasterJob job = s.input->job;
  job.clear_outline = true;
  for (auto _ : state) {
    s.backend->Rasterize(job);
    s.backend->Finish();
    s.Collect(state, &StageTimes::rasterize_us);
  }
  s.Report(state);
}

void BM_Fuse(benchmark::State& state) {
  Stage s;
  if (!s.Ready(state)) return;
  s.backend->Rasterize(s.input->job);
  for (auto _ : state) {
    s.backend->Fuse(s.input->job.row_begin, s.input->job.row_end);
    s.backend->Finish();
    s.Collect(state, &StageTimes::fuse_us);
  }
  s.Report(state);
}

void BM_Classify(benchmark::State& state) {
  Stage s;
  if (!s.Ready(state)) return;
  for (auto _ : state) {
    s.backend->Classify();
    s.backend->Finish();
    s.Collect(state, &StageTimes::classify_us);
  }
  s.Report(state);
}

void BM_InSight(benchmark::State& state) {
  Stage s;
  if (!s.Ready(state)) return;
  s.backend->Classify();
  std::vector<CellIndex> edges;
  edges.reserve(BorderLabelCount(s.input->params.height, s.input->params.width));
  for (auto _ : state) {
    s.backend->InSight(s.input->vehicle, &edges);
    s.Collect(state, &StageTimes::insight_us);
  }
  state.counters["edge_cells"] = double(edges.size());
  s.Report(state);
}

void BM_Shift(benchmark::State& state) {
  Stage s;
  if (!s.Ready(state)) return;
  int k = 0;
  for (auto _ : state) {
    ++k;
    s.backend->Shift(k % 2 ? 1 : -1, k % 2 ? -1 : 1);  // back and forth: the map stays full
    s.backend->Finish();
  }
}

// Host-only stages.
void BM_Preprocess(benchmark::State& state) {
  auto input = StageInputOrSkip(state, 300);
  if (!input) return;
  ScanStats stats;
  RasterJob job;
  for (auto _ : state) {
    input->preprocess->Run(input->scan, &stats);
    input->preprocess->Project(Vec2(150.4, 150.6), 0.3, 300, 300, &job);
  }
  state.counters["points"] = double(stats.points);
  state.counters["kept"] = double(stats.kept);
}

// The same from a preprocessor of the config with sensor.sweep_s 0 (argument 0) or 0.016 s, the
// ScaLa's (1): then each point is moved by the sensor's motion during the sweep (13 m/s,
// turning at 0.3 rad/s) before the projection.
void BM_PreprocessSweep(benchmark::State& state) {
  auto input = StageInputOrSkip(state, 300);
  if (!input) return;
  Config config = input->config;
  config.sensor.sweep_s = state.range(0) == 0 ? 0.0 : 0.016;
  Preprocessor preprocess(config);
  const SweepMotion motion{13.0, 0.0, 0.3};
  ScanStats stats;
  RasterJob job;
  for (auto _ : state) {
    preprocess.Run(input->scan, &stats);
    preprocess.Deskew(motion);
    preprocess.Project(Vec2(150.4, 150.6), 0.3, 300, 300, &job);
  }
  state.counters["points"] = double(stats.points);
  state.counters["kept"] = double(stats.kept);
}

// The projection of that scan from a preprocessor of the conservative polygon without the face
// layer (argument 0) and with it at 0.05 m (1): the difference is FaceCells().
void BM_ProjectFaces(benchmark::State& state) {
  auto input = StageInputOrSkip(state, 300);
  if (!input) return;
  Config config = input->config;
  config.polygon.shape = PolygonShape::kInside;
  config.polygon.face_tolerance_m = state.range(0) == 0 ? 0.0 : 0.05;
  Preprocessor preprocess(config);
  ScanStats stats;
  preprocess.Run(input->scan, &stats);
  RasterJob job;
  for (auto _ : state) {
    preprocess.Project(Vec2(150.4, 150.6), 0.3, 300, 300, &job);
    benchmark::DoNotOptimize(preprocess.face_near_cells().data());
  }
  state.counters["near"] = double(preprocess.face_near_cells().size());
  state.counters["beams"] = double(preprocess.beams().size());
}

// The mover layer's work on every scan (polygon.mover_memory_s): that scan's 581 beams, taken
// again every 40 ms from the same pose, compared with the outline of 0.2 s before (both
// detection passes, the runs) and the hazard of no mover: nothing moves. What followed vehicles
// add is in BM_DrivePipeline's highway case.
void BM_MoverObserve(benchmark::State& state) {
  auto input = StageInputOrSkip(state, 300);
  if (!input) return;
  Config config = input->config;
  config.polygon.shape = PolygonShape::kInside;
  config.polygon.mover_memory_s = 3.0;
  Preprocessor preprocess(config);
  ScanStats stats;
  preprocess.Run(input->scan, &stats);
  MoverTracker movers(MoverRule::Of(config));
  MapFrame frame;
  frame.width = frame.height = 300;
  std::vector<std::int32_t> hazard;
  double t = 0.0;
  for (auto _ : state) {
    t += 0.04;
    movers.BeginCycle(t);
    movers.Observe(0, Pose2D{1.0, 2.0, 0.3}, t, preprocess.beams());
    hazard.clear();
    movers.Hazard(t, frame, &hazard);
    benchmark::DoNotOptimize(hazard.data());
  }
  state.counters["beams"] = double(preprocess.beams().size());
  state.counters["movers"] = double(movers.movers());
}

// Deskew() alone on that scan's 2093 kept echoes and 581 beams (each iteration moves them again).
void BM_Deskew(benchmark::State& state) {
  auto input = StageInputOrSkip(state, 300);
  if (!input) return;
  Config config = input->config;
  config.sensor.sweep_s = 0.016;
  Preprocessor preprocess(config);
  ScanStats stats;
  preprocess.Run(input->scan, &stats);
  const SweepMotion motion{13.0, 0.0, 0.3};
  for (auto _ : state) {
    preprocess.Deskew(motion);
    benchmark::DoNotOptimize(preprocess.kept().data());
  }
  state.counters["points"] = double(preprocess.kept().size() + preprocess.beams().size());
}

void BM_Polygon(benchmark::State& state) {
  Stage s;
  if (!s.Ready(state)) return;
  s.backend->Classify();
  std::vector<CellIndex> edges;
  edges.reserve(BorderLabelCount(s.input->params.height, s.input->params.width));
  s.backend->InSight(s.input->vehicle, &edges);
  std::vector<Vec2> ring;
  for (const CellIndex& c : edges) ring.emplace_back(c.col + 0.5, c.row + 0.5);
  PolygonSimplifier simplifier(s.input->config.polygon.max_vertices,
                               s.input->config.polygon.epsilon_m / 0.2);
  std::vector<int> kept;
  const Vec2 vehicle(s.input->vehicle.col + 0.5, s.input->vehicle.row + 0.5);
  for (auto _ : state) simplifier.Simplify(ring, vehicle, &kept);
  state.counters["vertices"] = double(kept.size());
}

// backend: 0 TBB, 1 OpenCL, 2 OpenCL on PoCL's basic device, 3 on two of them (BenchBackend).
void Sizes(benchmark::internal::Benchmark* b) {
  for (const int backend : {0, 1, 2, 3}) {
    for (const int cells : {300, 1500}) b->Args({backend, cells});
  }
  b->ArgNames({"backend", "cells"})->Unit(benchmark::kMicrosecond);
}

BENCHMARK(BM_Preprocess)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PreprocessSweep)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Deskew)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ProjectFaces)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MoverObserve)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Rasterize)->Apply(Sizes);
BENCHMARK(BM_RasterizeOutline)->Apply(Sizes);
BENCHMARK(BM_Fuse)->Apply(Sizes);
BENCHMARK(BM_Classify)->Apply(Sizes);
BENCHMARK(BM_InSight)->Apply(Sizes);
BENCHMARK(BM_Shift)->Apply(Sizes);
BENCHMARK(BM_Polygon)
    ->Args({0, 300})
    ->Args({0, 1500})
    ->ArgNames({"backend", "cells"})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace freespace::bench
