// The rotated-map aligner (alignment.kind rotate), registered with the engine by
// RegisterBaselines(): the map stays centred on the sensor and turns with it, so every scan it is
// read back, resampled by the sensor's motion (MapWarper) and written again.
#include <cmath>
#include <vector>

#include "baselines/map_warper.hpp"
#include "engine/map_aligner.hpp"
#include "freespace/baselines.hpp"

namespace freespace {
namespace {

class RotateMapAligner final : public MapAligner {
 public:
  explicit RotateMapAligner(const Config& config)
      : warper_(config),
        buffer_(std::size_t(config.map.width_cells) * config.map.height_cells),
        resolution_(config.map.resolution_m) {}

  void Apply(const AlignStep& step, const CircleAligner& /*circle*/, const Pose2D& before,
             const Pose2D& now, Backend* backend, Result* r) override {
    if (!step.reset) {
      backend->ReadLogOdds(buffer_.data());
      warper_.Warp(before, now, buffer_.data());
      backend->WriteLogOdds(buffer_.data());
    }
    // Vehicle-centred and turning with the vehicle: the sensor at the centre facing +x.
    const Vec2 local = warper_.centre();
    r->circle_radius_m = 0.0;
    r->circle_centre_cells = local;
    r->map_yaw = now.yaw;
    const double c = std::cos(r->map_yaw), s = std::sin(r->map_yaw);
    r->origin = Vec2(now.x, now.y) -
                Vec2(c * local.x() - s * local.y(), s * local.x() + c * local.y()) * resolution_;
    r->origin_cell_x = r->origin_cell_y = 0;
    r->vehicle_cells = local;
    r->yaw = 0.0;
  }

 private:
  MapWarper warper_;
  std::vector<LogOdds> buffer_;
  double resolution_;
};

std::unique_ptr<MapAligner> MakeRotate(const Config& config) {
  return std::make_unique<RotateMapAligner>(config);
}

}  // namespace

void RegisterBaselines() { RegisterMapAligner(AlignmentKind::kRotate, &MakeRotate); }

}  // namespace freespace
