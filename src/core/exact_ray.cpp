// The end points of the exact border rays (core/exact_ray.hpp), from their integer stops.
#include "core/exact_ray.hpp"

#include <algorithm>

namespace freespace {

SensorCell MakeSensorCell(const Vec2& cells, int width, int height) {
  SensorCell s;
  s.x = std::clamp(ToFixed(cells.x()), 0, width * kFixedOne - 1);
  s.y = std::clamp(ToFixed(cells.y()), 0, height * kFixedOne - 1);
  s.cell = {FixedFloorCell(s.y), FixedFloorCell(s.x)};
  return s;
}

Vec2 RayStopPoint(const SensorCell& s, int target_col, int target_row, const RayStop& stop) {
  const Vec2 sensor(double(s.x) / kFixedOne, double(s.y) / kFixedOne);
  const Vec2 target(target_col + 0.5, target_row + 0.5);
  const Vec2 d = target - sensor;
  switch (stop.kind) {
    case kRayCrossX:
    case kRayCorner:
      return {double(stop.line), sensor.y() + (stop.line - sensor.x()) / d.x() * d.y()};
    case kRayCrossY:
      return {sensor.x() + (stop.line - sensor.y()) / d.y() * d.x(), double(stop.line)};
    default:
      return target;
  }
}

}  // namespace freespace
