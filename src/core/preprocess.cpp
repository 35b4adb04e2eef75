// Preprocessing: what is validated and how each bad point is treated is documented in
// docs/behaviour.md; every case is counted in ScanStats.
#include "core/preprocess.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace freespace {
namespace {
constexpr double kDegToRad = M_PI / 180.0;
constexpr float kNone = std::numeric_limits<float>::infinity();

}  // namespace

double SensorBins(const SensorConfig& s) {
  return std::floor((s.max_angle_deg - s.min_angle_deg) / s.angular_resolution_deg + 0.5) + 1.0;
}

Preprocessor::Preprocessor(const Config& config)
    : sensor_(config.sensor),
      resolution_m_(config.map.resolution_m),
      clear_outline_(!config.sensor_model.free_on_outline),
      face_rule_(FaceRule::Of(config)),
      min_angle_(config.sensor.min_angle_deg * kDegToRad),
      bin_width_(config.sensor.angular_resolution_deg * kDegToRad),
      bins_(int(SensorBins(config.sensor))),
      clutter_(config.clutter, int(SensorBins(config.sensor)),
               config.sensor.angular_resolution_deg * kDegToRad, config.backend.threads) {
  // The face layer in four parts in parallel when the backend may take every core, else in one.
  face_parts_.resize(config.backend.threads == 0 ? 4 : 1);
  const std::size_t expected = std::size_t(bins_) * sensor_.layers;
  echoes_.reserve(expected);
  keep_.reserve(expected);
  kept_.reserve(expected);
  bin_has_beam_.resize(bins_);
  bin_range_.resize(bins_);
  bin_echo_.resize(bins_);
  bin_cos_.resize(bins_);
  bin_sin_.resize(bins_);
  for (int b = 0; b < bins_; ++b) {
    bin_cos_[b] = std::cos(min_angle_ + b * bin_width_);
    bin_sin_[b] = std::sin(min_angle_ + b * bin_width_);
  }
  beams_.reserve(bins_);
  vertices_.reserve(2 * (bins_ + 1));
  occupied_.reserve(expected);
  ray_ends_.reserve(2 * expected);
}

bool Preprocessor::Run(const Scan& scan, ScanStats* stats) {
  *stats = ScanStats{};
  stats->points = int(scan.points.size());
  echoes_.clear();
  std::fill(bin_has_beam_.begin(), bin_has_beam_.end(), 0);
  std::fill(bin_range_.begin(), bin_range_.end(), kNone);

  const double max_angle = min_angle_ + (bins_ - 1) * bin_width_;
  const double echo_limit = sensor_.max_range_m - sensor_.no_echo_margin_m;
  for (const ScanPoint& p : scan.points) {
    const double a = p.angle_rad;
    // Bins extend half a bin beyond the aperture's first and last beam.
    if (!std::isfinite(a) || a < min_angle_ - 0.5 * bin_width_ ||
        a > max_angle + 0.5 * bin_width_) {
      ++stats->out_of_aperture;
      continue;
    }
    if (p.layer >= sensor_.layers) {
      ++stats->bad_layer;
      continue;
    }
    // a >= min - half a bin here, so truncation is the floor.
    const int bin = std::min(int((a - min_angle_) / bin_width_ + 0.5), bins_ - 1);
    bin_has_beam_[bin] = 1;
    if (!p.echo) {
      ++stats->no_echo;
      continue;
    }
    const double r = p.range_m;
    if (std::isnan(r) || r < sensor_.min_range_m) {  // NaN, negative, -inf, too close
      ++stats->invalid_range;
      continue;
    }
    if (r >= echo_limit) {  // saturated or +inf: the beam saw nothing
      ++stats->no_echo;
      continue;
    }
    // cos and sin from the bin centre's, rotated by the small offset d (|d| <= half a bin):
    // Taylor terms to d^4 are exact to far below float precision.
    const double d = a - (min_angle_ + bin * bin_width_), d2 = d * d;
    const double cd = 1.0 - d2 * (0.5 - d2 / 24.0), sd = d * (1.0 - d2 / 6.0);
    const double ca = bin_cos_[bin] * cd - bin_sin_[bin] * sd;
    const double sa = bin_sin_[bin] * cd + bin_cos_[bin] * sd;
    echoes_.push_back({float(r * ca), float(r * sa), float(r), float(a), bin});
  }
  stats->echoes = int(echoes_.size());

  stats->clutter = clutter_.Run(echoes_, &keep_);
  kept_.clear();
  for (std::size_t i = 0; i < echoes_.size(); ++i) {
    if (!keep_[i]) continue;
    const EchoPoint& e = echoes_[i];
    kept_.push_back(e);
    if (e.range < bin_range_[e.bin]) {
      bin_range_[e.bin] = e.range;
      bin_echo_[e.bin] = int(kept_.size()) - 1;
    }
  }
  stats->kept = int(kept_.size());

  // One polygon vertex per bin that had a beam; bins without a kept echo are virtual.
  beams_.clear();
  for (int b = 0; b < bins_; ++b) {
    if (!bin_has_beam_[b]) continue;
    if (bin_range_[b] != kNone) {
      const EchoPoint& e = kept_[bin_echo_[b]];
      beams_.push_back({e.angle, e.range, e.x, e.y, false});
    } else {
      beams_.push_back({float(min_angle_ + b * bin_width_), kNone, 0.0f, 0.0f, true});
    }
  }
  stats->beams = int(beams_.size());
  if (kept_.empty()) {
    stats->virtual_points = stats->beams;
    return false;
  }

  // Virtual range = min(previous real, next real); at an edge the one that exists.
  float previous = kNone;
  for (Beam& b : beams_) {
    if (!b.is_virtual) {
      previous = b.range;
    } else {
      b.range = previous;
    }
  }
  float next = kNone;
  for (auto it = beams_.rbegin(); it != beams_.rend(); ++it) {
    if (!it->is_virtual) {
      next = it->range;
    } else {
      it->range = std::min(it->range, next);
      const int b = int(std::lround((it->angle - min_angle_) / bin_width_));
      it->x = float(it->range * bin_cos_[b]);
      it->y = float(it->range * bin_sin_[b]);
      ++stats->virtual_points;
    }
  }
  return true;
}

