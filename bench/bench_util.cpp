// The backends the benchmarks compare, and the benchmarks' main.
#include "bench_util.hpp"

#include <algorithm>
#include <cstdlib>

#ifdef FREESPACE_WITH_OPENCL
#include "opencl/pocl.hpp"
#else
namespace freespace {
constexpr const char* kPoclPlatform = "(this build has no OpenCL backend)";
}  // namespace freespace
#endif

namespace freespace::bench {
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

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
  return v[mid];
}

void PairedTimes::Publish(benchmark::State& state, const char* a, const char* b,
                          const char* ratio) const {
  const double ma = Median(a_), mb = Median(b_);
  state.counters[a] = ma;
  state.counters[b] = mb;
  state.counters[ratio] = ma > 0 ? mb / ma : 0.0;
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
