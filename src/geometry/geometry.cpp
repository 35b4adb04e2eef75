// Plane geometry: see geometry.hpp.
#include "geometry/geometry.hpp"

#include <cmath>

namespace freespace::geometry {
namespace {

double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

double SignedArea(const Polygon& polygon) {
  const std::size_t n = polygon.size();
  if (n < 3) return 0.0;
  // Relative to the first vertex: keeps the sum exact-ish far from the world origin.
  const Vec2& o = polygon[0];
  double twice = 0.0;
  for (std::size_t i = 1; i + 1 < n; ++i) twice += Cross(polygon[i] - o, polygon[i + 1] - o);
  return 0.5 * twice;
}

Polygon ClipToConvex(const Polygon& subject, const Polygon& window) {
  Polygon output = subject, input;
  const std::size_t m = window.size();
  for (std::size_t e = 0; e < m && !output.empty(); ++e) {
    const Vec2& a = window[e];
    const Vec2 edge = window[(e + 1) % m] - a;
    input.swap(output);
    output.clear();
    const std::size_t n = input.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2& p = input[i];
      const Vec2& q = input[(i + 1) % n];
      const double dp = Cross(edge, p - a), dq = Cross(edge, q - a);  // >= 0: inside (left)
      if (dp >= 0.0) output.push_back(p);
      if ((dp >= 0.0) != (dq >= 0.0)) output.push_back(p + (q - p) * (dp / (dp - dq)));
    }
  }
  return output;
}

double AreaInBox(const Polygon& subject, double x0, double y0, double x1, double y1) {
  return std::abs(SignedArea(ClipToConvex(subject, Box(x0, y0, x1, y1))));
}

bool InsideConvex(const Polygon& convex, const Vec2& p) {
  const std::size_t n = convex.size();
  if (n < 3) return false;
  for (std::size_t i = 0; i < n; ++i) {
    if (Cross(convex[(i + 1) % n] - convex[i], p - convex[i]) < 0.0) return false;
  }
  return true;
}

bool InsidePolygon(const Polygon& polygon, const Vec2& p) {
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < a.x() + (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y())) {
      inside = !inside;
    }
  }
  return inside;
}

Vec2 Transform(const Pose2D& pose, const Vec2& local) {
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  return {pose.x + c * local.x() - s * local.y(), pose.y + s * local.x() + c * local.y()};
}

Polygon Transform(const Pose2D& pose, const Polygon& local) {
  Polygon out;
  out.reserve(local.size());
  for (const Vec2& p : local) out.push_back(Transform(pose, p));
  return out;
}

Pose2D Compose(const Pose2D& a, const Pose2D& b) {
  const Vec2 p = Transform(a, Vec2(b.x, b.y));
  return {p.x(), p.y(), std::remainder(a.yaw + b.yaw, 2.0 * M_PI)};
}

Pose2D Inverse(const Pose2D& a) {
  const double c = std::cos(a.yaw), s = std::sin(a.yaw);
  return {-(c * a.x + s * a.y), s * a.x - c * a.y, -a.yaw};
}

double RaySegment(const Vec2& origin, const Vec2& dir, const Vec2& a, const Vec2& b) {
  const Vec2 e = b - a;
  const double denom = Cross(dir, e);
  if (denom == 0.0) return -1.0;  // parallel: a grazing ray sees the neighbouring edges
  const Vec2 w = a - origin;
  const double t = Cross(w, e) / denom;
  const double u = Cross(w, dir) / denom;
  if (t < 0.0 || u < 0.0 || u > 1.0) return -1.0;
  return t;
}

Polygon Rectangle(const Vec2& centre, double length, double width, double yaw) {
  const Pose2D pose{centre.x(), centre.y(), yaw};
  const double hl = 0.5 * length, hw = 0.5 * width;
  return Transform(pose, Polygon{{-hl, -hw}, {hl, -hw}, {hl, hw}, {-hl, hw}});
}

Polygon Box(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

Polygon RegularPolygon(const Vec2& centre, double radius, int sides, double phase) {
  Polygon out;
  out.reserve(sides);
  for (int i = 0; i < sides; ++i) {
    const double a = phase + 2.0 * M_PI * i / sides;
    out.emplace_back(centre.x() + radius * std::cos(a), centre.y() + radius * std::sin(a));
  }
  return out;
}

}  // namespace freespace::geometry