void Preprocessor::Deskew(const SweepMotion& motion) {
  if (sensor_.sweep_s == 0.0) return;
  // A point at angle a is taken sweep_s ((a - min) / (max - min) - 1/2) after the timestamp.
  const double min = sensor_.min_angle_deg * kDegToRad, max = sensor_.max_angle_deg * kDegToRad;
  const double per_rad = sensor_.sweep_s / (max - min), mid = 0.5 * (min + max);
  for (EchoPoint& e : kept_) SweepPoint(motion, per_rad * (e.angle - mid), &e.x, &e.y);
  for (Beam& b : beams_) SweepPoint(motion, per_rad * (b.angle - mid), &b.x, &b.y);
}

void Preprocessor::Project(const Vec2& sensor_cells, double yaw, int width, int height,
                           RasterJob* job, bool faces) {
  const double c = std::cos(yaw), s = std::sin(yaw), k = 1.0 / resolution_m_;
  vertices_.clear();
  const std::int32_t ox = ToFixed(sensor_cells.x()), oy = ToFixed(sensor_cells.y());
  vertices_.push_back(ox);
  vertices_.push_back(oy);
  std::int32_t ymin = oy, ymax = oy;
  for (const Beam& b : beams_) {
    const std::int32_t vx = ToFixed(sensor_cells.x() + (c * b.x - s * b.y) * k);
    const std::int32_t vy = ToFixed(sensor_cells.y() + (s * b.x + c * b.y) * k);
    vertices_.push_back(vx);
    vertices_.push_back(vy);
    ymin = std::min(ymin, vy);
    ymax = std::max(ymax, vy);
  }

  occupied_.clear();
  int occ_row_min = height, occ_row_max = -1;
  for (const EchoPoint& e : kept_) {
    const std::int32_t fx = ToFixed(sensor_cells.x() + (c * e.x - s * e.y) * k);
    const std::int32_t fy = ToFixed(sensor_cells.y() + (s * e.x + c * e.y) * k);
    const int col = FixedFloorCell(fx), row = FixedFloorCell(fy);
    if (col < 0 || col >= width || row < 0 || row >= height) continue;
    occupied_.push_back(row * width + col);
    occ_row_min = std::min(occ_row_min, row);
    occ_row_max = std::max(occ_row_max, row);
  }

  // Rows whose centre 256 r + 128 lies in [ymin, ymax], plus the occupied rows.
  int r0 = int(std::ceil((double(ymin) - kFixedHalf) / kFixedOne));
  int r1 = int(std::floor((double(ymax) - kFixedHalf) / kFixedOne)) + 1;
  r0 = std::min(r0, occ_row_min);
  r1 = std::max(r1, occ_row_max + 1);
  job->vertices = vertices_.data();
  job->vertex_count = int(vertices_.size() / 2);
  job->occupied = occupied_.data();
  job->occupied_count = int(occupied_.size());
  job->clear_outline = clear_outline_;
  job->row_begin = std::clamp(r0, 0, height);
  job->row_end = std::clamp(r1, 0, height);
  if (faces) {
    ProjectFaces(width, height);
  } else {
    face_near_.clear();
    face_seen_.clear();
  }
}

void Preprocessor::ProjectFaces(int width, int height) {
  face_near_.clear();
  face_seen_.clear();
  if (face_rule_.tolerance_m > 0)
    FaceCells(vertices_, beams_, face_rule_, width, height, &face_parts_, &face_near_, &face_seen_);
}

void Preprocessor::ProjectRays(const Vec2& sensor_cells, double yaw, int width, int height,
                               RayJob* job) {
  const double c = std::cos(yaw), s = std::sin(yaw), k = 1.0 / resolution_m_;
  const int origin_col = FixedFloorCell(ToFixed(sensor_cells.x()));
  const int origin_row = FixedFloorCell(ToFixed(sensor_cells.y()));
  int row_min = origin_row, row_max = origin_row;
  ray_ends_.clear();
  occupied_.clear();
  for (const EchoPoint& e : kept_) {
    const int col = FixedFloorCell(ToFixed(sensor_cells.x() + (c * e.x - s * e.y) * k));
    const int row = FixedFloorCell(ToFixed(sensor_cells.y() + (s * e.x + c * e.y) * k));
    ray_ends_.push_back(col);
    ray_ends_.push_back(row);
    if (col >= 0 && col < width && row >= 0 && row < height) occupied_.push_back(row * width + col);
    row_min = std::min(row_min, row);
    row_max = std::max(row_max, row);
  }
  job->origin_col = origin_col;
  job->origin_row = origin_row;
  job->ends = ray_ends_.data();
  job->ray_count = int(ray_ends_.size() / 2);
  job->row_begin = std::clamp(row_min, 0, height);
  job->row_end = std::clamp(row_max + 1, 0, height);
}

}  // namespace freespace
