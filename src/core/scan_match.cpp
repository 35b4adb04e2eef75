// Heading correction from the scans: Gauss-Newton on the bilinearly interpolated settled
// occupancy (docs/design.md, "Heading correction").
#include "core/scan_match.hpp"

#include <algorithm>
#include <cmath>

namespace freespace {

namespace {

// A prior on the rotation, as a share of what one echo 5 m away on a sharp occupied edge
// constrains: where the echoes leave the rotation free (a scan of one round pole), it stays put.
constexpr double kPriorShare = 0.05;
constexpr double kPriorArmM = 5.0;
// Occupied evidence counts above this share of the clamp only: what many scans saw there, not
// the trail of a vehicle one or two scans saw.
constexpr double kSettledShare = 0.5;
// The least mean squared misfit a match's standard error is worked out from (echoes about 3 %
// of a settled cell's value off): a guard for a fit with nothing left, below the misfits seen
// (the simulated car park's least is 0.0056).
constexpr double kMinMisfit = 0.001;

}  // namespace

ScanMatcher::ScanMatcher(double max_step_rad, LogOdds l_max)
    : max_step_rad_(max_step_rad), l_max_(l_max) {}

double ScanMatcher::Evaluate(const MapView& map, const std::vector<EchoPoint>& echoes,
                             const Pose2D& at, Sums* sums) const {
  const double inv_res = 1.0 / map.resolution_m;
  const double lc = std::max<int>(l_max_, 1), l0 = lc * kSettledShare;
  // Settled occupied evidence only: free and unknown cells both count 0 (unknown at one half
  // would make the cells behind a face, never seen, pull every echo away from the sensor).
  const auto value = [&](LogOdds l) { return std::clamp<double>(l - l0, 0, lc - l0) / (lc - l0); };
  // World offsets to map cells: rotate by -map_yaw, scale; cell centres at integer + 0.5.
  const double mc = std::cos(map.map_yaw), ms = std::sin(map.map_yaw);
  const double c = std::cos(at.yaw), s = std::sin(at.yaw);
  double cost = 0.0;
  int used = 0;
  const std::size_t stride =
      std::max<std::size_t>(1, (echoes.size() + kMaxPoints - 1) / kMaxPoints);
  for (std::size_t i = 0; i < echoes.size(); i += stride) {
    const EchoPoint& p = echoes[i];
    const double qx = c * p.x - s * p.y, qy = s * p.x + c * p.y;  // world, from the sensor
    const double wx = at.x + qx - map.origin.x(), wy = at.y + qy - map.origin.y();
    const double cx = (mc * wx + ms * wy) * inv_res - 0.5;
    const double cy = (-ms * wx + mc * wy) * inv_res - 0.5;
    const double fx0 = std::floor(cx), fy0 = std::floor(cy);
    if (!(fx0 >= 0 && fy0 >= 0 && fx0 + 1 < map.width && fy0 + 1 < map.height)) continue;
    const LogOdds* row0 = map.log_odds + std::size_t(fy0) * map.width + std::size_t(fx0);
    const LogOdds* row1 = row0 + map.width;
    // Only echoes beside a settled occupied cell: an echo in space the map holds free or
    // unknown (a vehicle that moved there, a face seen for the first time) says nothing here.
    if (std::max({row0[0], row0[1], row1[0], row1[1]}) <= l0) continue;
    const double v00 = value(row0[0]), v10 = value(row0[1]);
    const double v01 = value(row1[0]), v11 = value(row1[1]);
    const double fx = cx - fx0, fy = cy - fy0;
    const double m = (1 - fy) * ((1 - fx) * v00 + fx * v10) + fy * ((1 - fx) * v01 + fx * v11);
    const double r = 1.0 - m;
    cost += r * r;
    ++used;
    if (sums == nullptr) continue;
    // dM/d(cell x, cell y) per metre, in world axes, then along the rotation about the sensor.
    const double gx = ((1 - fy) * (v10 - v00) + fy * (v11 - v01)) * inv_res;
    const double gy = ((1 - fx) * (v01 - v00) + fx * (v11 - v10)) * inv_res;
    const double wgx = mc * gx - ms * gy, wgy = ms * gx + mc * gy;
    const double j = -qy * wgx + qx * wgy;
    sums->h += j * j;
    sums->g += j * r;
  }
  if (sums != nullptr) sums->points = used;
  return used > 0 ? cost / used : 0.0;
}

MatchResult ScanMatcher::Match(const MapView& map, const std::vector<EchoPoint>& echoes,
                               const Pose2D& sensor) const {
  MatchResult out;
  if (map.log_odds == nullptr || !(map.resolution_m > 0)) return out;
  Pose2D at = sensor;
  const double prior =
      kPriorShare * kPriorArmM * kPriorArmM / (map.resolution_m * map.resolution_m);
  for (int it = 0; it < kIterations; ++it) {
    Sums sums;
    const double cost = Evaluate(map, echoes, at, &sums);
    if (it == 0) {
      out.cost_before = cost;
      out.points = sums.points;
    }
    if (sums.points < kMinPoints) return out;
    const double step = sums.g / (sums.h + prior * sums.points);
    if (!std::isfinite(step)) return out;
    at.yaw = std::clamp(at.yaw + step, sensor.yaw - max_step_rad_, sensor.yaw + max_step_rad_);
  }
  Sums final_sums;
  out.cost_after = Evaluate(map, echoes, at, &final_sums);
  if (final_sums.points < kMinPoints || !(out.cost_after < out.cost_before)) return out;
  out.applied = true;
  // A fit with no misfit left (every echo on saturated cells) still knows the rotation only to
  // the cells' quantization: a misfit of at least kMinMisfit.
  out.std_rad = std::sqrt(std::max(out.cost_after, kMinMisfit) / std::max(final_sums.h, 1e-30));
  out.dyaw = at.yaw - sensor.yaw;
  return out;
}

double HeadingFilter::Share(double match_std_rad, double t) {
  const double drift = drift_rad_per_s_ * std::max(0.0, t - t_);
  const double variance = variance_ + drift * drift;
  const double noise = kMisfitCorrelation * match_std_rad;
  const double share = variance / (variance + noise * noise);
  if (!std::isfinite(share)) return 0.0;
  variance_ = (1.0 - share) * variance;
  t_ = std::max(t_, t);
  return share;
}

}  // namespace freespace
