// PNG snapshots of the estimator's state: the map in grey (white free, black occupied, grey
// unknown), the free-space polygon, the vehicle and its position circle, and optionally a
// truth outline. North is up.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "freespace/result.hpp"
#include "freespace/scan.hpp"

namespace freespace {

// One scanner's scan as drawn: its world origin and its echoes (world metres).
struct ScannerRays {
  Vec2 origin;
  std::vector<Vec2> echoes;
};

struct SnapshotOverlay {
  // World polylines (metres) drawn in green, e.g. the simulator's true obstacle outlines.
  const std::vector<std::vector<Vec2>>* truth = nullptr;
  // Every scanner's rays to its echoes, thin, a colour per scanner, and its origin.
  const std::vector<ScannerRays>* rays = nullptr;
  std::string caption;
};

// The rays of a cycle's scans (Result::cycle_sensor_poses) for drawing: every `step`-th echo of
// each scan, in world metres.
std::vector<ScannerRays> CycleRays(const std::vector<Scan>& scans, const Result& result, int step);

// Pixels per cell so that the image is about 900 pixels wide (at least 1).
int SnapshotScale(int width, int height);

cv::Mat RenderSnapshot(const MapView& map, const Result& result,
                       const SnapshotOverlay& overlay = {});

// Writes `image` as PNG; throws InputError when it cannot.
void WritePng(const std::string& path, const cv::Mat& image);

}  // namespace freespace
