// The paper's polygon (C_Edge cell centres simplified) and the conservative polygon (on the free
// mask read back from the backend, with the vehicle's own cells and the safety margin).
#include "polygon_extractor.hpp"

#include <algorithm>
#include <cmath>

#include "core/inside_polygon.hpp"
#include "core/margin.hpp"
#include "core/simplifier.hpp"

namespace freespace {
namespace {

class PaperPolygon final : public PolygonExtractor {
 public:
  PaperPolygon(const Config& config, int labels)
      : simplifier_(config.polygon.max_vertices,
                    config.polygon.epsilon_m / config.map.resolution_m) {
    ring_.reserve(std::size_t(labels));
    kept_.reserve(std::size_t(labels));
  }

  double Extract(const std::vector<CellIndex>& edges, const Vec2& sensor, Backend* /*backend*/,
                 std::vector<Vec2>* polygon) override {
    ring_.clear();
    for (const CellIndex& c : edges) ring_.emplace_back(c.col + 0.5, c.row + 0.5);
    const double error = simplifier_.Simplify(ring_, sensor, &kept_);
    for (const int i : kept_) polygon->push_back(ring_[std::size_t(i)]);
    return error;
  }

 private:
  PolygonSimplifier simplifier_;
  std::vector<Vec2> ring_;  // C_Edge cell centres, the unsimplified polygon
  std::vector<int> kept_;
};

class ConservativePolygon final : public PolygonExtractor {
 public:
  ConservativePolygon(const Config& config, const Backend& backend)
      : width_(config.map.width_cells),
        height_(config.map.height_cells),
        opening_radius_(backend.params().opening_radius),
        builder_(width_, height_, config.polygon.max_vertices,
                 config.polygon.epsilon_m / config.map.resolution_m, config.backend.threads),
        free_(std::size_t(width_) * height_) {
    if (config.polygon.margin_cells > 0) {
      margin_ = std::make_unique<PolygonMargin>(width_, height_, config.polygon.margin_cells,
                                                config.polygon.margin_cone_deg);
    }
    if (backend.HostLogOdds() == nullptr) log_odds_copy_.resize(free_.size());
  }

  double Extract(const std::vector<CellIndex>& /*edges*/, const Vec2& sensor, Backend* backend,
                 std::vector<Vec2>* polygon) override {
    backend->ReadFree(free_.data());
    log_odds_ = nullptr;
    FreeWhereTheVehicleStands(sensor, backend);
    // The margin after: it may keep out cells near the vehicle, but never the sensor's own.
    if (margin_ != nullptr) margin_->Apply(LogOdds(backend), sensor, free_.data());
    return builder_.Build(free_.data(), sensor, polygon);
  }

 private:
  // The map on the host; on a device backend read back once per scan, when first needed.
  const freespace::LogOdds* LogOdds(Backend* backend) {
    if (log_odds_ != nullptr) return log_odds_;
    log_odds_ = backend->HostLogOdds();
    if (log_odds_ == nullptr) {
      backend->ReadLogOdds(log_odds_copy_.data());
      log_odds_ = log_odds_copy_.data();
    }
    return log_odds_;
  }

  // The opening removes free space narrower than the vehicle, and so the apex of the scans'
  // free wedge at the sensor, where the vehicle itself stands (on the first scans that is all
  // there is near it). For the conservative polygon the sensor's own cell is free (as it never
  // stops an in-sight ray), and so is every cell within the opening's radius of it that the
  // scans saw free more often than occupied (log-odds below 0).
  void FreeWhereTheVehicleStands(const Vec2& sensor, Backend* backend) {
    const int col = int(std::floor(sensor.x())), row = int(std::floor(sensor.y()));
    if (col < 0 || row < 0 || col >= width_ || row >= height_) return;
    free_[std::size_t(row) * width_ + col] = 1;
    const int h = opening_radius_;
    for (int r = std::max(0, row - h); r <= std::min(height_ - 1, row + h); ++r) {
      for (int c = std::max(0, col - h); c <= std::min(width_ - 1, col + h); ++c) {
        const std::size_t i = std::size_t(r) * width_ + c;
        // The map only now: on a device backend it is read back for this.
        if (!free_[i] && LogOdds(backend)[i] < 0) free_[i] = 1;
      }
    }
  }

  int width_, height_, opening_radius_;
  InsidePolygonBuilder builder_;
  std::unique_ptr<PolygonMargin> margin_;  // polygon.margin_cells > 0 only
  std::vector<std::uint8_t> free_;         // the free mask, read back every scan
  const freespace::LogOdds* log_odds_ = nullptr;
  std::vector<freespace::LogOdds> log_odds_copy_;  // device backends: the map, read back
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
