// The polygons.jsonl line of a scan (docs/formats.md).
#include "output/report.hpp"

#include <cstdio>

namespace freespace {

std::string PolygonJsonLine(std::uint64_t scan, const Result& r) {
  std::string line;
  line.reserve(128 + 40 * r.polygon.size());
  char buffer[256];
  std::snprintf(buffer, sizeof buffer,
                "{\"scan\":%llu,\"t\":%.6f,\"status\":\"%s\",\"pose\":{\"x\":%.6f,\"y\":%.6f,"
                "\"yaw\":%.6f},\"origin\":[%.6f,%.6f],\"vehicle_cells\":[%.4f,%.4f],"
                "\"speed\":%.3f,\"polygon_status\":\"%s\",\"polygon\":[",
                static_cast<unsigned long long>(scan), r.timestamp_s, ToString(r.status), r.pose.x,
                r.pose.y, r.pose.yaw, r.origin.x(), r.origin.y(), r.vehicle_cells.x(),
                r.vehicle_cells.y(), r.filtered_speed_mps, ToString(r.polygon_status));
  line += buffer;
  for (std::size_t i = 0; i < r.polygon.size(); ++i) {
    std::snprintf(buffer, sizeof buffer, "%s[%.4f,%.4f]", i ? "," : "", r.polygon[i].x(),
                  r.polygon[i].y());
    line += buffer;
  }
  line += "]}";
  return line;
}

}  // namespace freespace
