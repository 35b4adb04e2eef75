// Closed counter-clockwise rings and the GeoJSON Feature of a scan (output/polygon_text.hpp).
// GeoJSON (RFC 7946, section 3.1.6): a Polygon's exterior ring has four or more positions, the
// first and last equal, counter-clockwise. Coordinates are the world frame's metres, not
// WGS 84 longitude and latitude: the "prior arrangement" RFC 7946 section 4 allows, named by
// the feature's `frame` property.
#include "output/polygon_text.hpp"

#include <algorithm>
#include <cstdio>

namespace freespace {

std::vector<Vec2> ClosedCcwRing(const std::vector<Vec2>& polygon) {
  std::vector<Vec2> ring = polygon;
  if (ring.empty()) return ring;
  if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
  double twice_area = 0.0;  // shoelace formula
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Vec2& a = ring[i];
    const Vec2& b = ring[(i + 1) % ring.size()];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  if (twice_area < 0) std::reverse(ring.begin(), ring.end());
  ring.push_back(ring.front());
  return ring;
}

std::string RingJson(const std::vector<Vec2>& ring) {
  std::string text = "[";
  text.reserve(2 + 24 * ring.size());
  char buffer[64];
  for (std::size_t i = 0; i < ring.size(); ++i) {
    std::snprintf(buffer, sizeof buffer, "%s[%.4f,%.4f]", i ? "," : "", ring[i].x(), ring[i].y());
    text += buffer;
  }
  text += "]";
  return text;
}

std::string PolygonGeoJsonLine(const Result& r) {
  std::string line =
      "{\"type\":\"Feature\",\"id\":" + std::to_string(r.scan_index) + ",\"geometry\":";
  const std::vector<Vec2> ring = ClosedCcwRing(r.polygon);
  if (ring.size() >= 4) {
    line += "{\"type\":\"Polygon\",\"coordinates\":[" + RingJson(ring) + "]}";
  } else {
    line += "null";
  }
  char buffer[320];
  std::snprintf(buffer, sizeof buffer,
                ",\"properties\":{\"scan\":%llu,\"t_s\":%.6f,\"status\":\"%s\","
                "\"polygon_status\":\"%s\",\"frame\":\"%s\",\"pose\":{\"x\":%.6f,"
                "\"y\":%.6f,\"yaw\":%.6f},\"speed_mps\":%.3f}}",
                static_cast<unsigned long long>(r.scan_index), r.timestamp_s, ToString(r.status),
                ToString(r.polygon_status), kPolygonFrame, r.pose.x, r.pose.y, r.pose.yaw,
                r.filtered_speed_mps);
  line += buffer;
  return line;
}

}  // namespace freespace
