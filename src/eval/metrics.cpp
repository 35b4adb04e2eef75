// Quality metrics: see metrics.hpp and docs/metrics.md. Areas are exact: obstacle and polygon
// parts inside a cell come from convex clipping; cells that no polygon edge can touch are
// decided by their centre alone.
#include "eval/metrics.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "eval/stage_stats.hpp"

namespace freespace {
namespace {

using geometry::Polygon;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// A cell is truly occupied when obstacles cover more than this fraction of it (only to keep an
// obstacle edge lying exactly on a cell border from counting through rounding).
constexpr double kOccupiedFraction = 1e-6;

double Ratio(double a, double b) { return b > 0.0 ? a / b : kNaN; }

nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

// World offsets turned into the map's axes (by -map_yaw); divided by the resolution, cells.
Eigen::Matrix2d ToMapAxes(const MapView& map) {
  return Eigen::Rotation2Dd(-map.map_yaw).toRotationMatrix();
}

// Cell coordinates (continuous: cell (r, c) spans [c, c+1) x [r, r+1)) of world points.
Polygon ToCells(const Polygon& world, const MapView& map) {
  const Eigen::Matrix2d turn = ToMapAxes(map);
  Polygon out;
  out.reserve(world.size());
  for (const Vec2& p : world) out.push_back(turn * (p - map.origin) / map.resolution_m);
  return out;
}

struct Bounds {
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  explicit Bounds(const Polygon& p) {
    for (const Vec2& v : p) {
      x0 = std::min(x0, v.x());
      y0 = std::min(y0, v.y());
      x1 = std::max(x1, v.x());
      y1 = std::max(y1, v.y());
    }
  }
};

// The x of every crossing of `p`'s edges with the line y = `y` (half-open in y), sorted.
void RowCrossings(const Polygon& p, double y, std::vector<double>* xs) {
  xs->clear();
  const std::size_t n = p.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = p[i];
    const Vec2& b = p[j];
    if ((a.y() > y) != (b.y() > y)) {
      xs->push_back(a.x() + (b.x() - a.x()) * (y - a.y()) / (b.y() - a.y()));
    }
  }
  std::sort(xs->begin(), xs->end());
}

// Marks the cells of `mask` whose centre lies inside `p` (cell coordinates, even-odd).
void FillCentres(const Polygon& p, int width, int height, std::vector<std::uint8_t>* mask,
                 std::vector<double>* xs) {
  if (p.size() < 3) return;
  const Bounds b(p);
  const int r0 = std::max(0, int(std::floor(b.y0 - 0.5))),
            r1 = std::min(height - 1, int(std::ceil(b.y1)));
  for (int r = r0; r <= r1; ++r) {
    RowCrossings(p, r + 0.5, xs);
    for (std::size_t k = 0; k + 1 < xs->size(); k += 2) {
      // Centres c + 0.5 in [x_k, x_k+1).
      const int c0 = std::max(0, int(std::ceil((*xs)[k] - 0.5)));
      const int c1 = std::min(width - 1, int(std::ceil((*xs)[k + 1] - 0.5)) - 1);
      for (int c = c0; c <= c1; ++c) (*mask)[std::size_t(r) * width + c] = 1;
    }
  }
}

}  // namespace

nlohmann::json ScanMetrics::ToJson() const {
  return {{"scan", scan},
          {"t_s", t},
          {"observed", observed},
          {"observed_occupied", observed_occupied},
          {"correct", correct},
          {"accuracy", Number(accuracy)},
          {"false_free", false_free},
          {"false_free_majority", false_free_majority},
          {"false_free_moving", false_free_moving},
          {"false_free_rate", Number(false_free_rate)},
          {"false_free_mask", false_free_mask},
          {"false_free_mask_rate", Number(false_free_mask_rate)},
          {"false_occupied", false_occupied},
          {"errors_at_border", errors_at_border},
          {"polygon_area_m2", polygon_area_m2},
          {"intrusion_m2", intrusion_m2},
          {"intrusion_geometric_m2", intrusion_geometric_m2},
          {"intrusion_moving_m2", intrusion_moving_m2},
          {"intrusion_mask_m2", intrusion_mask_m2},
          {"intrusion_out_of_view_m2", Number(intrusion_out_of_view_m2)},
          {"reference_free_m2", reference_free_m2},
          {"covered_free_m2", covered_free_m2},
          {"coverage", Number(coverage)},
          {"reference_in_mask_m2", reference_in_mask_m2},
          {"coverage_mask", Number(coverage_mask)},
          {"reference_star_m2", reference_star_m2},
          {"coverage_star", Number(coverage_star)},
          {"reference_seen_m2", reference_seen_m2},
          {"covered_seen_m2", covered_seen_m2},
          {"coverage_seen", Number(coverage_seen)}};
}

