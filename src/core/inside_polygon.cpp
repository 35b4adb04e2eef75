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
// it; moving only b, or only a, has a bound of its own. Moving a vertex toward the sensor along
// its ray only shrinks the triangles on both sides of it, so each vertex takes the smaller
// factor of its two edges and every triangle stays inside its clear one.
//
// The simplified polygon's edges are then held inside the ring: a triangle (sensor, a, b) of
// the simplified polygon lies within the ring's fan triangles between a and b when every ring
// vertex between them lies on or beyond the edge a -> b, which is a bound on the same three
// kinds of pull. No cell is looked at again.
#include "core/inside_polygon.hpp"

#include <algorithm>
#include <cmath>

#include "core/backend.hpp"

namespace freespace {
namespace {

double Cross(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

// floor(x) for |x| < 2^31, without a library call.
int Floor(double x) {
  const int i = int(x);
  return i - (x < i);
}

// Below this area (cells^2) a triangle or an overlap counts as none: rounding only.
constexpr double kAreaTolerance = 1e-9;
// Cells within this distance of an edge are tested: rounding must not hide a crossed one.
constexpr double kReach = 1e-7;
// A cell whose part in a triangle lies within this fraction of the far edge is beyond it: the
// strip holds less than 1e-6 cells^2 of any triangle in a map of 8192 x 8192 cells.
constexpr double kEdgeTolerance = 1e-14;

// A convex polygon in (alpha, beta) coordinates, at most 8 vertices (a square cut by three
// half-planes).
struct Clip {
  double v[8][2];
  int n = 0;
  // Keeps the part where c0 + c1 * alpha + c2 * beta >= 0 (Sutherland-Hodgman).
  void Cut(double c0, double c1, double c2) {
    double f[8];
    bool all_in = true, all_out = true;
    for (int i = 0; i < n; ++i) {
      f[i] = c0 + c1 * v[i][0] + c2 * v[i][1];
      all_in = all_in && f[i] >= 0;
      all_out = all_out && f[i] < 0;
    }
    if (all_in) return;
    if (all_out) {
      n = 0;
      return;
    }
    double out[8][2];
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const int j = i + 1 < n ? i + 1 : 0;
      const double* p = v[i];
      const double* q = v[j];
      const double fp = f[i], fq = f[j];
      if (fp >= 0) {
        out[m][0] = p[0];
        out[m][1] = p[1];
        ++m;
      }
      if ((fp >= 0) != (fq >= 0)) {
        const double f = fp / (fp - fq);
        out[m][0] = p[0] + f * (q[0] - p[0]);
        out[m][1] = p[1] + f * (q[1] - p[1]);
        ++m;
      }
    }
    n = m;
    for (int i = 0; i < n; ++i) {
      v[i][0] = out[i][0];
      v[i][1] = out[i][1];
    }
  }
  double Area() const {
    double a = 0.0;
    for (int i = 0; i < n; ++i) {
      const int j = i + 1 < n ? i + 1 : 0;
      a += v[i][0] * v[j][1] - v[i][1] * v[j][0];
    }
    return 0.5 * std::abs(a);
  }
};

// The three bounds of PullBetweenRays, each 1 until a cell limits it.
struct PullBounds {
  double both = 1.0, only_a = 1.0, only_b = 1.0;

