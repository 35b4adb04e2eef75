// Inputs shared by the benchmarks: real scans from ../shared/data (a KITTI frame cut into a
// ScaLa-like 4-layer scan, and the Intel lab log), the engine state they produce, and the
// backends to compare.
#pragma once

#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "alignment.hpp"
#include "backend.hpp"
#include "freespace/freespace.hpp"
#include "preprocess.hpp"

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

// Creates a backend of `kind`; null (with the reason) when it cannot run here.
std::unique_ptr<Backend> MakeBackend(BackendKind kind, const KernelParams& params,
                                     std::string* why);

const char* BackendName(BackendKind kind);

}  // namespace freespace::bench