void QualityEvaluator::Cover(const MapView& map, const TruthFrame& truth) {
  const int w = map.width, h = map.height;
  covered_.assign(std::size_t(w) * h, 0.0f);
  moving_.assign(std::size_t(w) * h, 0);
  for (std::size_t i = 0; i < truth.obstacles.size(); ++i) {
    const Polygon& world = truth.obstacles[i];
    const bool moving = i < truth.moving.size() && truth.moving[i];
    if (world.size() < 3) continue;
    const Polygon p = ToCells(world, map);
    const Bounds b(p);
    const int c0 = std::max(0, int(std::floor(b.x0))), c1 = std::min(w - 1, int(std::floor(b.x1)));
    const int r0 = std::max(0, int(std::floor(b.y0))), r1 = std::min(h - 1, int(std::floor(b.y1)));
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        const bool full = geometry::InsideConvex(p, Vec2(c, r)) &&
                          geometry::InsideConvex(p, Vec2(c + 1, r)) &&
                          geometry::InsideConvex(p, Vec2(c, r + 1)) &&
                          geometry::InsideConvex(p, Vec2(c + 1, r + 1));
        const double area = full ? 1.0 : geometry::AreaInBox(p, c, r, c + 1, r + 1);
        float& cell = covered_[std::size_t(r) * w + c];
        cell = float(std::min(1.0, cell + area));
        if (moving && area > kOccupiedFraction) moving_[std::size_t(r) * w + c] = 1;
      }
    }
  }
}

void QualityEvaluator::PolygonCells(const MapView& map, const std::vector<Vec2>& world) {
  const int w = map.width, h = map.height;
  const std::size_t cells = std::size_t(w) * h;
  polygon_.assign(cells, 0.0f);
  if (world.size() < 3) return;
  const Polygon p = ToCells(world, map);
  // Cells an edge may touch: samples at most half a cell apart, each with its 8 neighbours
  // (a piece of edge shorter than a cell cannot leave that neighbourhood).
  edge_.assign(cells, 0);
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = p[i];
    const Vec2& b = p[(i + 1) % n];
    const int steps = int(std::ceil((b - a).norm() / 0.5)) + 1;
    for (int k = 0; k <= steps; ++k) {
      const Vec2 q = a + (b - a) * (double(k) / steps);
      const int qc = int(std::floor(q.x())), qr = int(std::floor(q.y()));
      for (int r = std::max(0, qr - 1); r <= std::min(h - 1, qr + 1); ++r) {
        for (int c = std::max(0, qc - 1); c <= std::min(w - 1, qc + 1); ++c) {
          edge_[std::size_t(r) * w + c] = 1;
        }
      }
    }
  }
  scratch_.assign(cells, 0);
  FillCentres(p, w, h, &scratch_, &crossings_);
  for (std::size_t i = 0; i < cells; ++i) {
    if (edge_[i]) {
      const int r = int(i / w), c = int(i % w);
      polygon_[i] = float(std::min(1.0, geometry::AreaInBox(p, c, r, c + 1, r + 1)));
    } else {
      polygon_[i] = scratch_[i] ? 1.0f : 0.0f;
    }
  }
}

void QualityEvaluator::See(const MapView& map, const Polygon& visible) {
  const int w = map.width, h = map.height;
  const std::size_t cells = std::size_t(w) * h;
  // Seen cells carry over a shift of the map by whole cells; a turn of its axes starts afresh.
  bool restart = !have_seen_ || w != seen_width_ || h != seen_height_ ||
                 std::abs(std::remainder(map.map_yaw - seen_yaw_, 2.0 * M_PI)) > 1e-9;
  int kx = 0, ky = 0;
  if (!restart) {
    const Vec2 d = ToMapAxes(map) * (map.origin - seen_origin_) / map.resolution_m;
    kx = int(std::lround(d.x()));
    ky = int(std::lround(d.y()));
    restart = std::abs(d.x() - kx) > 1e-6 || std::abs(d.y() - ky) > 1e-6;
  }
  if (restart) {
    seen_.assign(cells, 0);
  } else if (kx != 0 || ky != 0) {
    // The map's cell (r, c) is the old cell (r + ky, c + kx).
    scratch_.assign(cells, 0);
    for (int r = 0; r < h; ++r) {
      const int old_r = r + ky;
      if (old_r < 0 || old_r >= h) continue;
      for (int c = 0; c < w; ++c) {
        const int old_c = c + kx;
        if (old_c >= 0 && old_c < w)
          scratch_[std::size_t(r) * w + c] = seen_[std::size_t(old_r) * w + old_c];
      }
    }
    seen_.swap(scratch_);
  }
  have_seen_ = true;
  seen_origin_ = map.origin;
  seen_yaw_ = map.map_yaw;
  seen_width_ = w;
  seen_height_ = h;
  FillCentres(ToCells(visible, map), w, h, &seen_, &crossings_);
}

