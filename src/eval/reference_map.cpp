// The world-fixed reference map. It projects each scan exactly as the estimator does, in the
// local map's cell coordinates, and moves the result onto its own grid by the window's whole
// cell offset in fixed point; rows are then rasterized with the host's row kernel. So any
// difference from the local map comes from the alignment (shifting, forgetting, resampling),
// not from rounding.
#include "eval/reference_map.hpp"

#include <algorithm>
#include <cmath>

#include "host/host_backend.hpp"

namespace freespace {
namespace {
int Class(LogOdds l) { return l < 0 ? -1 : (l > 0 ? 1 : 0); }
}  // namespace

ReferenceMap::ReferenceMap(const Config& config, int margin_cells)
    : config_(config),
      params_(MakeKernelParams(config)),
      preprocess_(config),
      margin_(margin_cells) {}

LogOdds ReferenceMap::At(std::int64_t x, std::int64_t y) const {
  const std::int64_t gx = x - base_x_, gy = y - base_y_;
  if (gx < 0 || gy < 0 || gx >= width_ || gy >= height_) return 0;
  return grid_[std::size_t(gy) * width_ + gx];
}

void ReferenceMap::Recentre(std::int64_t x0, std::int64_t y0) {
  const int w = config_.map.width_cells, h = config_.map.height_cells;
  const int new_width = w + 2 * margin_, new_height = h + 2 * margin_;
  const std::int64_t new_base_x = x0 - margin_, new_base_y = y0 - margin_;
  std::vector<LogOdds> grid(std::size_t(new_width) * new_height, 0);
  for (int gy = 0; gy < new_height; ++gy) {
    for (int gx = 0; gx < new_width; ++gx) {
      grid[std::size_t(gy) * new_width + gx] = At(new_base_x + gx, new_base_y + gy);
    }
  }
  grid_.swap(grid);
  width_ = new_width;
  height_ = new_height;
  base_x_ = new_base_x;
  base_y_ = new_base_y;
}

void ReferenceMap::Forget(std::int64_t x0, std::int64_t y0) {
  const int w = config_.map.width_cells, h = config_.map.height_cells;
  // Cells of the old window that are outside the new one.
  for (std::int64_t y = window_y_; y < window_y_ + h; ++y) {
    for (std::int64_t x = window_x_; x < window_x_ + w; ++x) {
      if (x >= x0 && x < x0 + w && y >= y0 && y < y0 + h) {
        x = x0 + w - 1;  // skip the overlap of this row
        continue;
      }
      const std::int64_t gx = x - base_x_, gy = y - base_y_;
      if (gx >= 0 && gy >= 0 && gx < width_ && gy < height_) grid_[gy * width_ + gx] = 0;
    }
  }
}

void ReferenceMap::Update(const Scan& scan, const Result& r) {
  if (r.status == ScanStatus::kRejected) return;
  const int w = config_.map.width_cells, h = config_.map.height_cells;
  const double res = config_.map.resolution_m;
  if (!started_ || r.map_reset) {
    started_ = true;
    anchor_ = r.origin - Vec2(double(r.origin_cell_x), double(r.origin_cell_y)) * res;
    grid_.clear();
    width_ = height_ = 0;
    window_x_ = r.origin_cell_x;
    window_y_ = r.origin_cell_y;
    Recentre(window_x_, window_y_);
  }
  const std::int64_t x0 = r.origin_cell_x, y0 = r.origin_cell_y;
  Forget(x0, y0);
  window_x_ = x0;
  window_y_ = y0;
  if (x0 < base_x_ || y0 < base_y_ || x0 + w > base_x_ + width_ || y0 + h > base_y_ + height_) {
    Recentre(x0, y0);
  }

  ScanStats stats;
  if (!preprocess_.Run(scan, &stats)) return;
  RasterJob job;
  preprocess_.Project(r.vehicle_cells, r.yaw, w, h, &job);
  // Onto the reference grid: the window's offset, in whole cells of fixed point.
  const std::int64_t ox = (x0 - base_x_) * kFixedOne, oy = (y0 - base_y_) * kFixedOne;
  vertices_.resize(2 * std::size_t(job.vertex_count));
  std::int64_t ymin = INT64_MAX, ymax = INT64_MIN;
  for (int i = 0; i < job.vertex_count; ++i) {
    vertices_[2 * i] = std::int32_t(job.vertices[2 * i] + ox);
    vertices_[2 * i + 1] = std::int32_t(job.vertices[2 * i + 1] + oy);
    ymin = std::min<std::int64_t>(ymin, vertices_[2 * i + 1]);
    ymax = std::max<std::int64_t>(ymax, vertices_[2 * i + 1]);
  }
  // This scan's update of the window, one value per cell as stage 1 defines it: free inside
  // the polygon (less its outline where the config says so), occupied on the kept echoes
  // (occupied wins).
  const int gr0 = int(y0 - base_y_), gc0 = int(x0 - base_x_);
  row_.resize(width_);
  update_.assign(std::size_t(w) * h, kUpdateNone);
  for (int y = 0; y < h; ++y) {
    const std::int64_t centre = std::int64_t(gr0 + y) * kFixedOne + kFixedHalf;
    if (centre < ymin || centre > ymax) continue;  // no edge crosses this row
    host::RasterizeRow(vertices_.data(), job.vertex_count, width_, gr0 + y, row_.data());
    std::copy(row_.begin() + gc0, row_.begin() + gc0 + w, update_.begin() + std::size_t(y) * w);
  }
  // The cells the outline touches, when sensor_model.free_on_outline is false (window cells).
  if (job.clear_outline)
    host::ClearOutline(job.vertices, job.vertex_count, w, 0, h, update_.data());
  for (int i = 0; i < job.occupied_count; ++i) update_[job.occupied[i]] = kUpdateOccupied;
  // Fusion, as stage 2.
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::uint8_t u = update_[std::size_t(y) * w + x];
      if (u == kUpdateNone) continue;
      LogOdds& cell = grid_[std::size_t(gr0 + y) * width_ + gc0 + x];
      const int delta = u == kUpdateFree ? params_.l_free : params_.l_occupied;
      cell = LogOdds(std::clamp(cell + delta, int(params_.l_min), int(params_.l_max)));
    }
  }
}