  // Limits them by cell (row, col), which lies outside the mask, for the triangle (sensor,
  // sensor + u, sensor + v) of twice the area det > 0.
  void Limit(int row, int col, const Vec2& sensor, const Vec2& u, const Vec2& v, double det) {
    // Wholly beyond the edge u -> v (up to rounding: the cells a ray ended on): nothing to
    // limit. The edge's normal towards the sensor, against each corner.
    const Vec2 normal(u.y() - v.y(), v.x() - u.x());  // (v - u) turned left
    const double reach = kEdgeTolerance * det;        // det = normal . (0 - u) relative
    const Vec2 corners[4] = {Vec2(col, row) - sensor, Vec2(col + 1, row) - sensor,
                             Vec2(col + 1, row + 1) - sensor, Vec2(col, row + 1) - sensor};
    bool near = false;
    for (const Vec2& w : corners) near = near || normal.dot(w - u) > reach;
    if (!near) return;
    // The corners in (alpha, beta), divided by det: a corner on a ray's end (a ray that
    // ended at a cell corner) gets exactly alpha = 1 or beta = 1.
    Clip cell;
    double least = INFINITY;
    for (const Vec2& w : corners) {
      double* ab = cell.v[cell.n++];
      ab[0] = Cross(w, v) / det;
      ab[1] = Cross(u, w) / det;
      least = std::min(least, ab[0] + ab[1]);
    }
    if (least >= 1.0 - kEdgeTolerance) return;
    cell.Cut(0, 1, 0);  // alpha >= 0
    cell.Cut(0, 0, 1);  // beta >= 0
    // The overlap's area in cells^2 is det times its area in (alpha, beta).
    if (cell.n < 3 || cell.Area() * det <= kAreaTolerance) return;
    for (int i = 0; i < cell.n; ++i) both = std::min(both, cell.v[i][0] + cell.v[i][1]);
    Clip near_a = cell;    // alpha <= 1: beta / (1 - alpha) is constant along edges ending at
    near_a.Cut(1, -1, 0);  // alpha = 1, so the least lies at a vertex with alpha < 1
    for (int i = 0; i < near_a.n; ++i) {
      if (near_a.v[i][0] < 1.0) only_b = std::min(only_b, near_a.v[i][1] / (1.0 - near_a.v[i][0]));
    }
    Clip near_b = cell;
    near_b.Cut(1, 0, -1);
    for (int i = 0; i < near_b.n; ++i) {
      if (near_b.v[i][1] < 1.0) only_a = std::min(only_a, near_b.v[i][0] / (1.0 - near_b.v[i][1]));
    }
  }

  // The choice that keeps the most of the triangle (its area scales with scale_a * scale_b).
  void Choose(double* scale_a, double* scale_b) const {
    const double b0 = std::clamp(both, 0.0, 1.0), a1 = std::clamp(only_a, 0.0, 1.0);
    const double b1 = std::clamp(only_b, 0.0, 1.0);
    *scale_a = *scale_b = b0;
    if (b1 > b0 * b0 && b1 >= a1) {
      *scale_a = 1.0;
      *scale_b = b1;
    } else if (a1 > b0 * b0) {
      *scale_a = a1;
      *scale_b = 1.0;
    }
  }
};

}  // namespace

InsidePolygonBuilder::InsidePolygonBuilder(int width, int height, int max_vertices, double epsilon)
    : width_(width), height_(height), simplifier_(max_vertices, epsilon) {
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
  ring_.reserve(2 * labels_.size());
  end_.reserve(labels_.size());
  end_stop_.resize(labels_.size());
  need_a_.resize(labels_.size());
  need_b_.resize(labels_.size());
  corner_.resize(labels_.size());
  corner_at_.resize(labels_.size());
  kept_.reserve(std::size_t(std::max(max_vertices, 3)) + 1);
  scale_.reserve(std::size_t(std::max(max_vertices, 3)) + 1);
}

void InsidePolygonBuilder::PullBetweenRays(const MaskView& mask, const Vec2& sensor, const Vec2& a,
                                           const Vec2& b, const NearSide& near, double* scale_a,
                                           double* scale_b) const {
  *scale_a = *scale_b = 1.0;
  const Vec2 u = a - sensor, v = b - sensor;
  const double det = Cross(u, v);     // twice the triangle's area
  if (det <= kAreaTolerance) return;  // no area: the edge runs along its rays
  PullBounds bounds;
  const double y0 = std::min(a.y(), b.y()) - kReach, y1 = std::max(a.y(), b.y()) + kReach;
  const int r0 = std::max(near.row_min, int(Floor(y0)));
  const int r1 = std::min(near.row_max, int(Floor(y1)));
  const int c0 = std::max(near.col_min, int(Floor(std::min(a.x(), b.x()) - kReach)));
  const int c1 = std::min(near.col_max, int(Floor(std::max(a.x(), b.x()) + kReach)));
  if ((r1 - r0 + 1) * (c1 - c0 + 1) <= 6) {
    // A short edge (the common one: two rays on one wall): every cell of its box.
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        if (!mask.Allowed(c, r)) bounds.Limit(r, c, sensor, u, v, det);
      }
    }
    bounds.Choose(scale_a, scale_b);
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
    const int from = std::max(near.col_min, int(Floor(x0 - kReach)));
    const int to = std::min(near.col_max, int(Floor(x1 + kReach)));
    if (from > to) continue;
    const std::uint64_t* line = mask.bits + std::size_t(r) * mask.words;
    for (int w = from >> 6; w <= to >> 6; ++w) {
      std::uint64_t blocked = ~line[w];
      if (w == from >> 6) blocked &= ~std::uint64_t{0} << (from & 63);
      if (w == to >> 6) blocked &= ~std::uint64_t{0} >> (63 - (to & 63));
      while (blocked != 0) {
        bounds.Limit(r, w * 64 + __builtin_ctzll(blocked), sensor, u, v, det);
        blocked &= blocked - 1;
      }
    }
  }
  bounds.Choose(scale_a, scale_b);
}

