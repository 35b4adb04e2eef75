// The mover layer's inside test (movers.hpp): a point against a scan's outline, one at a time
// or a whole scan's points in one pass.
#include <algorithm>
#include <cmath>

#include "core/movers.hpp"

namespace freespace {

namespace {

// InsideOutline() of the point (x, y) in the outline's sensor frame at angle a (FastAtan2).
bool InsideAt(const MoverTracker::Outline& outline, double x, double y, float a,
              double bin_width_rad, double margin, int spread, std::size_t* at) {
  const std::vector<float>& angle = outline.angle;
  const std::size_t n = angle.size();
  if (n < 2) return false;
  if (a < angle.front()) a += float(2.0 * M_PI);  // the outline's angles run from the first on
  if (!(a >= angle.front()) || !(a < angle.back())) return false;
  // The first beam after a: a few steps from the hint (consecutive points lie at neighbouring
  // angles), else a binary search.
  std::size_t i = (at != nullptr && *at >= 1 && *at < n) ? *at : 0;
  for (int step = 0; i != 0 && step < 8; ++step) {
    if (angle[i - 1] > a) {
      --i;
    } else if (angle[i] <= a) {
      ++i;
    } else {
      break;
    }
    if (i == 0 || i == n) i = 0;
  }
  if (i == 0 || angle[i - 1] > a || angle[i] <= a)
    i = std::size_t(std::upper_bound(angle.begin(), angle.end(), a) - angle.begin());
  if (at != nullptr) *at = i;
  // Beams more than two bins apart leave no outline between them.
  if (angle[i] - angle[i - 1] > 2.5 * bin_width_rad) return false;
  const std::size_t lo = i - 1 - std::min(i - 1, std::size_t(spread));
  const std::size_t hi = std::min(n - 1, i + std::size_t(spread));
  float nearest = outline.range[lo];
  for (std::size_t k = lo + 1; k <= hi; ++k) nearest = std::min(nearest, outline.range[k]);
  const double reach = nearest - margin;
  return reach > 0.0 && x * x + y * y < reach * reach;
}

}  // namespace

bool InsideOutline(const MoverTracker::Outline& outline, const Vec2& p, double bin_width_rad,
                   double margin, int spread, std::size_t* at) {
  const double c = outline.cos_yaw, s = outline.sin_yaw;
  const double dx = p.x() - outline.pose.x, dy = p.y() - outline.pose.y;
  const double x = c * dx + s * dy, y = -s * dx + c * dy;
  return InsideAt(outline, x, y, FastAtan2(float(y), float(x)), bin_width_rad, margin, spread, at);
}

void ToOutlineFrame(const MoverTracker::Outline& outline, const std::vector<Vec2>& points,
                    OutlineFrame* frame) {
  const std::size_t n = points.size();
  frame->x.resize(n);
  frame->y.resize(n);
  frame->angle.resize(n);
  const double c = outline.cos_yaw, s = outline.sin_yaw;
  const double px = outline.pose.x, py = outline.pose.y;
  double* fx = frame->x.data();
  double* fy = frame->y.data();
  float* fa = frame->angle.data();
  for (std::size_t k = 0; k < n; ++k) {
    const double dx = points[k].x() - px, dy = points[k].y() - py;
    const double x = c * dx + s * dy, y = -s * dx + c * dy;
    fx[k] = x;
    fy[k] = y;
    fa[k] = FastAtan2(float(y), float(x));
  }
}

bool InsideOutlineAt(const MoverTracker::Outline& outline, const OutlineFrame& frame, std::size_t k,
                     double bin_width_rad, double margin, int spread, std::size_t* at) {
  return InsideAt(outline, frame.x[k], frame.y[k], frame.angle[k], bin_width_rad, margin, spread,
                  at);
}

}  // namespace freespace
