// Shared benchmark inputs.
#include "bench_util.hpp"

#include <cstdlib>
#include <filesystem>
#include <map>

#include "core/crew.hpp"
#ifdef FREESPACE_WITH_OPENCL
#include "opencl/pocl.hpp"
#else
namespace freespace {
constexpr const char* kPoclPlatform = "(this build has no OpenCL backend)";
}  // namespace freespace
#endif

namespace freespace::bench {

std::string DataDir() {
  if (const char* env = std::getenv("FREESPACE_DATA_DIR")) return env;
  return FREESPACE_BENCH_DATA_DIR;
}

std::vector<Scan> LoadScans(const std::string& relative_path, SensorConfig* sensor) {
  std::vector<Scan> scans;
  const std::string path = DataDir() + "/" + relative_path;
  if (!std::filesystem::exists(path)) return scans;
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

namespace {

// Whether PoCL lists a device whose name starts with `prefix` ("pthread-<cpu>", "basic-<cpu>").
bool PoclLists(const std::string& prefix) {
  for (const ComputePlatform& p : ListComputeDevices(BackendConfig{}).platforms) {
    if (p.name != kPoclPlatform) continue;
    for (const ComputeDevice& d : p.devices) {
      if (d.name.rfind(prefix, 0) == 0) return true;
    }
  }
  return false;
}

}  // namespace

BackendConfig BenchBackend(std::int64_t arg) {
  BackendConfig config;
  config.kind = arg == 0 ? BackendKind::kTbb : BackendKind::kOpenCl;
  if (arg == 1) {
    static const bool pthread = PoclLists("pthread-");
    if (pthread) {
      config.opencl_platform = kPoclPlatform;
      config.opencl_device = "pthread-";
    }
  } else if (arg == 2 || arg == 3) {
    config.opencl_platform = kPoclPlatform;
    config.opencl_device = "basic-";
    config.opencl_devices = arg == 3 ? 2 : 1;
  }
  return config;
}

std::unique_ptr<Backend> MakeBackend(const BackendConfig& config, const KernelParams& params,
                                     std::string* why) {
  try {
    std::unique_ptr<Backend> backend = CreateBackend(config, params);
    // One crew per size for the whole run, as an estimator would own one.
    static std::map<int, std::unique_ptr<Crew>> crews;
    const Backend::CrewRequest request = backend->WantedCrew();
    if (request.helpers > 0) {
      std::unique_ptr<Crew>& crew = crews[request.helpers];
      if (!crew) crew = std::make_unique<Crew>(request.helpers, request.linger, request.window);
      backend->UseCrew(crew.get());
    }
    return backend;
  } catch (const std::exception& e) {
    *why = e.what();
    return nullptr;
  }
}

}  // namespace freespace::bench

// PoCL lists only its pthread device unless POCL_DEVICES names others; the benchmarks ask for
// both CPU devices, the basic one twice (backends 2 and 3), unless the caller chose.
int main(int argc, char** argv) {
  setenv("POCL_DEVICES", "pthread basic basic", 0);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
