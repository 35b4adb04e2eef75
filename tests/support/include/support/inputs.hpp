// Inputs shared by the tests and the benchmarks: scans of the recorded logs, the engine state of
// a real multi-layer scan ready for single-stage runs, and small hand-made configs and scans.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/alignment.hpp"
#include "core/backend.hpp"
#include "core/preprocess.hpp"
#include "freespace/freespace.hpp"

namespace freespace::test {

// All scans of the log `relative_path` under DataDir() (and its sensor, when `sensor` is not
// null); an empty vector when the file is absent.
std::vector<Scan> LoadScans(const std::string& relative_path, SensorConfig* sensor);

// The engine state of a real multi-layer scan on a map of `cells` x `cells` at 0.2 m: the
// config, the preprocessed scan and its raster job, ready for single-stage runs.
struct StageInput {
  Config config;
  KernelParams params;
  Scan scan;
  std::unique_ptr<Preprocessor> preprocess;
  RasterJob job;
  CellIndex vehicle;
  std::vector<LogOdds> map;  // after a few fused scans: realistic free / occupied / unknown
};

// Builds the StageInput from the KITTI frame (a ScaLa-like 4-layer cut); null when the data is
// absent.
std::unique_ptr<StageInput> MakeStageInput(int cells);

// A config whose map is width x height and that stays valid for tiny maps.
Config SmallConfig(int width, int height, double resolution = 0.2);

// Kernel params with the default probabilities for a width x height map.
KernelParams SmallParams(int width, int height, int opening_radius = 0);

// A single-layer scan: beams at `angles_deg` with `ranges` (negative = no echo).
Scan MakeScan(double t, Pose2D pose, const std::vector<double>& angles_deg,
              const std::vector<double>& ranges);

// Sensor `sensor`'s scan of a wall across its view `range` metres ahead, on 4 layers from -30 to
// 30 deg.
Scan Wall(double t, const Pose2D& pose, int sensor, double range);

// A rig of two default sensors at one mount, "a" and "b".
Config TwoAlike();

}  // namespace freespace::test
