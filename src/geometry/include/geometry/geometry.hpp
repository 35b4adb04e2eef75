// Plane geometry shared by the simulator and the quality metrics: polygons as vertex lists
// (counter-clockwise, closed implicitly), exact areas, convex clipping, point tests, rigid
// transforms and ray-segment intersection. All in double metres.
#pragma once

#include <vector>

#include "freespace/types.hpp"

namespace freespace::geometry {

using Polygon = std::vector<Vec2>;

// Shoelace area: positive for counter-clockwise vertex order.
double SignedArea(const Polygon& polygon);

// The part of `subject` inside `window` (Sutherland-Hodgman). `window` must be convex and
// counter-clockwise; `subject` may be concave: the result then can hold zero-width bridges
// along the window's edges, but its area is exact.
Polygon ClipToConvex(const Polygon& subject, const Polygon& window);

// Area of `subject` inside the axis-aligned box [x0, x1] x [y0, y1] (exact, any simple
// polygon, either orientation: the absolute value is returned).
double AreaInBox(const Polygon& subject, double x0, double y0, double x1, double y1);

// True when `p` lies inside or on the convex counter-clockwise polygon.
bool InsideConvex(const Polygon& convex, const Vec2& p);

// Even-odd point in polygon; points exactly on an edge may go either way.
bool InsidePolygon(const Polygon& polygon, const Vec2& p);

// The rigid transform `pose` applied to a point given in the pose's frame.
Vec2 Transform(const Pose2D& pose, const Vec2& local);
Polygon Transform(const Pose2D& pose, const Polygon& local);
// a composed with b: the pose b (given in a's frame) in a's parent frame.
Pose2D Compose(const Pose2D& a, const Pose2D& b);
Pose2D Inverse(const Pose2D& a);

// Distance t >= 0 along the ray origin + t * dir (dir of unit length) to the segment [a, b],
// or a negative value when the ray misses it. A ray through an endpoint hits.
double RaySegment(const Vec2& origin, const Vec2& dir, const Vec2& a, const Vec2& b);

// Shapes, counter-clockwise.
// A rectangle `length` along the heading `yaw` and `width` across, centred at `centre`.
Polygon Rectangle(const Vec2& centre, double length, double width, double yaw);
// An axis-aligned box.
Polygon Box(double x0, double y0, double x1, double y1);
// A regular polygon of `sides` vertices on a circle of `radius` (small round objects).
Polygon RegularPolygon(const Vec2& centre, double radius, int sides, double phase = 0.0);

}  // namespace freespace::geometry
