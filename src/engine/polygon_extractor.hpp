// The free-space polygon of a scan (polygon.shape), one implementation per shape, chosen once
// when the estimator is built: the paper's (C_Edge cell centres, capped Douglas-Peucker) or the
// conservative one that covers free cells only.
#pragma once

#include <memory>
#include <vector>

#include "core/backend.hpp"
#include "freespace/config.hpp"
#include "freespace/types.hpp"

namespace freespace {

class PolygonExtractor {
 public:
  virtual ~PolygonExtractor() = default;

  // Builds the polygon (counter-clockwise, map cells, at most polygon.max_vertices vertices)
  // around the sensor at `sensor` (map cells) from C_Edge (`edges`) or the classified map of
  // `backend`. Returns the simplification error in cells.
  virtual double Extract(const std::vector<CellIndex>& edges, const Vec2& sensor, Backend* backend,
                         std::vector<Vec2>* polygon) = 0;
};

// For `backend`, which the extractor is then given on every call.
std::unique_ptr<PolygonExtractor> MakePolygonExtractor(const Config& config,
                                                       const Backend& backend);

}  // namespace freespace
