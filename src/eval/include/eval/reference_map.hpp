// A world-fixed reference map, for the paper's alignment comparison (section V.B): the same
// enhanced inverse sensor model written into a large grid that never moves, on the same
// lattice as the estimator's local map. The local map of the circle alignment must equal the
// reference inside its window, cell for cell; a resampled (rotated) map shows its error.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/backend.hpp"
#include "core/preprocess.hpp"
#include "freespace/config.hpp"
#include "freespace/result.hpp"

namespace freespace {

// Differences between a local map and the reference over the cells both cover and either has
// observed.
struct MapDifference {
  long compared = 0;        // cells compared
  long different = 0;       // cells whose log-odds differ at all
  long class_mismatch = 0;  // free / unknown / occupied (p < , = , > 0.5) differ
  double mean_abs_probability = 0.0;
};

class ReferenceMap {
 public:
  // `margin_cells` of room around the local window on every side; the reference grid grows
  // (and is re-anchored) when the window leaves it.
  explicit ReferenceMap(const Config& config, int margin_cells = 1500);

  // Adds one scan, given the estimator's Result for it on the circle alignment (its window
  // and the sensor's local position). Cells that left the local window since the last scan
  // are forgotten, as a local map forgets them. A rejected scan changes nothing.
  void Update(const Scan& scan, const Result& circle_result);

  // Compares an axis-aligned local map (circle alignment) with the reference window.
  MapDifference CompareCircle(const MapView& map, const Result& result) const;

  // Compares a vehicle-centred, rotated map (alignment rotate) with the reference: each of
  // its cells against the reference cell holding its centre.
  MapDifference CompareRotated(const MapView& map, const Result& result) const;

 private:
  LogOdds At(std::int64_t x, std::int64_t y) const;  // absolute lattice cell (from the anchor)
  void Forget(std::int64_t x0, std::int64_t y0);     // keep only the window at (x0, y0)
  void Recentre(std::int64_t x0, std::int64_t y0);

  Config config_;
  KernelParams params_;
  Preprocessor preprocess_;
  int margin_;
  int width_ = 0, height_ = 0;  // reference grid size
  std::int64_t base_x_ = 0;     // lattice cell of the grid's cell (0, 0)
  std::int64_t base_y_ = 0;
  std::vector<LogOdds> grid_;
  bool started_ = false;
  std::int64_t window_x_ = 0;  // lattice cell of the local window's (0, 0)
  std::int64_t window_y_ = 0;
  Vec2 anchor_;  // world position of lattice cell (0, 0)'s corner
  std::vector<std::int32_t> vertices_;
  std::vector<std::uint8_t> row_;
  std::vector<std::uint8_t> update_;
};

}  // namespace freespace
