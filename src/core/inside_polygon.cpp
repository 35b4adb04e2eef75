// The conservative polygon. Why it covers mask cells only.
//
// Every ray is clear up to its end: it ends where it first enters (or touches at a corner) a
// cell outside the mask. Neighbouring rays aim at neighbouring border cells, so the wedge
// between them is less than a cell wide inside the map. A cell outside the mask that overlaps
// the fan triangle (sensor, a, b) of two neighbouring ends with some area therefore cannot lie
// inside it, nor reach it across the rays: it must cross the edge a -> b. So the cells that
// edge meets are the only ones to test. In the triangle's barycentric coordinates (alpha along
// a, beta along b) the least alpha + beta over such a cell's part inside the wedge is the
// largest factor by which a and b may be scaled toward the sensor together without touching
// it; moving only b, or only a, has a bound of its own. Each triangle keeps its own factors: the
// ring reaches a ray's end at the factor of the triangle before it and leaves at the factor of
// the triangle after it, along the ray, which is clear up to its end. So the side of a shadow
// is a step along one ray, and a far end pulled in for the pole beside it keeps its other
// triangle whole.
//
// The simplified polygon's edges are then held inside the ring: a triangle (sensor, a, b) of
// the simplified polygon lies within the ring's fan triangles between a and b when every ring
// vertex between them lies on or beyond the edge a -> b, which is a bound on the same three
// kinds of pull. No cell is looked at again.
#include "core/inside_polygon.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/backend.hpp"
#include "core/fan_pull.hpp"
#include "core/fixed_point.hpp"

namespace freespace {
namespace {

using fan::Cross;
using fan::kAreaTolerance;

// Cells within this distance of an edge are tested: rounding must not hide a crossed one.
constexpr double kReach = 1e-7;
// The simplification splits at a ring vertex its edge would cut off (pulling the edge in
// afterwards) before it spends a vertex on one the edge only passes outside: a vertex inside
// counts this many times its distance. Over the urban drive, weights of 1, 10 and 100 left
// 6.3 %, 4.8 % and 4.1 % of the area in sight out of the polygon though in the mask and
// clear of shadows; 1000 and more changed nothing.
constexpr double kInwardWeight = 100.0;

}  // namespace

InsidePolygonBuilder::InsidePolygonBuilder(int width, int height, int max_vertices, double epsilon,
                                           int parts)
    : width_(width),
      height_(height),
      area_(max_vertices, epsilon, kInwardWeight, 4 * BorderLabelCount(height, width)),
      simplifier_(max_vertices, epsilon),
      parts_(std::max(1, parts)) {
  simplifier_.set_inward_weight(kInwardWeight);
  // One ray per distinct border cell: the corner cells, which two labels share, once.
  const int labels = BorderLabelCount(height, width);
  const CellIndex first = BorderCell(0, height, width);
  CellIndex last{-1, -1};
  for (int l = 0; l < labels; ++l) {
    const CellIndex cell = BorderCell(l, height, width);
    if (cell == last || (l > 0 && cell == first)) continue;
    last = cell;
    labels_.push_back(l);
  }
  part_beyond_.resize(std::size_t(parts_));
  ring_.reserve(4 * labels_.size());  // per ray: its end in and out, a corner in and out
  end_.reserve(labels_.size());
  end_stop_.resize(labels_.size());
  need_a_.resize(labels_.size());
  need_b_.resize(labels_.size());
  corner_.resize(labels_.size());
  corner_at_.resize(labels_.size());
  split_in_at_.resize(labels_.size());
  split_out_at_.resize(labels_.size());
  kept_.reserve(std::size_t(std::max(max_vertices, 3)) + 1);
  scale_.reserve(std::size_t(std::max(max_vertices, 3)) + 1);
}

void InsidePolygonBuilder::PullBetweenRays(const MaskView& mask, const Vec2& sensor, const Vec2& a,
                                           const Vec2& b, const NearSide& near, PairPull* pull,
                                           double* scale_a, double* scale_b) const {
  *scale_a = *scale_b = 1.0;
  const Vec2 u = a - sensor, v = b - sensor;
  const double det = Cross(u, v);     // twice the triangle's area
  if (det <= kAreaTolerance) return;  // no area: the edge runs along its rays
  FanPull bounds;
  const double y0 = std::min(a.y(), b.y()) - kReach, y1 = std::max(a.y(), b.y()) + kReach;
  const int r0 = std::max(near.row_min, FloorCell(y0));
  const int r1 = std::min(near.row_max, FloorCell(y1));
  const int c0 = std::max(near.col_min, FloorCell(std::min(a.x(), b.x()) - kReach));
  const int c1 = std::min(near.col_max, FloorCell(std::max(a.x(), b.x()) + kReach));
  if ((r1 - r0 + 1) * (c1 - c0 + 1) <= 6) {
    // A short edge (the common one: two rays on one wall): every cell of its box.
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        if (!mask.Allowed(c, r)) Block(r, c, sensor, u, v, det, &bounds, pull);
      }
    }
    Settle(sensor, a, b, bounds, pull, scale_a, scale_b);
    return;
  }
  // A long edge: the cells it meets, a row at a time, found 64 cells a word.
  const double slope = b.y() != a.y() ? (b.x() - a.x()) / (b.y() - a.y()) : 0.0;
  for (int r = r0; r <= r1; ++r) {
    double x0 = std::min(a.x(), b.x()), x1 = std::max(a.x(), b.x());
    if (b.y() != a.y()) {  // the edge's part in rows [r, r + 1], x at its two ends there
      const double ya = std::clamp(double(r), std::min(a.y(), b.y()), std::max(a.y(), b.y()));
      const double yb = std::clamp(double(r + 1), std::min(a.y(), b.y()), std::max(a.y(), b.y()));
      const double xa = a.x() + (ya - a.y()) * slope, xb = a.x() + (yb - a.y()) * slope;
      x0 = std::max(x0, std::min(xa, xb));
      x1 = std::min(x1, std::max(xa, xb));
    }
    const int from = std::max(near.col_min, FloorCell(x0 - kReach));
    const int to = std::min(near.col_max, FloorCell(x1 + kReach));
    if (from > to) continue;
    const std::uint64_t* line = mask.bits + std::size_t(r) * mask.words;
    for (int w = from >> 6; w <= to >> 6; ++w) {
      std::uint64_t blocked = ~line[w];
      if (w == from >> 6) blocked &= ~std::uint64_t{0} << (from & 63);
      if (w == to >> 6) blocked &= ~std::uint64_t{0} >> (63 - (to & 63));
      while (blocked != 0) {
        Block(r, w * 64 + __builtin_ctzll(blocked), sensor, u, v, det, &bounds, pull);
        blocked &= blocked - 1;
      }
    }
  }
  Settle(sensor, a, b, bounds, pull, scale_a, scale_b);
}

