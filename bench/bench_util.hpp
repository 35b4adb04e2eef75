// Inputs shared by the benchmarks: real scans from ../shared/data (a KITTI frame cut into a
// ScaLa-like 4-layer scan, and the Intel lab log), the engine state they produce, and the
// backends to compare.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/alignment.hpp"
#include "core/backend.hpp"
#include "core/preprocess.hpp"
#include "engine/backend_factory.hpp"
#include "freespace/freespace.hpp"

namespace freespace::bench {

// The recorded data folder (FREESPACE_DATA_DIR, else the one configured at build time).
std::string DataDir();

// All scans of a log, or an empty vector when the file is absent.
std::vector<Scan> LoadScans(const std::string& relative_path, SensorConfig* sensor);

// The engine state of a real multi-layer scan on a map of `cells` x `cells` at 0.2 m: the
// config, the preprocessed scan and its raster job, ready for single-stage benchmarks.
struct StageInput {
  Config config;
  KernelParams params;
  Scan scan;
  std::unique_ptr<Preprocessor> preprocess;
  RasterJob job;
  CellIndex vehicle;
  std::vector<LogOdds> map;  // after a few fused scans: realistic free / occupied / unknown
};

// Builds the StageInput from the KITTI frame; null when the data is absent.
std::unique_ptr<StageInput> MakeStageInput(int cells);

// The backends the benchmarks compare, by their `backend` argument:
//   0  TBB;
//   1  OpenCL on the device the engine's rule takes, except that where PoCL lists its pthread
//      device (a worker pool) that one is taken;
//   2  OpenCL on PoCL's basic device (the kernels run on the thread that enqueues them); a case
//      says why it cannot run where PoCL does not list it;
//   3  as 2, split over two basic devices (opencl_devices: 2), where PoCL lists two.
// FREESPACE_OPENCL_PLATFORM / FREESPACE_OPENCL_DEVICE replace these filters, as in the engine.
BackendConfig BenchBackend(std::int64_t arg);

// Creates the backend of `config`; null (with the reason) when it cannot run here.
std::unique_ptr<Backend> MakeBackend(const BackendConfig& config, const KernelParams& params,
                                     std::string* why);

}  // namespace freespace::bench
