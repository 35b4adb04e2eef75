// Shared test helpers.
#include "test_util.hpp"

#include <map>

#include "core/crew.hpp"
#include "engine/backend_factory.hpp"
#include "freespace/baselines.hpp"
#include "host/host_backend.hpp"

namespace freespace::test {
namespace {

// The rotated-map baseline is there for every test that configures it.
const bool kBaselinesRegistered = (RegisterBaselines(), true);

}  // namespace

void AttachCrew(Backend* backend) {
  // One crew per size for the whole test run, as an estimator would own one: a backend split
  // over several devices gets its helpers, so that the split runs on threads as it does there.
  static std::map<int, std::unique_ptr<Crew>> crews;
  const Backend::CrewRequest request = backend->WantedCrew();
  if (request.helpers <= 0) return;
  std::unique_ptr<Crew>& crew = crews[request.helpers];
  if (!crew) crew = std::make_unique<Crew>(request.helpers, request.linger, request.window);
  backend->UseCrew(crew.get());
}

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
    std::unique_ptr<Backend> made = CreateBackend(backend, params);
    AttachCrew(made.get());
    return made;
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