void InsidePolygonBuilder::Block(int row, int col, const Vec2& sensor, const Vec2& u, const Vec2& v,
                                 double det, FanPull* bounds, PairPull* pull) {
  if (!bounds->Limit(row, col, sensor, u, v, det)) return;  // reaches no part of the triangle
  if (pull->count < kMaxBlocked) {
    pull->blocked[pull->count++] = CellIndex{row, col};
  } else {
    pull->overflow = true;
  }
}

void InsidePolygonBuilder::Settle(const Vec2& sensor, const Vec2& a, const Vec2& b,
                                  const FanPull& bounds, PairPull* pull, double* scale_a,
                                  double* scale_b) {
  bounds.Choose(scale_a, scale_b);  // pull->split is false: the pull came fresh
  if (pull->count == 0 || pull->overflow) return;
  const CellIndex* begin = pull->blocked;
  const CellIndex* end = pull->blocked + pull->count;
  // Going round the corner c of a blocked cell that pokes in deepest (least alpha + beta; the
  // silhouette of the cell that casts a shadow): the triangles (a, c) and (c, b), each pulled
  // on its own, often keep far more. Trying every corner kept no more over the urban drive.
  const Vec2 u = a - sensor, v = b - sensor;
  const double det = Cross(u, v);
  double deepest = det;
  Vec2 at = Vec2::Zero();
  for (const CellIndex* cell_at = begin; cell_at != end; ++cell_at) {
    const CellIndex& cell = *cell_at;
    for (int corner = 0; corner < 4; ++corner) {
      const Vec2 c(cell.col + (corner == 1 || corner == 2), cell.row + (corner >= 2));
      const double da = Cross(u, c - sensor), db = Cross(c - sensor, v);
      if (da <= kAreaTolerance || db <= kAreaTolerance || da + db >= deepest) continue;
      deepest = da + db;
      at = c;
    }
  }
  // The two triangles round the corner keep at most their whole area, da + db = deepest: no
  // more than the pull keeps already, and there is nothing to go round for.
  if (deepest >= det || deepest <= det * *scale_a * *scale_b) return;
  const Vec2 w = at - sensor;
  const double da = Cross(u, w), db = Cross(w, v);
  FanPull first, second;
  for (const CellIndex* cell = begin; cell != end; ++cell) {
    first.Limit(cell->row, cell->col, sensor, u, w, da);
    second.Limit(cell->row, cell->col, sensor, w, v, db);
  }
  double a1, c1, c2, b2;
  first.Choose(&a1, &c1);
  second.Choose(&c2, &b2);
  if (da * a1 * c1 + db * c2 * b2 <= det * *scale_a * *scale_b) return;
  pull->split = true;
  pull->at = at;
  pull->in = c1;
  pull->out = c2;
  *scale_a = a1;
  *scale_b = b2;
}

