// Quality of the estimator's outputs against exact truth (definitions: docs/metrics.md).
// Inputs are only what the estimator publishes (the MapView and the free-space polygon in
// world metres) and the true geometry in the same frame (convex obstacle outlines and the
// true visibility polygon of each scan), so the metrics know nothing of the engine's inside.
#pragma once

#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "freespace/result.hpp"
#include "geometry/geometry.hpp"

namespace freespace {

// The truth of one scan in the frame the map is built in.
struct TruthFrame {
  std::vector<geometry::Polygon> obstacles;  // convex, counter-clockwise, at the scan's time
  std::vector<bool> moving;                  // per obstacle: it moves (empty: none moves)
  // The scanner's true visibility polygon of this scan: the scanner, then each beam's end from
  // the first beam to the last (its aperture).
  geometry::Polygon visible;
  std::vector<geometry::Polygon> visible_more;  // a rig's other scanners' visibility polygons
  geometry::Polygon in_sight;  // the true visibility all around the sensor now (empty: coverage
                               // is not scored)
};

// Scores of one scan. Rates are NaN when their denominator is empty.
struct ScanMetrics {
  std::uint64_t scan = 0;
  double t = 0.0;
  // Cells of the map (docs/metrics.md): observed = log-odds not 0; the map calls a cell free
  // when p < 0.5 and occupied when p > 0.5; a cell is truly occupied when an obstacle covers
  // any of it (more than 1e-6 of its area).
  long observed = 0;
  long observed_occupied = 0;         // observed and truly occupied
  long correct = 0;                   // observed cells the map calls as the truth has them
  double accuracy = 0.0;              // correct / observed
  long false_free = 0;                // truly occupied observed cells called free
  long false_free_majority = 0;       // of these, cells covered at least half
  double false_free_rate = 0.0;       // false_free / observed_occupied
  long false_free_moving = 0;         // of these, cells a moving obstacle covers
  long false_free_mask = 0;           // truly occupied cells in the engine's free mask
  double false_free_mask_rate = 0.0;  // false_free_mask / observed_occupied
  long false_occupied = 0;            // truly free observed cells called occupied
  long errors_at_border = 0;          // wrong cells next to (8-neighbour) a cell of the other truth
  // The polygon, m^2.
  double polygon_area_m2 = 0.0;
  double intrusion_m2 = 0.0;            // polygon area on truly occupied cells
  double intrusion_geometric_m2 = 0.0;  // polygon area inside the obstacles themselves
  double intrusion_moving_m2 = 0.0;     // of intrusion_m2, on cells a moving obstacle covers
  double intrusion_mask_m2 = 0.0;  // of intrusion_m2, on cells the engine's free mask calls free
                                   // (map errors; the rest is the polygon's own)
  // Of intrusion_m2, on cells outside every scanner's aperture now (the bearing of the cell's
  // centre from the scanner lies outside its first to last beam): where the map's memory, not
  // this scan, bounds the polygon. NaN when the truth holds no scanner's visibility polygon.
  double intrusion_out_of_view_m2 = 0.0;
  // Coverage (docs/metrics.md): the reference is the truly free, observed cells in sight of
  // the sensor now (TruthFrame::in_sight); NaN when in_sight is empty.
  double reference_free_m2 = 0.0;     // truly free cells, observed, in sight now
  double covered_free_m2 = 0.0;       // polygon area on those cells
  double coverage = 0.0;              // covered_free_m2 / reference_free_m2
  double reference_in_mask_m2 = 0.0;  // of reference_free_m2, cells the free mask calls free
  double coverage_mask = 0.0;         // reference_in_mask_m2 / reference_free_m2: what a polygon
                                      // drawn on this free mask could cover at most
  // Of reference_free_m2, the polygon's area on it plus the whole of each cell it does not
  // cover whole that the free mask calls free and whose centre the polygon's centre sees
  // through free-mask cells (a straight line): what a polygon star-shaped around that centre
  // on this free mask could cover at most. NaN without a centre.
  double reference_star_m2 = 0.0;
  double coverage_star = 0.0;  // reference_star_m2 / reference_free_m2
  // The same over the truly free, observed cells seen at any scan so far (hidden ones too).
  double reference_seen_m2 = 0.0;
  double covered_seen_m2 = 0.0;
  double coverage_seen = 0.0;

  nlohmann::json ToJson() const;
};

// Scores scans in order. The "seen so far" area (union of the true visibility polygons) is
// kept in the map's cells and moves with the map's origin; a scan whose origin is not a
// whole number of cells from the last one, or whose map_yaw differs, restarts it. World points
// go to cells through the map's origin, map_yaw and resolution (MapView).
class QualityEvaluator {
 public:
  // `map`: the estimator's map after the scan; `polygon`: its free-space polygon (world
  // metres); `truth`: the true geometry of the scan in the map's world frame.
  // `centre`: the point the polygon is star-shaped around, map cells (Result::vehicle_cells);
  // NaN leaves coverage_star unscored.
  ScanMetrics Evaluate(const MapView& map, const std::vector<Vec2>& polygon,
                       const TruthFrame& truth, const Vec2& centre = Vec2(NAN, NAN));
  void Reset() { have_seen_ = false; }

  // The per-cell results of the last Evaluate() (row-major like the map), for drawing/tests.
  const std::vector<float>& covered_fraction() const { return covered_; }
  const std::vector<std::uint8_t>& seen() const { return seen_; }
  const std::vector<float>& polygon_fraction() const { return polygon_; }

 private:
  void Cover(const MapView& map, const TruthFrame& truth);
  void PolygonCells(const MapView& map, const std::vector<Vec2>& polygon);
  void See(const MapView& map, const geometry::Polygon& visible);

  std::vector<float> covered_;        // obstacle area fraction per cell, 0 .. 1
  std::vector<std::uint8_t> moving_;  // a moving obstacle covers part of the cell
  std::vector<std::uint8_t> in_sight_;
  std::vector<float> polygon_;      // polygon area fraction per cell, 0 .. 1
  std::vector<std::uint8_t> seen_;  // inside a true visibility polygon so far
  std::vector<std::uint8_t> scratch_;
  std::vector<std::uint8_t> edge_;  // cells an edge of the polygon may touch
  std::vector<double> crossings_;
  bool have_seen_ = false;
  Vec2 seen_origin_;
  double seen_yaw_ = 0.0;
  int seen_width_ = 0, seen_height_ = 0;
};

// Per-scan scores of a drive and their summary (docs/metrics.md, "Summary").
class MetricsSeries {
 public:
  void Add(const ScanMetrics& m) { scans_.push_back(m); }
  const std::vector<ScanMetrics>& scans() const { return scans_; }
  std::size_t size() const { return scans_.size(); }
  // {"accuracy": {"mean", "min", "pooled"}, "false_free_rate": {...}, "intrusion_m2":
  // {"mean", "median", "p95", "max"}, ...}.
  nlohmann::json Summary() const;

 private:
  std::vector<ScanMetrics> scans_;
};

}  // namespace freespace
