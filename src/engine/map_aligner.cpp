// The aligner registry and the built-in aligner: the vehicle on a circle (paper III), which moves
// the map by whole cells only (eqs. 4, 5).
#include "engine/map_aligner.hpp"

#include <atomic>

#include "freespace/errors.hpp"

namespace freespace {
namespace {

class CircleMapAligner final : public MapAligner {
 public:
  void Apply(const AlignStep& step, const CircleAligner& circle, const Pose2D& /*before*/,
             const Pose2D& /*now*/, Backend* backend, Result* r) override {
    if (!step.reset) backend->Shift(step.shift_x, step.shift_y);  // eqs. (4), (5)
    r->circle_radius_m = step.radius_m;
    r->circle_centre_cells = step.circle_centre;
    r->origin = circle.origin_world();
    r->origin_cell_x = circle.origin_x();
    r->origin_cell_y = circle.origin_y();
    r->map_yaw = 0.0;
    r->vehicle_cells = step.local;  // eqs. (6), (7)
    r->yaw = step.yaw;
  }
};

std::unique_ptr<MapAligner> MakeCircle(const Config& /*config*/) {
  return std::make_unique<CircleMapAligner>();
}

constexpr int kKinds = 2;
std::atomic<MapAlignerFactory> registry[kKinds] = {&MakeCircle, nullptr};

}  // namespace

void RegisterMapAligner(AlignmentKind kind, MapAlignerFactory factory) {
  registry[int(kind)].store(factory);
}

std::unique_ptr<MapAligner> MakeMapAligner(const Config& config) {
  const MapAlignerFactory factory = registry[int(config.alignment.kind)].load();
  if (factory == nullptr) {
    throw ConfigError(std::string("alignment.kind = ") + ToString(config.alignment.kind) +
                      ": this aligner is in the freespace::baselines library; link it and call "
                      "freespace::RegisterBaselines() first (freespace/baselines.hpp)");
  }
  return factory(config);
}

}  // namespace freespace
