// The polygons.jsonl line of a scan (docs/formats.md). Numbers through AppendJsonNumber: never
// cut, `null` when not finite.
#include "output/report.hpp"

#include "output/polygon_text.hpp"

namespace freespace {

std::string PolygonJsonLine(std::uint64_t scan, const Result& r) {
  std::string line;
  line.reserve(200 + 24 * r.polygon.size());
  line += "{\"scan\":" + std::to_string(scan) + ",\"t_s\":";
  AppendJsonNumber(&line, r.timestamp_s, 6);
  line += std::string(",\"status\":\"") + ToString(r.status) + "\",\"frame\":\"" + kPolygonFrame +
          "\",\"pose\":";
  AppendJsonPose(&line, r.pose.x, r.pose.y, r.pose.yaw);
  line += ",\"origin\":[";
  AppendJsonNumber(&line, r.origin.x(), 6);
  line += ',';
  AppendJsonNumber(&line, r.origin.y(), 6);
  line += "],\"vehicle_cells\":[";
  AppendJsonNumber(&line, r.vehicle_cells.x(), 4);
  line += ',';
  AppendJsonNumber(&line, r.vehicle_cells.y(), 4);
  line += "],\"map_yaw_rad\":";
  AppendJsonNumber(&line, r.map_yaw, 9);
  line += ",\"pose_correction\":";
  AppendJsonPose(&line, r.pose_correction.x, r.pose_correction.y, r.pose_correction.yaw);
  line += ",\"speed_mps\":";
  AppendJsonNumber(&line, r.filtered_speed_mps, 3);
  line += std::string(",\"polygon_status\":\"") + ToString(r.polygon_status) + "\",\"polygon\":";
  line += RingJson(ClosedCcwRing(r.polygon));  // closed, counter-clockwise
  line += "}";
  return line;
}

}  // namespace freespace
