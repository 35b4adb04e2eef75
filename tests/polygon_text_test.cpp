// The polygon as files hold it: closed counter-clockwise rings whatever the input's turn, and
// every scan of a simulated drive as a GeoJSON Feature that keeps RFC 7946's rules for a
// Polygon (a ring of four or more positions, first equal to last, exterior counter-clockwise,
// two numbers a position) or has a null geometry when the scan has no polygon.
#include "output/polygon_text.hpp"

#include <nlohmann/json.hpp>

#include "sim/simulator.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

double TwiceSignedArea(const std::vector<Vec2>& closed) {
  double a = 0;
  for (std::size_t i = 0; i + 1 < closed.size(); ++i) {
    a += closed[i].x() * closed[i + 1].y() - closed[i + 1].x() * closed[i].y();
  }
  return a;
}

TEST(PolygonText, RingsAreClosedAndCounterClockwise) {
  const std::vector<Vec2> ccw = {{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  const std::vector<Vec2> cw(ccw.rbegin(), ccw.rend());
  for (const auto& input : {ccw, cw}) {
    const std::vector<Vec2> ring = ClosedCcwRing(input);
    ASSERT_EQ(ring.size(), 5u);
    EXPECT_EQ(ring.front(), ring.back());
    EXPECT_DOUBLE_EQ(TwiceSignedArea(ring), 4.0);
  }
  // An already closed ring is not closed twice.
  std::vector<Vec2> closed = ccw;
  closed.push_back(ccw.front());
  EXPECT_EQ(ClosedCcwRing(closed).size(), 5u);
  EXPECT_TRUE(ClosedCcwRing({}).empty());
  EXPECT_EQ(RingJson({{1, -2.5}, {0.00004, 3}}), "[[1.0000,-2.5000],[0.0000,3.0000]]");
}

// Checks one feature against RFC 7946 (sections 3.1.1, 3.1.6, 3.2); returns what is wrong.
std::string GeoJsonProblem(const nlohmann::json& f) {
  if (f.value("type", "") != "Feature") return "type is not Feature";
  if (!f.contains("geometry") || !f.contains("properties")) return "no geometry or properties";
  if (!f["properties"].is_object()) return "properties not an object";
  const nlohmann::json& g = f["geometry"];
  if (g.is_null()) return "";
  if (g.value("type", "") != "Polygon") return "geometry type is not Polygon";
  if (!g["coordinates"].is_array() || g["coordinates"].size() != 1) return "not one ring";
  std::vector<Vec2> ring;
  for (const auto& p : g["coordinates"][0]) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) {
      return "position is not two numbers";
    }
    ring.emplace_back(p[0].get<double>(), p[1].get<double>());
  }
  if (ring.size() < 4) return "ring of fewer than four positions";
  if (ring.front() != ring.back()) return "ring not closed";
  if (TwiceSignedArea(ring) <= 0) return "exterior ring not counter-clockwise";
  return "";
}

TEST(PolygonText, EveryScanOfADriveIsAValidGeoJsonFeature) {
  sim::SimulationOptions options;
  options.scenario = "parking";
  options.duration_s = 2.0;
  options.seed = 4;
  sim::Simulation drive(options);
  Config config;
  config.polygon.shape = PolygonShape::kInside;
  Estimator estimator(config);
  Scan scan;
  int polygons = 0;
  while (drive.Next(&scan)) {
    const Result& r = estimator.Process(scan);
    const std::string line = PolygonGeoJsonLine(r);
    ASSERT_EQ(line.find('\n'), std::string::npos);
    const nlohmann::json f = nlohmann::json::parse(line);
    EXPECT_EQ(GeoJsonProblem(f), "") << line;
    EXPECT_EQ(f["id"], r.scan_index);
    EXPECT_EQ(f["properties"]["frame"], "world");
    EXPECT_EQ(f["properties"]["polygon_status"], ToString(r.polygon_status));
    if (f["geometry"].is_null()) {
      EXPECT_NE(r.polygon_status, PolygonStatus::kOk);
    } else {
      EXPECT_EQ(f["geometry"]["coordinates"][0].size(), r.polygon.size() + 1);
      ++polygons;
    }
  }
  EXPECT_GT(polygons, 20) << "the drive should give polygons on most scans";
}

}  // namespace
}  // namespace freespace