void InsidePolygonBuilder::PullInsideRing(const Vec2& sensor, int i, int j, double* scale_a,
                                          double* scale_b) const {
  const int n = int(ring_.size());
  const Vec2 a = ring_[std::size_t(i)] - sensor, b = ring_[std::size_t(j)] - sensor;
  const double det = Cross(a, b);
  *scale_a = *scale_b = 1.0;
  FanPull bounds;
  if (det <= kAreaTolerance) {
    // Half a turn or more, or no area: the edge cannot pass the ring on its far side.
    if (det < -kAreaTolerance) bounds.both = bounds.only_a = bounds.only_b = 0.0;
  } else {
    for (int k = i + 1 < n ? i + 1 : 0; k != j; k = k + 1 < n ? k + 1 : 0) {
      const Vec2 p = ring_[std::size_t(k)] - sensor;
      // p must lie on or beyond the edge: both ends scaled by s, only b, or only a.
      bounds.both = std::min(bounds.both, Cross(p, b - a) / det);
      const double c1 = Cross(b, p - a);
      if (c1 > 0) bounds.only_b = std::min(bounds.only_b, Cross(a, p) / c1);
      const double e = Cross(a, p) - det;
      if (e < 0) bounds.only_a = std::min(bounds.only_a, Cross(b, p) / e);
    }
  }
  bounds.Choose(scale_a, scale_b);
}

InsidePolygonBuilder::NearSide InsidePolygonBuilder::Near(const Vec2& sensor, const RayStop& a,
                                                          const RayStop& b) const {
  NearSide near{0, height_ - 1, 0, width_ - 1};
  // Two rays that stopped on one cell edge line: the edge between them runs along it, and the
  // cells beyond the line touch the triangle along the edge only.
  if (a.kind == b.kind && a.line == b.line) {
    if (a.kind == kRayCrossX) {
      if (sensor.x() < a.line)
        near.col_max = a.line - 1;
      else
        near.col_min = a.line;
    } else if (a.kind == kRayCrossY) {
      if (sensor.y() < a.line)
        near.row_max = a.line - 1;
      else
        near.row_min = a.line;
    }
  }
  return near;
}

bool InsidePolygonBuilder::Distinct(std::vector<Vec2>* polygon) {
  std::vector<Vec2>& p = *polygon;
  std::size_t n = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (n > 0 && (p[i] - p[n - 1]).squaredNorm() <= 1e-18) continue;
    p[n++] = p[i];
  }
  while (n > 1 && (p[n - 1] - p[0]).squaredNorm() <= 1e-18) --n;
  p.resize(n);
  double area = 0.0;
  for (std::size_t i = 0; i < n; ++i) area += Cross(p[i], p[(i + 1) % n]);
  if (n < 3 || area <= kAreaTolerance) {
    p.clear();
    return false;
  }
  return true;
}

bool InsidePolygonBuilder::RayEnds(const SensorCell& s, const std::vector<RayStop>& stops,
                                   int begin, int end) {
  bool beyond = false;  // a ray ended outside the sensor's own cell
  for (int k = begin; k < end; ++k) {
    const int label = labels_[std::size_t(k)];
    const CellIndex target = BorderCell(label, height_, width_);
    const RayStop& stop = stops[std::size_t(label)];
    const Vec2 p = RayStopPoint(s, target.col, target.row, stop);
    end_[std::size_t(k)] = p;
    end_stop_[std::size_t(k)] = stop;
    beyond = beyond || p.x() < s.cell.col - kReach || p.x() > s.cell.col + 1 + kReach ||
             p.y() < s.cell.row - kReach || p.y() > s.cell.row + 1 + kReach;
  }
  return beyond;
}

