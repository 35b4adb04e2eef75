// The free-space polygon of a scan (polygon.shape), one implementation per shape, chosen once
// when the estimator is built: the paper's (the in-sight edges' cell centres, capped
// Douglas-Peucker) or the conservative one that covers cells of the polygon mask only.
#pragma once

#include <memory>
#include <vector>

#include "core/backend.hpp"
#include "freespace/config.hpp"
#include "freespace/result.hpp"
#include "freespace/types.hpp"

namespace freespace {

class PolygonExtractor {
 public:
  virtual ~PolygonExtractor() = default;

  // The border rays from the sensor at `sensor` (map cells; its cell `vehicle`) on the
  // classified map of `backend`: kernel stage 4 (for the conservative polygon stage 3b, the
  // polygon mask, first, its margin along the lines of sight from `scanners`, map cells; none:
  // from the sensor). Writes C_Edge into `edges`; adds the stages' times to `times`.
  virtual void CastRays(const Vec2& sensor, CellIndex vehicle, const std::vector<Vec2>& scanners,
                        Backend* backend, std::vector<CellIndex>* edges, StageTimes* times) = 0;

  // Builds the polygon (counter-clockwise, map cells, at most polygon.max_vertices distinct
  // vertices) from the rays of the last CastRays(). Returns false, with `polygon` empty, when
  // nothing around the sensor is free. `error`: the simplification error in cells.
  virtual bool Extract(const std::vector<CellIndex>& edges, const Vec2& sensor,
                       std::vector<Vec2>* polygon, double* error) = 0;
  // The last Extract() returned false though space around the sensor is free: the simplified
  // polygon, pulled inside it, collapsed (most often with a very small polygon.max_vertices).
  virtual bool too_few_vertices() const { return false; }
};

// For `backend`, which the extractor is then given on every call.
std::unique_ptr<PolygonExtractor> MakePolygonExtractor(const Config& config,
                                                       const Backend& backend);

}  // namespace freespace