namespace {

// Whether the straight line from `from` (map cells) to the centre of cell (row, col) passes
// through free-mask cells only, leaving out the cell it starts in and the cell itself (a grid
// walk; at a grid corner it steps along x first).
bool SeesThroughFree(const MapView& map, const Vec2& from, int row, int col) {
  const Vec2 to(col + 0.5, row + 0.5);
  const Vec2 d = to - from;
  int c = int(std::floor(from.x())), r = int(std::floor(from.y()));
  const int step_c = d.x() > 0 ? 1 : -1, step_r = d.y() > 0 ? 1 : -1;
  const double dx = std::abs(d.x()), dy = std::abs(d.y());
  // The line's parameter at the next vertical and horizontal grid line, and per cell.
  double next_x = dx > 0 ? ((step_c > 0 ? c + 1 - from.x() : from.x() - c) / dx) : INFINITY;
  double next_y = dy > 0 ? ((step_r > 0 ? r + 1 - from.y() : from.y() - r) / dy) : INFINITY;
  const double per_x = dx > 0 ? 1.0 / dx : INFINITY, per_y = dy > 0 ? 1.0 / dy : INFINITY;
  while (!(c == col && r == row)) {
    if (next_x <= next_y) {
      c += step_c;
      next_x += per_x;
    } else {
      r += step_r;
      next_y += per_y;
    }
    if (c == col && r == row) break;
    if (c < 0 || r < 0 || c >= map.width || r >= map.height) return false;
    if (!map.free[std::size_t(r) * map.width + c]) return false;
  }
  return true;
}

// A scanner's aperture as its visibility polygon (map cells) spans it: the polygon's first
// vertex is the scanner, the next its first beam's end and the last its last beam's end.
struct Aperture {
  Vec2 origin;
  double first = 0.0, span = 0.0;  // radians: the first beam's bearing, and on to the last

  static double Wrap(double a) {  // into [0, 2 pi)
    a = std::fmod(a, 2.0 * M_PI);
    return a < 0.0 ? a + 2.0 * M_PI : a;
  }
  static double Bearing(const Vec2& from, const Vec2& to) {
    return std::atan2(to.y() - from.y(), to.x() - from.x());
  }
  explicit Aperture(const Polygon& cells)
      : origin(cells[0]),
        first(Bearing(cells[0], cells[1])),
        span(Wrap(Bearing(cells[0], cells.back()) - first)) {}
  bool Holds(const Vec2& p) const { return Wrap(Bearing(origin, p) - first) <= span; }
};

// The apertures of the scanners of `truth` (none without a visibility polygon).
std::vector<Aperture> Apertures(const TruthFrame& truth, const MapView& map) {
  std::vector<Aperture> out;
  if (truth.visible.size() >= 3) out.emplace_back(ToCells(truth.visible, map));
  for (const Polygon& more : truth.visible_more) {
    if (more.size() >= 3) out.emplace_back(ToCells(more, map));
  }
  return out;
}

}  // namespace

