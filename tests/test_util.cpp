// Shared test helpers.
#include "test_util.hpp"

#include "host_backend.hpp"

namespace freespace::test {

std::unique_ptr<Backend> MakeBackend(BackendKind kind, const KernelParams& params,
                                     std::string* skip_reason) {
  if (kind == BackendKind::kTbb) return std::make_unique<HostBackend>(params, 0);
  if (!OpenClCompiledIn()) {
    *skip_reason = "this build has no OpenCL backend (FREESPACE_WITH_OPENCL off or not found)";
    return nullptr;
  }
  BackendConfig backend;
  backend.kind = BackendKind::kOpenCl;
  try {
    return CreateBackend(backend, params);
  } catch (const BackendError& e) {
    *skip_reason = std::string("no usable OpenCL device: ") + e.what();
    return nullptr;
  }
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

}  // namespace freespace::test
