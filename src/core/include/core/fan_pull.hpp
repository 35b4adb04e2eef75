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
    fan::Clip cell;
    double least = INFINITY;
    for (int k = 0; k < 4; ++k) {
      double* ab = cell.v[cell.n++];
      ab[0] = (wx[k] * v.y() - wy[k] * v.x()) / det;
      ab[1] = (u.x() * wy[k] - u.y() * wx[k]) / det;
      least = std::min(least, ab[0] + ab[1]);
    }
    if (least >= 1.0 - fan::kEdgeTolerance) return false;
    cell.Cut(0, 1, 0);  // alpha >= 0
    cell.Cut(0, 0, 1);  // beta >= 0
    // The overlap's area in cells^2 is det times its area in (alpha, beta).
    if (cell.n < 3 || cell.Area() * det <= fan::kAreaTolerance) return false;
    for (int i = 0; i < cell.n; ++i) both = std::min(both, cell.v[i][0] + cell.v[i][1]);
    fan::Clip near_a = cell;  // alpha <= 1: beta / (1 - alpha) is constant along edges ending at
    near_a.Cut(1, -1, 0);     // alpha = 1, so the least lies at a vertex with alpha < 1
    for (int i = 0; i < near_a.n; ++i) {
      if (near_a.v[i][0] < 1.0) only_b = std::min(only_b, near_a.v[i][1] / (1.0 - near_a.v[i][0]));
    }
    fan::Clip near_b = cell;
    near_b.Cut(1, 0, -1);
    for (int i = 0; i < near_b.n; ++i) {
      if (near_b.v[i][1] < 1.0) only_a = std::min(only_a, near_b.v[i][0] / (1.0 - near_b.v[i][1]));
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