void InsidePolygonBuilder::PullInsideRing(const Vec2& sensor, int i, int j, double* scale_a,
                                          double* scale_b) const {
  const int n = int(ring_.size());
  const Vec2 a = ring_[std::size_t(i)] - sensor, b = ring_[std::size_t(j)] - sensor;
  const double det = Cross(a, b);
  *scale_a = *scale_b = 1.0;
  PullBounds bounds;
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

void InsidePolygonBuilder::Compact() {
  // Rays that end on one cell edge line (or on one border side) end on a straight line, in
  // order along it: the vertices between the first and the last of such a run change nothing.
  // Pulled vertices left their line. Rays blocked at once end at the sensor: one is enough.
  const auto inner = [](const Vec2& a, const Vec2& p, const Vec2& b) {
    return (a.x() == p.x() && p.x() == b.x()) || (a.y() == p.y() && p.y() == b.y());
  };
  const std::size_t m = ring_.size();
  std::size_t count = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const Vec2& previous = count > 0 ? ring_[count - 1] : ring_[m - 1];
    if (inner(previous, ring_[k], ring_[k + 1 < m ? k + 1 : 0])) continue;
    ring_[count++] = ring_[k];
  }
  ring_.resize(count);
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

bool InsidePolygonBuilder::RayEnds(const SensorCell& s, const std::vector<RayStop>& stops) {
  const int m = int(labels_.size());
  end_.resize(labels_.size());
  bool beyond = false;  // a ray ended outside the sensor's own cell
  for (int k = 0; k < m; ++k) {
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
    const int from = Floor(x ? p.y() : p.x()), to = Floor(x ? q.y() : q.x());
    if (from == to) return;  // one cell next to the line: the one ray a came through
    const int across = (x ? sensor.x() : sensor.y()) < a.line ? a.line - 1 : a.line;
    bool clear = true;
    for (int i = std::min(from, to); clear && i <= std::max(from, to); ++i) {
      clear = x ? mask.Allowed(across, i) : mask.Allowed(i, across);
    }
    if (clear) return;
  }
  PullBetweenRays(mask, sensor, end_[std::size_t(k)], end_[std::size_t(next)], Near(sensor, a, b),
                  &need_a_[std::size_t(k)], &need_b_[std::size_t(k)]);
}

void InsidePolygonBuilder::AssembleRing(const Vec2& sensor) {
  const int m = int(end_.size());
  ring_.clear();
  for (int k = 0; k < m; ++k) {
    const double scale =
        std::min(need_a_[std::size_t(k)], need_b_[std::size_t(k > 0 ? k - 1 : m - 1)]);
    ring_.push_back(sensor + scale * (end_[std::size_t(k)] - sensor));
    if (corner_[std::size_t(k)]) ring_.push_back(corner_at_[std::size_t(k)]);
  }
  Compact();
}

bool InsidePolygonBuilder::Build(const MaskView& mask, const SensorCell& s,
                                 const std::vector<RayStop>& stops, std::vector<Vec2>* polygon,
                                 double* error) {
  polygon->clear();
  *error = 0.0;
  if (!RayEnds(s, stops)) return false;
  const Vec2 sensor(double(s.x) / kFixedOne, double(s.y) / kFixedOne);
  // Neighbouring rays can pass a cell outside the mask between them: the ring goes round it or
  // is pulled in first, so that the simplification works on a ring whose fan lies in the mask.
  for (int k = 0; k < int(end_.size()); ++k) BetweenRays(mask, sensor, k);
  AssembleRing(sensor);
  *error = simplifier_.Simplify(ring_, sensor, &kept_);
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
  return Distinct(polygon);
}

}  // namespace freespace
