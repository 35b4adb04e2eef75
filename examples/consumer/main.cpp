// The README's library example, compiled: a vehicle drives 20 m down a corridor 8 m wide; each
// scan of a 4-layer scanner sees both walls. Prints the library version, the backend, and per
// scan the free-space polygon's vertex count; exits 1 when the last scan has no polygon.
//   consumer [CONFIG.yaml]   (without an argument: the built-in defaults, the ScaLa setup)
#include <cmath>
#include <freespace/freespace.hpp>
#include <iostream>
#include <limits>
#include <vector>

namespace {

// The range from (x, y) along `heading` to the nearer wall at y = +-4 m, or +inf (no echo).
float RangeToWall(double y, double heading) {
  const double dy = std::sin(heading);
  if (std::abs(dy) < 1e-9) return std::numeric_limits<float>::infinity();
  const double wall = dy > 0 ? 4.0 : -4.0;
  return static_cast<float>((wall - y) / dy);
}

// One full scan at `x` metres along the corridor, heading +x.
freespace::Scan CorridorScan(const freespace::SensorConfig& sensor, double x, double t) {
  freespace::Scan scan;
  scan.timestamp_s = t;
  scan.pose = {x, 0.0, 0.0};
  const double step = sensor.angular_resolution_deg * M_PI / 180.0;
  for (int layer = 0; layer < sensor.layers; ++layer) {
    for (double a = sensor.min_angle_deg * M_PI / 180.0; a <= sensor.max_angle_deg * M_PI / 180.0;
         a += step) {
      freespace::ScanPoint p;
      p.layer = static_cast<std::uint8_t>(layer);
      p.angle_rad = static_cast<float>(a);
      p.range_m = RangeToWall(0.0, a);
      p.echo = std::isfinite(p.range_m) && p.range_m < sensor.max_range_m;
      scan.points.push_back(p);
    }
  }
  return scan;
}

}  // namespace

int main(int argc, char** argv) {
  freespace::SetLogCallback([](freespace::LogLevel level, const std::string& message) {
    std::cerr << "consumer: " << freespace::ToString(level) << ": " << message << "\n";
  });
  try {
    freespace::Config config =
        argc > 1 ? freespace::Config::FromYamlFile(argv[1]) : freespace::Config();
    freespace::Estimator estimator(config);  // validates, allocates everything
    std::cout << "freespace " << freespace::LibraryVersion() << " (headers " << freespace::kVersion
              << "), backend " << estimator.backend_name() << "\n";
    const freespace::Result* last = nullptr;
    for (int i = 0; i < 25; ++i) {
      const freespace::Scan scan = CorridorScan(config.sensor, 0.8 * i, 0.04 * i);
      const freespace::Result& r = estimator.Process(scan);
      std::cout << "scan " << r.scan_index << ": " << freespace::ToString(r.status) << ", "
                << r.polygon.size() << " vertices\n";
      last = &r;
    }
    const freespace::MapView map = estimator.map();
    std::cout << "map " << map.width << " x " << map.height << " at " << map.resolution_m << " m\n";
    if (last->polygon_status != freespace::PolygonStatus::kOk) {
      std::cerr << "consumer: no free-space polygon on the last scan\n";
      return 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "consumer: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