ScanMetrics QualityEvaluator::Evaluate(const MapView& map, const std::vector<Vec2>& polygon,
                                       const TruthFrame& truth, const Vec2& centre) {
  Cover(map, truth);
  PolygonCells(map, polygon);
  See(map, truth.visible);
  for (const Polygon& more : truth.visible_more) See(map, more);
  const bool score_in_sight = truth.in_sight.size() >= 3;
  in_sight_.assign(std::size_t(map.width) * map.height, 0);
  if (score_in_sight) {
    FillCentres(ToCells(truth.in_sight, map), map.width, map.height, &in_sight_, &crossings_);
  }

  ScanMetrics m;
  const std::vector<Aperture> apertures = Apertures(truth, map);
  const auto out_of_view = [&](std::size_t i) {
    const Vec2 at(double(i % std::size_t(map.width)) + 0.5,
                  double(i / std::size_t(map.width)) + 0.5);
    return std::none_of(apertures.begin(), apertures.end(),
                        [&](const Aperture& a) { return a.Holds(at); });
  };
  double intrusion_out_of_view = 0.0;
  double intrusion = 0.0, intrusion_moving = 0.0, intrusion_mask = 0.0, reference = 0.0,
         covered = 0.0, reference_seen = 0.0, covered_seen = 0.0, in_mask = 0.0, star = 0.0;
  const bool score_star = score_in_sight && std::isfinite(centre.x()) && std::isfinite(centre.y());
  const std::size_t cells = std::size_t(map.width) * map.height;
  for (std::size_t i = 0; i < cells; ++i) {
    const LogOdds l = map.log_odds[i];
    const bool occupied = covered_[i] > kOccupiedFraction;
    if (occupied) intrusion += polygon_[i];
    if (occupied && map.free[i]) intrusion_mask += polygon_[i];
    if (occupied && polygon_[i] > 0.0f && out_of_view(i)) intrusion_out_of_view += polygon_[i];
    if (moving_[i]) intrusion_moving += polygon_[i];
    if (l == 0) continue;
    ++m.observed;
    const bool called_free = l < 0;
    if (occupied) {
      ++m.observed_occupied;
      if (called_free) {
        ++m.false_free;
        if (covered_[i] >= 0.5f) ++m.false_free_majority;
        if (moving_[i]) ++m.false_free_moving;
      } else {
        ++m.correct;
      }
      if (map.free[i]) ++m.false_free_mask;
    } else {
      if (called_free) {
        ++m.correct;
      } else {
        ++m.false_occupied;
      }
      if (in_sight_[i]) {
        reference += 1.0;
        covered += polygon_[i];
        in_mask += map.free[i] ? 1.0 : 0.0;
        if (score_star) {
          const bool sees = map.free[i] && polygon_[i] < 1.0f &&
                            SeesThroughFree(map, centre, int(i / std::size_t(map.width)),
                                            int(i % std::size_t(map.width)));
          star += sees ? 1.0 : polygon_[i];
        }
      }
      if (seen_[i]) {
        reference_seen += 1.0;
        covered_seen += polygon_[i];
      }
    }
  }
  // Wrong cells on an obstacle's border: a neighbour has the other truth.
  const int w = map.width, h = map.height;
  auto occupied = [&](int r, int c) {
    return covered_[std::size_t(r) * w + c] > kOccupiedFraction;
  };
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const LogOdds l = map.log_odds[std::size_t(r) * w + c];
      const bool truth = occupied(r, c);
      if (l == 0 || (l > 0) == truth) continue;
      bool border = false;
      for (int dr = -1; dr <= 1 && !border; ++dr) {
        for (int dc = -1; dc <= 1 && !border; ++dc) {
          const int rr = r + dr, cc = c + dc;
          border = rr >= 0 && rr < h && cc >= 0 && cc < w && occupied(rr, cc) != truth;
        }
      }
      m.errors_at_border += border ? 1 : 0;
    }
  }
  const double cell_area = map.resolution_m * map.resolution_m;
  m.accuracy = Ratio(double(m.correct), double(m.observed));
  m.false_free_rate = Ratio(double(m.false_free), double(m.observed_occupied));
  m.false_free_mask_rate = Ratio(double(m.false_free_mask), double(m.observed_occupied));
  m.polygon_area_m2 = std::abs(geometry::SignedArea(polygon));
  m.intrusion_m2 = intrusion * cell_area;
  m.intrusion_moving_m2 = intrusion_moving * cell_area;
  m.intrusion_mask_m2 = intrusion_mask * cell_area;
  m.intrusion_out_of_view_m2 = apertures.empty() ? kNaN : intrusion_out_of_view * cell_area;
  m.reference_free_m2 = reference * cell_area;
  m.covered_free_m2 = covered * cell_area;
  m.coverage = score_in_sight ? Ratio(covered, reference) : kNaN;
  m.reference_in_mask_m2 = in_mask * cell_area;
  m.coverage_mask = score_in_sight ? Ratio(in_mask, reference) : kNaN;
  m.reference_star_m2 = star * cell_area;
  m.coverage_star = score_star ? Ratio(star, reference) : kNaN;
  m.reference_seen_m2 = reference_seen * cell_area;
  m.covered_seen_m2 = covered_seen * cell_area;
  m.coverage_seen = Ratio(covered_seen, reference_seen);
  if (polygon.size() >= 3) {
    const Bounds pb(polygon);
    for (const Polygon& o : truth.obstacles) {
      const Bounds ob(o);
      if (ob.x0 > pb.x1 || ob.x1 < pb.x0 || ob.y0 > pb.y1 || ob.y1 < pb.y0) continue;
      m.intrusion_geometric_m2 +=
          std::abs(geometry::SignedArea(geometry::ClipToConvex(polygon, o)));
    }
  }
  return m;
}

