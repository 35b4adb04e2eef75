// The paper's polygon (C_Edge cell centres simplified) and the conservative polygon (exact rays
// on the polygon mask, kernel stages 3b and 4, then the ring pulled inside the mask and
// simplified on the host).
#include "polygon_extractor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include "core/inside_polygon.hpp"
#include "core/simplifier.hpp"

namespace freespace {
namespace {

using Clock = std::chrono::steady_clock;

double Micros(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::micro>(b - a).count();
}

class PaperPolygon final : public PolygonExtractor {
 public:
  PaperPolygon(const Config& config, int labels)
      : simplifier_(config.polygon.max_vertices,
                    config.polygon.epsilon_m / config.map.resolution_m) {
    ring_.reserve(std::size_t(labels));
    kept_.reserve(std::size_t(labels));
  }

  void CastRays(const Vec2& /*sensor*/, CellIndex vehicle, const std::vector<Vec2>& /*scanners*/,
                Backend* backend, std::vector<CellIndex>* edges, StageTimes* times) override {
    const Clock::time_point start = Clock::now();
    backend->InSight(vehicle, edges);
    vehicle_ = vehicle;
    times->insight_us = Micros(start, Clock::now());
  }

  bool Extract(const std::vector<CellIndex>& edges, const Vec2& sensor, std::vector<Vec2>* polygon,
               double* error) override {
    *error = 0.0;
    // Nothing free around the sensor: every ray stopped at its first step.
    const bool beyond = std::any_of(edges.begin(), edges.end(), [&](const CellIndex& c) {
      return std::max(std::abs(c.row - vehicle_.row), std::abs(c.col - vehicle_.col)) > 1;
    });
    if (!beyond) return false;
    ring_.clear();
    for (const CellIndex& c : edges) ring_.emplace_back(c.col + 0.5, c.row + 0.5);
    *error = simplifier_.Simplify(ring_, sensor, &kept_);
    for (const int i : kept_) polygon->push_back(ring_[std::size_t(i)]);
    return true;
  }

 private:
  PolygonSimplifier simplifier_;
  std::vector<Vec2> ring_;  // C_Edge cell centres, the unsimplified polygon
  std::vector<int> kept_;
  CellIndex vehicle_;
};

class ConservativePolygon final : public PolygonExtractor {
 public:
  ConservativePolygon(const Config& config, const Backend& backend)
      : width_(config.map.width_cells),
        height_(config.map.height_cells),
        words_((width_ + 63) / 64),
        // The pairs of rays in eight parts in parallel when the backend may take every core.
        builder_(width_, height_, config.polygon.max_vertices,
                 config.polygon.epsilon_m / config.map.resolution_m,
                 config.backend.threads == 0 ? 8 : 1) {
    stops_.reserve(std::size_t(BorderLabelCount(height_, width_)));
    if (backend.HostMaskBits() == nullptr) mask_copy_.resize(std::size_t(words_) * height_);
  }

  void CastRays(const Vec2& sensor, CellIndex /*vehicle*/, const std::vector<Vec2>& scanners,
                Backend* backend, std::vector<CellIndex>* edges, StageTimes* times) override {
    const Clock::time_point start = Clock::now();
    sensor_ = MakeSensorCell(sensor, width_, height_);
    MarginViews views;
    if (scanners.empty()) views.Add(sensor_);
    for (const Vec2& s : scanners) views.Add(MakeSensorCell(s, width_, height_));
    backend->Mask(sensor_, views);
    const Clock::time_point masked = Clock::now();
    backend->InSightExact(sensor_, &stops_, edges);
    mask_.bits = backend->HostMaskBits();
    if (mask_.bits == nullptr) {  // only the rows the rays could reach
      int r0 = height_, r1 = 0;
      for (const CellIndex& e : *edges) {
        r0 = std::min(r0, e.row);
        r1 = std::max(r1, e.row + 1);
      }
      r0 = std::max(0, std::min(r0, sensor_.cell.row) - 1);
      r1 = std::min(height_, std::max(r1, sensor_.cell.row + 1) + 1);
      backend->ReadMaskBits(r0, r1, mask_copy_.data());
      mask_.bits = mask_copy_.data();
    }
    times->mask_us = Micros(start, masked);
    times->insight_us = Micros(masked, Clock::now());
  }

  bool Extract(const std::vector<CellIndex>& /*edges*/, const Vec2& /*sensor*/,
               std::vector<Vec2>* polygon, double* error) override {
    mask_.width = width_;
    mask_.height = height_;
    mask_.words = words_;
    return builder_.Build(mask_, sensor_, stops_, polygon, error);
  }
  bool too_few_vertices() const override { return builder_.collapsed(); }

 private:
  int width_, height_, words_;
  InsidePolygonBuilder builder_;
  SensorCell sensor_;
  std::vector<RayStop> stops_;
  MaskView mask_;
  std::vector<std::uint64_t> mask_copy_;  // device backends: the mask rows read back
};

}  // namespace

std::unique_ptr<PolygonExtractor> MakePolygonExtractor(const Config& config,
                                                       const Backend& backend) {
  if (config.polygon.shape == PolygonShape::kInside) {
    return std::make_unique<ConservativePolygon>(config, backend);
  }
  return std::make_unique<PaperPolygon>(
      config, BorderLabelCount(backend.params().height, backend.params().width));
}

}  // namespace freespace