void InsidePolygonBuilder::BetweenRays(const MaskView& mask, const Vec2& sensor, int k) {
  const int next = k + 1 < int(end_.size()) ? k + 1 : 0;
  const RayStop& a = end_stop_[std::size_t(k)];
  const RayStop& b = end_stop_[std::size_t(next)];
  need_a_[std::size_t(k)] = need_b_[std::size_t(k)] = 1.0;
  corner_[std::size_t(k)] = 0;
  // Two rays that entered one cell across two of its edges: the edge between their ends cuts
  // that cell's corner, and that cell alone (the edge lies in its square). The ring goes round
  // the corner instead: along the two edges, which the rays reached from the cells before.
  if (a.cell == b.cell && ((a.kind == kRayCrossX && b.kind == kRayCrossY) ||
                           (a.kind == kRayCrossY && b.kind == kRayCrossX))) {
    const RayStop& x = a.kind == kRayCrossX ? a : b;
    const RayStop& y = a.kind == kRayCrossY ? a : b;
    corner_at_[std::size_t(k)] = Vec2(x.line, y.line);
    corner_[std::size_t(k)] = 1;
    return;
  }
  // Two rays that reached neighbouring border cells: the edge lies in those two cells.
  if (a.kind == kRayEnd && b.kind == kRayEnd) return;
  // Two rays that stopped on one cell edge line: the edge runs along it, and the cells beyond
  // the line touch the triangle along the edge only; on the sensor's side the rays came
  // through the cells next to the line. When those are all in the mask, nothing reaches in.
  if (a.kind == b.kind && a.line == b.line && (a.kind == kRayCrossX || a.kind == kRayCrossY)) {
    // Into one cell, or into two beside each other along the line: the one ray a came through.
    if (a.cell == b.cell || (a.kind == kRayCrossX && std::abs(a.cell - b.cell) == width_) ||
        (a.kind == kRayCrossY && std::abs(a.cell - b.cell) == 1 &&
         a.cell / width_ == b.cell / width_)) {
      return;
    }
    const bool x = a.kind == kRayCrossX;
    const Vec2& p = end_[std::size_t(k)];
    const Vec2& q = end_[std::size_t(next)];
    const int from = FloorCell(x ? p.y() : p.x()), to = FloorCell(x ? q.y() : q.x());
    if (from == to) return;  // one cell next to the line: the one ray a came through
    const int across = (x ? sensor.x() : sensor.y()) < a.line ? a.line - 1 : a.line;
    bool clear = true;
    for (int i = std::min(from, to); clear && i <= std::max(from, to); ++i) {
      clear = x ? mask.Allowed(across, i) : mask.Allowed(i, across);
    }
    if (clear) return;
  }
  PairPull pull;
  PullBetweenRays(mask, sensor, end_[std::size_t(k)], end_[std::size_t(next)], Near(sensor, a, b),
                  &pull, &need_a_[std::size_t(k)], &need_b_[std::size_t(k)]);
  if (pull.split) {
    corner_[std::size_t(k)] = 2;
    corner_at_[std::size_t(k)] = pull.at;
    split_in_at_[std::size_t(k)] = pull.in;
    split_out_at_[std::size_t(k)] = pull.out;
  }
}

// Rays that end on one cell edge line (or on one border side) end on a straight line, in order
// along it: the vertices between the first and the last of such a run change nothing. Pulled
// vertices left their line. Rays blocked at once end at the sensor: one is enough. So a vertex
// is dropped when it lies on a row or column line with the last one kept and the next one.
void InsidePolygonBuilder::RingCompactor::Offer(const Vec2& next) {
  if (started_) {
    const Vec2& before = ring_->empty() ? last_ : ring_->back();
    if (!Inner(before, pending_, next)) ring_->push_back(pending_);
  } else {
    first_ = next;
    started_ = true;
  }
  pending_ = next;
}

void InsidePolygonBuilder::RingCompactor::Close() {
  if (!started_) return;
  const Vec2& before = ring_->empty() ? last_ : ring_->back();
  if (!Inner(before, pending_, ring_->empty() ? first_ : ring_->front()))
    ring_->push_back(pending_);
}