MapDifference ReferenceMap::CompareCircle(const MapView& map, const Result& r) const {
  MapDifference d;
  double sum = 0.0;
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const LogOdds local = map.log_odds[std::size_t(y) * map.width + x];
      const LogOdds ref = At(r.origin_cell_x + x, r.origin_cell_y + y);
      if (local == 0 && ref == 0) continue;
      ++d.compared;
      d.different += local != ref;
      d.class_mismatch += Class(local) != Class(ref);
      sum += std::abs(ProbabilityFromLogOdds(local) - ProbabilityFromLogOdds(ref));
    }
  }
  d.mean_abs_probability = d.compared ? sum / double(d.compared) : 0.0;
  return d;
}

MapDifference ReferenceMap::CompareRotated(const MapView& map, const Result& r) const {
  MapDifference d;
  double sum = 0.0;
  const double res = map.resolution_m;
  const double c = std::cos(map.map_yaw), s = std::sin(map.map_yaw);
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const Vec2 cell(x + 0.5, y + 0.5);
      const Vec2 world =
          map.origin + Vec2(c * cell.x() - s * cell.y(), s * cell.x() + c * cell.y()) * res;
      const Vec2 lattice = (world - anchor_) / res;
      const std::int64_t lx = std::int64_t(std::floor(lattice.x()));
      const std::int64_t ly = std::int64_t(std::floor(lattice.y()));
      if (lx < window_x_ || ly < window_y_ || lx >= window_x_ + config_.map.width_cells ||
          ly >= window_y_ + config_.map.height_cells) {
        continue;  // outside the reference's window: nothing to compare with
      }
      const LogOdds local = map.log_odds[std::size_t(y) * map.width + x];
      const LogOdds ref = At(lx, ly);
      if (local == 0 && ref == 0) continue;
      ++d.compared;
      d.different += local != ref;
      d.class_mismatch += Class(local) != Class(ref);
      sum += std::abs(ProbabilityFromLogOdds(local) - ProbabilityFromLogOdds(ref));
    }
  }
  (void)r;
  d.mean_abs_probability = d.compared ? sum / double(d.compared) : 0.0;
  return d;
}

}  // namespace freespace
