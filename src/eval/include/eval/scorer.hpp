// Scores the estimator's output of each scan of a simulated drive against its truth: places
// the true obstacles (movers at their poses) in the frame the map is built in, casts the true
// visibility polygon and hands both to the QualityEvaluator.
#pragma once

#include <vector>

#include "eval/metrics.hpp"
#include "freespace/result.hpp"
#include "sim/truth.hpp"
#include "sim/world.hpp"

namespace freespace::sim {

class TruthScorer {
 public:
  // `truth` must outlive the scorer; its scans may grow while scoring (a drive in progress).
  explicit TruthScorer(const Truth& truth);

  // Scores scan `index` of the truth: `map` and `result` are the estimator's after that scan.
  // Scans must come in order (the seen area accumulates). Throws InputError when the truth has
  // no such scan or its time differs from result.timestamp_s by more than 1e-6 s.
  ScanMetrics Score(std::size_t index, const MapView& map, const Result& result);

  // The per-cell results of the last Score() (covered and polygon fractions), for drawing and
  // diagnostics.
  const QualityEvaluator& evaluator() const { return evaluator_; }

  // The index of the truth's scan at time t (within 1e-6 s); throws InputError when none is.
  std::size_t Find(double t) const;

  // The true obstacle outlines of scan `index` in the map's frame, closed, for drawing: those
  // whose bounding box meets the box [lo, hi].
  std::vector<std::vector<Vec2>> Outlines(std::size_t index, const Vec2& lo, const Vec2& hi) const;

 private:
  const TruthScan& At(std::size_t index, double t) const;

  const Truth& truth_;
  RayCaster caster_;
  QualityEvaluator evaluator_;
  TruthFrame frame_;
};

}  // namespace freespace::sim