void InsidePolygonBuilder::AssembleRing(const Vec2& sensor) {
  const int m = int(end_.size());
  ring_.clear();
  if (m == 0) return;
  // Each triangle keeps its own pull: the ring comes in to ray k's end at the scale the
  // triangle before it allows and leaves from the scale the one after it allows, running along
  // the ray between the two (clear up to its end). A shadow's side is such a step. The last
  // ray's last vertex, worked out first, is the neighbour before the first ray's first.
  const auto last_of = [&](int k) -> Vec2 {
    if (corner_[std::size_t(k)] == 1) return corner_at_[std::size_t(k)];
    if (corner_[std::size_t(k)] == 2)
      return sensor + split_out_at_[std::size_t(k)] * (corner_at_[std::size_t(k)] - sensor);
    return sensor + need_a_[std::size_t(k)] * (end_[std::size_t(k)] - sensor);
  };
  RingCompactor ring(&ring_, last_of(m - 1));
  for (int k = 0; k < m; ++k) {
    const Vec2 d = end_[std::size_t(k)] - sensor;
    const double in = need_b_[std::size_t(k > 0 ? k - 1 : m - 1)], out = need_a_[std::size_t(k)];
    ring.Offer(sensor + in * d);
    if (out != in) ring.Offer(sensor + out * d);
    if (corner_[std::size_t(k)] == 1) ring.Offer(corner_at_[std::size_t(k)]);
    if (corner_[std::size_t(k)] == 2) {  // round a blocked cell's corner, pulled on each side
      const Vec2 c = corner_at_[std::size_t(k)] - sensor;
      const double c_in = split_in_at_[std::size_t(k)], c_out = split_out_at_[std::size_t(k)];
      ring.Offer(sensor + c_in * c);
      if (c_out != c_in) ring.Offer(sensor + c_out * c);
    }
  }
  ring.Close();
}

bool InsidePolygonBuilder::Build(const MaskView& mask, const SensorCell& s,
                                 const std::vector<RayStop>& stops, std::vector<Vec2>* polygon,
                                 double* error) {
  polygon->clear();
  *error = 0.0;
  collapsed_ = false;
  const int pairs = int(labels_.size());  // one ray per label kept, each with the next
  end_.resize(labels_.size());
  const Vec2 sensor(double(s.x) / kFixedOne, double(s.y) / kFixedOne);
  // Neighbouring rays can pass a cell outside the mask between them: the ring goes round it or
  // is pulled in first, so that the simplification works on a ring whose fan lies in the mask.
  // Each part takes its rays' ends and the pairs within them; the pairs across two parts follow.
  const auto bound = [&](int part) { return int(std::int64_t(pairs) * part / parts_); };
  const auto run = [&](int part) {
    const int begin = bound(part), end = bound(part + 1);  // once: each is a division
    part_beyond_[std::size_t(part)] = RayEnds(s, stops, begin, end);
    for (int k = begin; k + 1 < end; ++k) BetweenRays(mask, sensor, k);
  };
  if (parts_ == 1) {
    run(0);
  } else {
    tbb::parallel_for(0, parts_, run);
  }
  if (std::none_of(part_beyond_.begin(), part_beyond_.end(), [](char b) { return b != 0; }))
    return false;
  for (int part = 0; part < parts_; ++part) {
    if (bound(part + 1) > bound(part)) BetweenRays(mask, sensor, bound(part + 1) - 1);
  }
  AssembleRing(sensor);
  *error = area_.Simplify(ring_, sensor, &kept_);
  if (*error < 0.0) *error = simplifier_.Simplify(ring_, sensor, &kept_);
  const int n = int(kept_.size());
  scale_.assign(std::size_t(n), 1.0);
  for (int k = 0; k < n; ++k) {
    const int next = k + 1 < n ? k + 1 : 0;
    double sa = 1.0, sb = 1.0;
    PullInsideRing(sensor, kept_[std::size_t(k)], kept_[std::size_t(next)], &sa, &sb);
    scale_[std::size_t(k)] = std::min(scale_[std::size_t(k)], sa);
    scale_[std::size_t(next)] = std::min(scale_[std::size_t(next)], sb);
  }
  for (int k = 0; k < n; ++k) {
    polygon->push_back(sensor + scale_[std::size_t(k)] *
                                    (ring_[std::size_t(kept_[std::size_t(k)])] - sensor));
  }
  collapsed_ = !Distinct(polygon);
  return !collapsed_;
}

}  // namespace freespace
