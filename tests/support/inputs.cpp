// Scans and stage inputs for the tests and the benchmarks.
#include "support/inputs.hpp"

#include <cmath>
#include <filesystem>

#include "support/paths.hpp"

namespace freespace::test {

std::vector<Scan> LoadScans(const std::string& relative_path, SensorConfig* sensor) {
  std::vector<Scan> scans;
  const std::string path = DataDir() + "/" + relative_path;
  if (DataDir().empty() || !std::filesystem::exists(path)) return scans;
  auto reader = OpenLog(path);
  if (sensor != nullptr) *sensor = reader->sensor();
  Scan scan;
  while (reader->Next(&scan)) scans.push_back(scan);
  return scans;
}

std::unique_ptr<StageInput> MakeStageInput(int cells) {
  SensorConfig sensor;
  std::vector<Scan> scans = LoadScans("kitti/kitti_00_000000.bin", &sensor);
  if (scans.empty()) return nullptr;
  auto in = std::make_unique<StageInput>();
  in->config.map.width_cells = in->config.map.height_cells = cells;
  in->config.sensor = sensor;
  in->params = MakeKernelParams(in->config);
  in->scan = scans[0];
  in->preprocess = std::make_unique<Preprocessor>(in->config);
  ScanStats stats;
  in->preprocess->Run(in->scan, &stats);
  const Vec2 local(0.5 * cells + 0.37, 0.5 * cells + 0.61);
  in->preprocess->Project(local, 0.3, cells, cells, &in->job);
  in->vehicle = {int(local.y()), int(local.x())};
  // A realistic map: the scan fused five times from slightly different poses.
  Estimator estimator(in->config);
  for (int k = 0; k < 5; ++k) {
    Scan s = in->scan;
    s.timestamp_s = 0.1 * k;
    s.pose = {0.4 * k, 0.05 * k, 0.3 + 0.01 * k};
    estimator.Process(s);
  }
  const MapView view = estimator.map();
  in->map.assign(view.log_odds, view.log_odds + std::size_t(cells) * cells);
  return in;
}

Config SmallConfig(int width, int height, double resolution) {
  Config config;
  config.map.width_cells = width;
  config.map.height_cells = height;
  config.map.resolution_m = resolution;
  config.alignment.margin_m = 0.0;
  config.classify.vehicle_width_m = 0.0;
  config.sensor.max_range_m = 20.0;
  return config;
}

KernelParams SmallParams(int width, int height, int opening_radius) {
  Config config = SmallConfig(width, height);
  KernelParams p = MakeKernelParams(config);
  p.opening_radius = opening_radius;
  return p;
}

Scan MakeScan(double t, Pose2D pose, const std::vector<double>& angles_deg,
              const std::vector<double>& ranges) {
  Scan scan;
  scan.timestamp_s = t;
  scan.pose = pose;
  for (std::size_t i = 0; i < angles_deg.size(); ++i) {
    ScanPoint p;
    p.layer = 0;
    p.angle_rad = float(angles_deg[i] * M_PI / 180.0);
    p.echo = ranges[i] >= 0.0;
    p.range_m = p.echo ? float(ranges[i]) : 0.0f;
    scan.points.push_back(p);
  }
  return scan;
}

Scan Wall(double t, const Pose2D& pose, int sensor, double range) {
  Scan scan;
  scan.timestamp_s = t;
  scan.pose = pose;
  scan.sensor = sensor;
  for (int layer = 0; layer < 4; ++layer) {
    for (double a = -30.0; a <= 30.0; a += 0.25) {
      ScanPoint p;
      p.layer = std::uint8_t(layer);
      p.angle_rad = float(a * M_PI / 180.0);
      p.range_m = float(range / std::cos(a * M_PI / 180.0));
      scan.points.push_back(p);
    }
  }
  return scan;
}

Config TwoAlike() {
  Config c;
  SensorConfig s;
  s.name = "a";
  c.sensors.push_back(s);
  s.name = "b";
  c.sensors.push_back(s);
  return c;
}

}  // namespace freespace::test
