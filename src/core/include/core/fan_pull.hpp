// The bounds of the conservative polygon's fan triangles (core/inside_polygon.hpp): how far the
// two far ends of a triangle (sensor, a, b) may be scaled toward the sensor so that it overlaps
// no given cell, worked out in the triangle's barycentric coordinates (alpha along a, beta
// along b).
#pragma once

#include <algorithm>
#include <cmath>

#include "freespace/types.hpp"

namespace freespace {
namespace fan {

inline double Cross(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

// Below this area (cells^2) a triangle or an overlap counts as none: rounding only.
constexpr double kAreaTolerance = 1e-9;
// A cell whose part in a triangle lies within this fraction of the far edge is beyond it: the
// strip holds less than 1e-6 cells^2 of any triangle in a map of 8192 x 8192 cells.
constexpr double kEdgeTolerance = 1e-14;

// The part of the convex polygon with vertices (a[i], b[i]), i < n, where f >= 0 (f affine,
// f[i] its value at vertex i), into (oa, ob), at most n + 1 vertices (Sutherland-Hodgman);
// returns how many.
inline int CutBy(const double* f, const double* a, const double* b, int n, double* oa, double* ob) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const int j = i + 1 < n ? i + 1 : 0;
    const double fp = f[i], fq = f[j];
    if (fp >= 0) {
      oa[m] = a[i];
      ob[m] = b[i];
      ++m;
    }
    if ((fp >= 0) != (fq >= 0)) {
      const double t = fp / (fp - fq);
      oa[m] = a[i] + t * (a[j] - a[i]);
      ob[m] = b[i] + t * (b[j] - b[i]);
      ++m;
    }
  }
  return m;
}

// The area of the polygon (a[i], b[i]), i < n.
inline double Area(const double* a, const double* b, int n) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) {
    const int j = i + 1 < n ? i + 1 : 0;
    s += a[i] * b[j] - b[i] * a[j];
  }
  return 0.5 * std::abs(s);
}

}  // namespace fan

// How far the ends a = sensor + u and b = sensor + v of a fan triangle may stay so that it
// overlaps no cell outside the mask: three bounds, each 1 until a cell limits it.
struct FanPull {
  double both = 1.0, only_a = 1.0, only_b = 1.0;

  // Limits them by cell (row, col), which lies outside the mask, for the triangle (sensor,
  // sensor + u, sensor + v) of twice the area det > 0. False when the cell reaches no part of
  // the wedge on the sensor's side of u -> v.
  bool Limit(int row, int col, const Vec2& sensor, const Vec2& u, const Vec2& v, double det) {
    // Wholly beyond the edge u -> v (up to rounding: the cells a ray ended on): nothing to
    // limit. The edge's normal towards the sensor, against each corner.
    const double nx = u.y() - v.y(), ny = v.x() - u.x();  // (v - u) turned left
    const double reach = fan::kEdgeTolerance * det;       // det = normal . (0 - u) relative
    // The corners relative to the sensor, as plain numbers: built as small vectors they went
    // through the stack, and each load waited for two stores.
    const double x0 = col - sensor.x(), x1 = (col + 1) - sensor.x();
    const double y0 = row - sensor.y(), y1 = (row + 1) - sensor.y();
    const double wx[4] = {x0, x1, x1, x0}, wy[4] = {y0, y0, y1, y1};
    bool near = false;
    for (int k = 0; k < 4; ++k) near = near || nx * (wx[k] - u.x()) + ny * (wy[k] - u.y()) > reach;
    if (!near) return false;
    // Wholly on the far side of a ray (beta <= 0 or alpha <= 0 at every corner): no area in
    // the wedge, as the clipping below would find.
    bool before_a = true, beyond_b = true;
    for (int k = 0; k < 4; ++k) {
      before_a = before_a && u.x() * wy[k] - u.y() * wx[k] <= 0.0;
      beyond_b = beyond_b && wx[k] * v.y() - wy[k] * v.x() <= 0.0;
    }
    if (before_a || beyond_b) return false;
    // The corners in (alpha, beta), divided by det: a corner on a ray's end (a ray that
    // ended at a cell corner) gets exactly alpha = 1 or beta = 1.
    double al[8], be[8];  // room for the square cut by three half-planes
    double least = INFINITY;
    for (int k = 0; k < 4; ++k) {
      al[k] = (wx[k] * v.y() - wy[k] * v.x()) / det;
      be[k] = (u.x() * wy[k] - u.y() * wx[k]) / det;
      least = std::min(least, al[k] + be[k]);
    }
    if (least >= 1.0 - fan::kEdgeTolerance) return false;
    double ta[8], tb[8], f[8];
    for (int k = 0; k < 4; ++k) f[k] = al[k];
    int n = fan::CutBy(f, al, be, 4, ta, tb);  // alpha >= 0
    for (int k = 0; k < n; ++k) f[k] = tb[k];
    n = fan::CutBy(f, ta, tb, n, al, be);  // beta >= 0
    // The overlap's area in cells^2 is det times its area in (alpha, beta).
    if (n < 3 || fan::Area(al, be, n) * det <= fan::kAreaTolerance) return false;
    for (int i = 0; i < n; ++i) both = std::min(both, al[i] + be[i]);
    // alpha <= 1: beta / (1 - alpha) is constant along edges ending at alpha = 1, so the least
    // lies at a vertex with alpha < 1. Likewise beta <= 1 for only_a.
    for (int k = 0; k < n; ++k) f[k] = 1.0 - al[k];
    int m = fan::CutBy(f, al, be, n, ta, tb);
    for (int i = 0; i < m; ++i) {
      if (ta[i] < 1.0) only_b = std::min(only_b, tb[i] / (1.0 - ta[i]));
    }
    for (int k = 0; k < n; ++k) f[k] = 1.0 - be[k];
    m = fan::CutBy(f, al, be, n, ta, tb);
    for (int i = 0; i < m; ++i) {
      if (tb[i] < 1.0) only_a = std::min(only_a, ta[i] / (1.0 - tb[i]));
    }
    return true;
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

}  // namespace freespace
