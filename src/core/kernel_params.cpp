// Kernel parameters from the config (fixed-point log-odds and thresholds), and C_Edge from the
// stop cells of the border rays, shared by both backends.
#include <algorithm>
#include <cmath>

#include "core/backend.hpp"

namespace freespace {

LogOdds LogOddsFromProbability(double p) {
  const double l = std::log(p / (1.0 - p)) * kLogOddsScale;
  return LogOdds(std::clamp<long>(std::lround(l), -32767, 32767));
}

LogOdds LogOddsThreshold(double p) {
  const double l = std::log(p / (1.0 - p)) * kLogOddsScale;
  return LogOdds(std::clamp<long>(long(std::floor(l)), -32767, 32767));
}

double ProbabilityFromLogOdds(LogOdds l) {
  return 1.0 / (1.0 + std::exp(-double(l) / kLogOddsScale));
}

KernelParams MakeKernelParams(const Config& config) {
  KernelParams p;
  p.width = config.map.width_cells;
  p.height = config.map.height_cells;
  p.l_free = LogOddsFromProbability(config.sensor_model.p_free);
  p.l_occupied = LogOddsFromProbability(config.sensor_model.p_occupied);
  p.l_min = LogOddsFromProbability(config.sensor_model.p_min);
  p.l_max = LogOddsFromProbability(config.sensor_model.p_max);
  p.t_low = LogOddsThreshold(config.classify.t_low);
  p.t_high = LogOddsThreshold(config.classify.t_high);
  // The opening's disk about the vehicle's width: 2h + 1 cells across, closest to width /
  // resolution.
  const double side = config.classify.vehicle_width_m / config.map.resolution_m;
  p.opening_radius = int(std::max(0L, std::lround((side - 1.0) / 2.0)));
  p.veto_echoes = config.classify.veto_current_echoes;
  p.margin_cells = config.polygon.margin_cells;
  const double half_angle = config.polygon.margin_cone_deg * M_PI / 180.0;
  p.margin_all = config.polygon.margin_cone_deg >= 180.0;
  p.cone_cos = std::int32_t(std::lround(std::cos(half_angle) * kConeOne));
  p.cone_sin = std::int32_t(std::lround(std::sin(half_angle) * kConeOne));
  return p;
}

bool OutlineColumns(std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1, int row,
                    int width, int* c_lo, int* c_hi) {
  const std::int64_t top = std::int64_t(row) * kFixedOne, bottom = top + kFixedOne;
  if (std::max(y0, y1) < top || std::min(y0, y1) > bottom) return false;
  std::int64_t xa = x0, xb = x1;
  if (y0 != y1) {
    // x on the edge's line at the part's two ends (a vertex's own x where the part ends at one),
    // floor-divided with a positive denominator.
    const std::int64_t sign = y1 > y0 ? 1 : -1, den = sign * (y1 - y0);
    const auto x_at = [&](std::int64_t y) {
      if (y == y0) return x0;
      if (y == y1) return x1;
      return x0 + FloorDiv(sign * (y - y0) * (x1 - x0), den);
    };
    xa = x_at(std::max(std::min(y0, y1), top));
    xb = x_at(std::min(std::max(y0, y1), bottom));
  }
  const std::int64_t lo = FloorDiv(std::min(xa, xb), kFixedOne);
  const std::int64_t hi = FloorDiv(std::max(xa, xb), kFixedOne);
  if (hi < 0 || lo >= width) return false;
  *c_lo = int(std::max<std::int64_t>(lo, 0));
  *c_hi = int(std::min<std::int64_t>(hi, width - 1));
  return true;
}

void CollectEdges(const std::int32_t* stop, int labels, int width, std::uint64_t* seen,
                  std::vector<CellIndex>* edges) {
  edges->clear();
  std::int32_t last = -1;
  for (int l = 0; l < labels; ++l) {
    const std::int32_t s = stop[l];
    // Neighbouring rays often stop at the same cell: only a new cell needs the bitset.
    if (s == last) continue;
    last = s;
    std::uint64_t& word = seen[s >> 6];
    const std::uint64_t bit = std::uint64_t{1} << (s & 63);
    if (word & bit) continue;
    edges->push_back({s / width, s % width});
    word |= bit;
  }
  // Every bit set above belongs to an edge cell, so clearing their words clears them all.
  for (const CellIndex& e : *edges) seen[(e.row * width + e.col) >> 6] = 0;
}

}  // namespace freespace