nlohmann::json MetricsSeries::Summary() const {
  // Mean, extremes and quantiles of a per-scan value over the scans where it is defined.
  auto stats = [&](double (*field)(const ScanMetrics&)) {
    std::vector<double> v;
    double sum = 0.0;
    for (const ScanMetrics& m : scans_) {
      const double x = field(m);
      if (!std::isfinite(x)) continue;
      v.push_back(x);
      sum += x;
    }
    if (v.empty()) return nlohmann::json{{"mean", nullptr}};
    const double lo = *std::min_element(v.begin(), v.end());
    const double hi = *std::max_element(v.begin(), v.end());
    const double mean = sum / double(v.size());
    const double median = Quantile(v, 0.5), p95 = Quantile(v, 0.95);
    return nlohmann::json{
        {"mean", mean}, {"min", lo}, {"median", median}, {"p95", p95}, {"max", hi}};
  };
  // Sums over all scans, for the pooled ratios.
  double correct = 0, observed = 0, false_free = 0, occupied = 0, moving = 0, majority = 0,
         mask = 0, covered = 0, reference = 0, covered_seen = 0, reference_seen = 0, border = 0,
         in_mask = 0, star = 0;
  for (const ScanMetrics& m : scans_) {
    correct += double(m.correct);
    observed += double(m.observed);
    false_free += double(m.false_free);
    occupied += double(m.observed_occupied);
    moving += double(m.false_free_moving);
    majority += double(m.false_free_majority);
    mask += double(m.false_free_mask);
    covered += m.covered_free_m2;
    reference += m.reference_free_m2;
    in_mask += m.reference_in_mask_m2;
    if (!std::isnan(m.coverage_star)) star += m.reference_star_m2;
    covered_seen += m.covered_seen_m2;
    reference_seen += m.reference_seen_m2;
    border += double(m.errors_at_border);
  }
  nlohmann::json accuracy = stats([](const ScanMetrics& m) { return m.accuracy; });
  accuracy["pooled"] = Number(Ratio(correct, observed));
  accuracy["errors_at_border_share"] = Number(Ratio(border, observed - correct));
  nlohmann::json ff = stats([](const ScanMetrics& m) { return m.false_free_rate; });
  ff["pooled"] = Number(Ratio(false_free, occupied));
  ff["pooled_static"] = Number(Ratio(false_free - moving, occupied));
  ff["share_majority_covered"] = Number(Ratio(majority, false_free));
  ff["share_moving"] = Number(Ratio(moving, false_free));
  nlohmann::json ffm = stats([](const ScanMetrics& m) { return m.false_free_mask_rate; });
  ffm["pooled"] = Number(Ratio(mask, occupied));
  nlohmann::json coverage = stats([](const ScanMetrics& m) { return m.coverage; });
  coverage["pooled"] = Number(Ratio(covered, reference));
  nlohmann::json coverage_mask = stats([](const ScanMetrics& m) { return m.coverage_mask; });
  coverage_mask["pooled"] = Number(Ratio(in_mask, reference));
  nlohmann::json coverage_star = stats([](const ScanMetrics& m) { return m.coverage_star; });
  coverage_star["pooled"] = Number(Ratio(star, reference));
  nlohmann::json seen = stats([](const ScanMetrics& m) { return m.coverage_seen; });
  seen["pooled"] = Number(Ratio(covered_seen, reference_seen));
  return {
      {"scans", scans_.size()},
      {"accuracy", accuracy},
      {"false_free_rate", ff},
      {"false_free_mask_rate", ffm},
      {"intrusion_m2", stats([](const ScanMetrics& m) { return m.intrusion_m2; })},
      {"intrusion_geometric_m2",
       stats([](const ScanMetrics& m) { return m.intrusion_geometric_m2; })},
      {"intrusion_moving_m2", stats([](const ScanMetrics& m) { return m.intrusion_moving_m2; })},
      {"intrusion_mask_m2", stats([](const ScanMetrics& m) { return m.intrusion_mask_m2; })},
      {"intrusion_out_of_view_m2",
       stats([](const ScanMetrics& m) { return m.intrusion_out_of_view_m2; })},
      {"coverage", coverage},
      {"coverage_mask", coverage_mask},
      {"coverage_star", coverage_star},
      {"coverage_seen", seen},
      {"polygon_area_m2", stats([](const ScanMetrics& m) { return m.polygon_area_m2; })},
      {"observed_cells", stats([](const ScanMetrics& m) { return double(m.observed); })},
  };
}

}  // namespace freespace
