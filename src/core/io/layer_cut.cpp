// The layer cut of a point cloud (core/layer_cut.hpp).
#include "core/layer_cut.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

namespace freespace::io {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

}  // namespace

std::string CheckElevationCut(const std::vector<double>& elevations_deg, double tolerance_deg) {
  std::ostringstream why;
  if (elevations_deg.empty() || elevations_deg.size() > 255) {
    why << elevations_deg.size() << " layer elevations: needs 1 to 255";
    return why.str();
  }
  for (std::size_t i = 0; i < elevations_deg.size(); ++i) {
    const double e = elevations_deg[i];
    if (!std::isfinite(e) || e <= -90.0 || e >= 90.0) {
      why << "elevation " << e << " deg: must lie in (-90, 90)";
      return why.str();
    }
    if (i > 0 && !(e > elevations_deg[i - 1])) {
      why << "elevation " << e << " deg after " << elevations_deg[i - 1]
          << ": elevations must increase (layer 0 the lowest)";
      return why.str();
    }
  }
  if (!std::isfinite(tolerance_deg) || tolerance_deg <= 0.0 || tolerance_deg > 10.0) {
    why << "tolerance " << tolerance_deg << " deg: must lie in (0, 10]";
    return why.str();
  }
  return "";
}

LayerCut::LayerCut(const SensorConfig& sensor, std::vector<double> elevations_deg,
                   double tolerance_deg)
    : sensor_(sensor),
      elevations_deg_(std::move(elevations_deg)),
      tolerance_deg_(tolerance_deg),
      bins_(int(std::floor((sensor.max_angle_deg - sensor.min_angle_deg) /
                               sensor.angular_resolution_deg +
                           0.5)) +
            1),
      layers_(sensor.layers) {
  nearest_.resize(std::size_t(bins_) * std::size_t(layers_));
  angle_.resize(nearest_.size());
  Clear();
}

void LayerCut::Clear() {
  std::fill(nearest_.begin(), nearest_.end(), std::numeric_limits<float>::infinity());
  used_ = 0;
}

bool LayerCut::Add(double x, double y, double z) {
  const double horizontal = std::hypot(x, y);
  if (!(horizontal > 0.0)) return false;
  const double elevation = std::atan2(z, horizontal) * kRadToDeg;
  int layer = -1;
  double best = tolerance_deg_;
  for (int l = 0; l < int(elevations_deg_.size()) && l < layers_; ++l) {
    const double d = std::abs(elevation - elevations_deg_[l]);
    if (d <= best) {
      best = d;
      layer = l;
    }
  }
  return layer >= 0 && AddOnLayer(layer, x, y);
}

bool LayerCut::AddOnLayer(int layer, double x, double y) {
  if (layer < 0 || layer >= layers_) return false;
  const double horizontal = std::hypot(x, y);
  if (!(horizontal > 0.0) || horizontal < sensor_.min_range_m) return false;
  const double azimuth = std::atan2(y, x) * kRadToDeg;
  const long bin = std::lround((azimuth - sensor_.min_angle_deg) / sensor_.angular_resolution_deg);
  if (bin < 0 || bin >= bins_) return false;
  const std::size_t k = std::size_t(layer) * std::size_t(bins_) + std::size_t(bin);
  ++used_;
  if (horizontal < nearest_[k]) {
    nearest_[k] = float(horizontal);
    angle_[k] = float(azimuth / kRadToDeg);
  }
  return true;
}

void LayerCut::Fill(std::vector<ScanPoint>* points) const {
  points->resize(nearest_.size());
  for (int l = 0; l < layers_; ++l) {
    for (int b = 0; b < bins_; ++b) {
      const std::size_t k = std::size_t(l) * std::size_t(bins_) + std::size_t(b);
      ScanPoint& p = (*points)[k];
      p.layer = std::uint8_t(l);
      p.echo = std::isfinite(nearest_[k]);
      p.range_m = p.echo ? nearest_[k] : 0.0f;
      p.angle_rad =
          p.echo ? angle_[k]
                 : float((sensor_.min_angle_deg + b * sensor_.angular_resolution_deg) / kRadToDeg);
    }
  }
}

}  // namespace freespace::io
