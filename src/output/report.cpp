// The polygons.jsonl line of a scan (docs/formats.md).
#include "output/report.hpp"

#include <cstdio>

#include "output/polygon_text.hpp"

namespace freespace {

std::string PolygonJsonLine(std::uint64_t scan, const Result& r) {
  std::string line;
  line.reserve(128 + 40 * r.polygon.size());
  char buffer[256];
  std::snprintf(buffer, sizeof buffer,
                "{\"scan\":%llu,\"t_s\":%.6f,\"status\":\"%s\",\"frame\":\"%s\","
                "\"pose\":{\"x\":%.6f,\"y\":%.6f,"
                "\"yaw\":%.6f},\"origin\":[%.6f,%.6f],\"vehicle_cells\":[%.4f,%.4f],"
                "\"speed_mps\":%.3f,\"polygon_status\":\"%s\",\"polygon\":",
                static_cast<unsigned long long>(scan), r.timestamp_s, ToString(r.status),
                kPolygonFrame, r.pose.x, r.pose.y, r.pose.yaw, r.origin.x(), r.origin.y(),
                r.vehicle_cells.x(), r.vehicle_cells.y(), r.filtered_speed_mps,
                ToString(r.polygon_status));
  line += buffer;
  line += RingJson(ClosedCcwRing(r.polygon));  // closed, counter-clockwise
  line += "}";
  return line;
}

}  // namespace freespace
