// Truth placed in the map's frame and scored: see scorer.hpp.
#include "eval/scorer.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "freespace/errors.hpp"
#include "sim/scanner.hpp"

namespace freespace::sim {

TruthScorer::TruthScorer(const Truth& truth) : truth_(truth), caster_(truth.world) {}

const TruthScan& TruthScorer::At(std::size_t index, double t) const {
  if (index >= truth_.scans.size()) {
    throw InputError("truth: no scan " + std::to_string(index) + " (the truth holds " +
                     std::to_string(truth_.scans.size()) + ")");
  }
  const TruthScan& s = truth_.scans[index];
  if (std::isfinite(t) && std::abs(s.t - t) > 1e-6) {
    throw InputError("truth: scan " + std::to_string(index) + " is at t = " + std::to_string(s.t) +
                     " s, the log's at " + std::to_string(t) + " s: log and truth do not match");
  }
  return s;
}

ScanMetrics TruthScorer::Score(std::size_t index, const MapView& map, const Result& result) {
  const TruthScan& s = At(index, result.timestamp_s);
  // The scoring runs in the frame the map is kept in, whose axes are the cells': the input
  // poses' frame corrected as the engine corrected it (alignment.scan_match; else the same).
  const Pose2D& correction = result.pose_correction;
  const Pose2D to_map = Compose(correction, TruthToMapFrame(s));
  MapView kept = map;
  const Pose2D placed = Compose(correction, Pose2D{map.origin.x(), map.origin.y(), map.map_yaw});
  kept.origin = Vec2(placed.x, placed.y);
  kept.map_yaw = placed.yaw;
  frame_.obstacles = truth_.world.Place(s.movers);
  frame_.moving.resize(frame_.obstacles.size());
  for (std::size_t i = 0; i < frame_.obstacles.size(); ++i) {
    frame_.obstacles[i] = Transform(to_map, frame_.obstacles[i]);
    frame_.moving[i] = truth_.world.obstacles[i].mover >= 0;
  }
  caster_.PlaceMovers(s.movers);
  const Rig& rig = truth_.rig;
  if (rig.several()) {
    // Each scanner of the rig at its mount; the in-sight area is around the reference point.
    frame_.visible_more.clear();
    for (std::size_t k = 0; k < rig.scanners.size(); ++k) {
      const Pose2D sensor = Compose(s.pose, rig.scanners[k].mount());
      Polygon seen = Transform(to_map, VisibilityPolygon(caster_, sensor, rig.scanners[k]));
      if (k == 0) {
        frame_.visible = std::move(seen);
      } else {
        frame_.visible_more.push_back(std::move(seen));
      }
    }
  } else {
    frame_.visible = Transform(to_map, VisibilityPolygon(caster_, s.sensor, truth_.scanner));
  }
  // In sight all around, as far as the map reaches from the sensor.
  const double reach = std::hypot(map.width, map.height) * map.resolution_m;
  frame_.in_sight = Transform(to_map, SurroundingVisibility(caster_, Vec2(s.sensor.x, s.sensor.y),
                                                            truth_.scanner.resolution_deg, reach));
  ScanMetrics m = evaluator_.Evaluate(kept, Transform(correction, result.polygon), frame_,
                                      result.vehicle_cells);
  m.scan = s.index;
  m.t = s.t;
  return m;
}

std::size_t TruthScorer::Find(double t) const {
  const auto& scans = truth_.scans;
  const auto it = std::lower_bound(scans.begin(), scans.end(), t - 1e-6,
                                   [](const TruthScan& s, double v) { return s.t < v; });
  if (it == scans.end() || std::abs(it->t - t) > 1e-6) {
    throw InputError("truth: no scan at t = " + std::to_string(t) +
                     " s: the log does not belong to this truth file");
  }
  return std::size_t(it - scans.begin());
}

std::vector<std::vector<Vec2>> TruthScorer::Outlines(std::size_t index, const Vec2& lo,
                                                     const Vec2& hi) const {
  const TruthScan& s = At(index, NAN);
  const Pose2D to_map = TruthToMapFrame(s);
  std::vector<std::vector<Vec2>> lines;
  for (std::vector<Vec2>& line : truth_.world.Outlines(s.movers)) {
    std::vector<Vec2> moved = Transform(to_map, line);
    Vec2 min = moved.front(), max = moved.front();
    for (const Vec2& p : moved) {
      min = min.cwiseMin(p);
      max = max.cwiseMax(p);
    }
    if (min.x() <= hi.x() && max.x() >= lo.x() && min.y() <= hi.y() && max.y() >= lo.y()) {
      lines.push_back(std::move(moved));
    }
  }
  return lines;
}

}  // namespace freespace::sim
