// Closed counter-clockwise rings and the GeoJSON Feature of a scan (output/polygon_text.hpp).
// GeoJSON (RFC 7946, section 3.1.6): a Polygon's exterior ring has four or more positions, the
// first and last equal, counter-clockwise. Coordinates are the world frame's metres, not
// WGS 84 longitude and latitude: the "prior arrangement" RFC 7946 section 4 allows, named by
// the feature's `frame` property.
#include "output/polygon_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace freespace {

void AppendJsonNumber(std::string* text, double v, int decimals) {
  if (!std::isfinite(v)) {
    *text += "null";
    return;
  }
  char buffer[352];  // at most 309 integer digits, a sign, a point and the decimals
  const int n = std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  text->append(buffer, std::size_t(n));
}

void AppendJsonPose(std::string* text, double x, double y, double yaw) {
  *text += "{\"x\":";
  AppendJsonNumber(text, x, 6);
  *text += ",\"y\":";
  AppendJsonNumber(text, y, 6);
  *text += ",\"yaw\":";
  AppendJsonNumber(text, yaw, 6);
  *text += '}';
}

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
  for (std::size_t i = 0; i < ring.size(); ++i) {
    text += i ? ",[" : "[";
    AppendJsonNumber(&text, ring[i].x(), 4);
    text += ',';
    AppendJsonNumber(&text, ring[i].y(), 4);
    text += ']';
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
  line += ",\"properties\":{\"scan\":" + std::to_string(r.scan_index) + ",\"t_s\":";
  AppendJsonNumber(&line, r.timestamp_s, 6);
  line += std::string(",\"status\":\"") + ToString(r.status) + "\",\"polygon_status\":\"" +
          ToString(r.polygon_status) + "\",\"frame\":\"" + kPolygonFrame + "\",\"pose\":";
  AppendJsonPose(&line, r.pose.x, r.pose.y, r.pose.yaw);
  line += ",\"speed_mps\":";
  AppendJsonNumber(&line, r.filtered_speed_mps, 3);
  line += "}}";
  return line;
}

}  // namespace freespace
