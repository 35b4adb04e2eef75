// The polygons.jsonl line of a scan (docs/formats.md).
#include "output/report.hpp"

#include <cmath>
#include <cstdio>

namespace freespace {
namespace {

// Appends `v` with `decimals` fixed decimals, or `null` when it is not finite (JSON has no
// NaN). The buffer holds any finite double in fixed notation (at most 309 integer digits), so
// no number is ever cut.
void AppendNumber(std::string* line, double v, int decimals) {
  if (!std::isfinite(v)) {
    *line += "null";
    return;
  }
  char buffer[352];
  const int n = std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  line->append(buffer, std::size_t(n));
}

}  // namespace

std::string PolygonJsonLine(std::uint64_t scan, const Result& r) {
  std::string line;
  line.reserve(200 + 24 * r.polygon.size());
  line += "{\"scan\":" + std::to_string(scan) + ",\"t\":";
  AppendNumber(&line, r.timestamp_s, 6);
  line += ",\"status\":\"";
  line += ToString(r.status);
  line += "\",\"pose\":{\"x\":";
  AppendNumber(&line, r.pose.x, 6);
  line += ",\"y\":";
  AppendNumber(&line, r.pose.y, 6);
  line += ",\"yaw\":";
  AppendNumber(&line, r.pose.yaw, 6);
  line += "},\"origin\":[";
  AppendNumber(&line, r.origin.x(), 6);
  line += ',';
  AppendNumber(&line, r.origin.y(), 6);
  line += "],\"vehicle_cells\":[";
  AppendNumber(&line, r.vehicle_cells.x(), 4);
  line += ',';
  AppendNumber(&line, r.vehicle_cells.y(), 4);
  line += "],\"speed\":";
  AppendNumber(&line, r.filtered_speed_mps, 3);
  line += ",\"polygon_status\":\"";
  line += ToString(r.polygon_status);
  line += "\",\"polygon\":[";
  for (std::size_t i = 0; i < r.polygon.size(); ++i) {
    line += i ? ",[" : "[";
    AppendNumber(&line, r.polygon[i].x(), 4);
    line += ',';
    AppendNumber(&line, r.polygon[i].y(), 4);
    line += ']';
  }
  line += "]}";
  return line;
}

}  // namespace freespace
