// The OpenCL runtime itself: device choice by config and environment, the errors it gives
// (the devices it saw, the compiler's build log), the program cache and the event timings.
// Compiled only when the OpenCL backend is; each test skips when no OpenCL device exists here.
#include <cstdlib>

#include "opencl_backend.hpp"
#include "opencl_runtime.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

// The device an unfiltered choice takes, or a skip when there is none.
#define FREESPACE_DEVICE_OR_SKIP(var)                        \
  opencl::DeviceChoice var;                                  \
  try {                                                      \
    var = opencl::ChooseDevice(BackendConfig{});             \
  } catch (const BackendError& e) {                          \
    GTEST_SKIP() << "no usable OpenCL device: " << e.what(); \
  }

// Sets an environment variable for the life of the object.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (had_) {
      setenv(name_, old_.c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::string old_;
  bool had_ = false;
};

std::string ErrorOf(const BackendConfig& config) {
  try {
    opencl::ChooseDevice(config);
  } catch (const BackendError& e) {
    return e.what();
  }
  return "";
}

TEST(OpenClRuntime, DeviceFilterMatchingNothingNamesTheDevicesFound) {
  FREESPACE_DEVICE_OR_SKIP(found);
  BackendConfig config;
  config.kind = BackendKind::kOpenCl;
  config.opencl_device = "no-such-device";
  const std::string message = ErrorOf(config);
  EXPECT_NE(message.find("no usable OpenCL device matches"), std::string::npos) << message;
  EXPECT_NE(message.find("\"no-such-device\" (config)"), std::string::npos) << message;
  EXPECT_NE(message.find(found.platform_name), std::string::npos) << message;
  EXPECT_NE(message.find(found.device_name), std::string::npos) << message;
  // Through the factory: an explicit opencl backend throws, it does not fall back.
  EXPECT_THROW(CreateBackend(config, test::SmallParams(4, 4)), BackendError);
}

TEST(OpenClRuntime, PlatformFilterMatchingNothingThrows) {
  FREESPACE_DEVICE_OR_SKIP(found);
  BackendConfig config;
  config.opencl_platform = "no-such-platform";
  const std::string message = ErrorOf(config);
  EXPECT_NE(message.find("\"no-such-platform\" (config)"), std::string::npos) << message;
  EXPECT_NE(message.find(found.device_name), std::string::npos) << message;
}

TEST(OpenClRuntime, EnvironmentOverridesTheConfiguredDevice) {
  FREESPACE_DEVICE_OR_SKIP(found);
  BackendConfig config;
  {
    const ScopedEnv env(opencl::kDeviceEnv, "no-such-device");
    const std::string message = ErrorOf(config);
    EXPECT_NE(message.find("\"no-such-device\" (FREESPACE_OPENCL_DEVICE)"), std::string::npos)
        << message;
  }
  {
    config.opencl_device = "no-such-device";
    const ScopedEnv env(opencl::kDeviceEnv, found.device_name.c_str());
    EXPECT_EQ(opencl::ChooseDevice(config).device, found.device);
  }
  {
    config.opencl_device.clear();
    const ScopedEnv env(opencl::kPlatformEnv, "no-such-platform");
    EXPECT_NE(ErrorOf(config).find("(FREESPACE_OPENCL_PLATFORM)"), std::string::npos);
  }
  // A substring of the name is enough.
  config.opencl_device = found.device_name.substr(0, 3);
  EXPECT_EQ(opencl::ChooseDevice(config).device, found.device);
}

TEST(OpenClRuntime, BrokenKernelThrowsWithTheCompilersLog) {
  FREESPACE_DEVICE_OR_SKIP(found);
  const auto context = opencl::DeviceContext::Get(found);
  const opencl::KernelFile broken[] = {
      {"good.cl", "__kernel void good(__global int* x) { x[0] = 1; }\n"},
      {"broken.cl", "__kernel void broken(__global int* x) {\n  x[0] = no_such_name;\n}\n"}};
  try {
    opencl::BuildProgram(context->context(), context->device(), broken, 2, "-cl-std=CL1.2");
    FAIL() << "a broken program built";
  } catch (const BackendError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("failed to build"), std::string::npos) << message;
    EXPECT_NE(message.find("CL_BUILD_PROGRAM_FAILURE"), std::string::npos) << message;
    EXPECT_NE(message.find("no_such_name"), std::string::npos) << message;
    EXPECT_NE(message.find("broken.cl:2"), std::string::npos) << message;  // file and line
  }
  // The embedded kernels build with the backend's options.
  const KernelParams params = test::SmallParams(7, 5, 1);
  EXPECT_NO_THROW(opencl::BuildProgram(context->context(), context->device(), opencl::kKernelFiles,
                                       opencl::kKernelFileCount,
                                       OpenClBackend::BuildOptions(params, 1, 1)));
}

TEST(OpenClRuntime, ProgramsAreBuiltOncePerOptions) {
  FREESPACE_DEVICE_OR_SKIP(found);
  const auto context = opencl::DeviceContext::Get(found);
  EXPECT_EQ(context, opencl::DeviceContext::Get(found));
  const KernelParams a = test::SmallParams(9, 4), b = test::SmallParams(4, 9);
  const cl_program pa = context->EmbeddedProgram(OpenClBackend::BuildOptions(a, 1, 1));
  EXPECT_EQ(pa, context->EmbeddedProgram(OpenClBackend::BuildOptions(a, 1, 1)));
  EXPECT_NE(pa, context->EmbeddedProgram(OpenClBackend::BuildOptions(b, 1, 1)));
  const std::string options = OpenClBackend::BuildOptions(a, 1, 1);
  EXPECT_NE(options.find("-DWIDTH=9 -DHEIGHT=4"), std::string::npos) << options;
  EXPECT_NE(options.find("-DL_FREE=(" + std::to_string(a.l_free) + ")"), std::string::npos);
}

TEST(OpenClRuntime, AutoTakesOpenClWhenADeviceExists) {
  FREESPACE_DEVICE_OR_SKIP(found);
  BackendConfig config;
  config.kind = BackendKind::kAuto;
  const auto backend = CreateBackend(config, test::SmallParams(5, 5));
  EXPECT_EQ(backend->name(), "opencl: " + found.device_name);
}

TEST(OpenClRuntime, EstimatorReportsEventTimesOfTheKernelStages) {
  FREESPACE_DEVICE_OR_SKIP(found);
  Config config = test::SmallConfig(60, 60);
  config.backend.kind = BackendKind::kOpenCl;
  Estimator estimator(config);
  std::vector<double> angles, ranges;
  for (int a = -60; a <= 60; ++a) {
    angles.push_back(a);
    ranges.push_back(3.0);
  }
  const Result& first = estimator.Process(test::MakeScan(0.0, {}, angles, ranges));
  ASSERT_EQ(first.status, ScanStatus::kOk);
  for (const double t : {first.times.rasterize_us, first.times.fuse_us, first.times.classify_us,
                         first.times.insight_us}) {
    EXPECT_GT(t, 0.0);
    EXPECT_LT(t, first.times.total_us);
  }
  // A scan without update reports no rasterize / fuse time (not the last scan's).
  Scan empty;
  empty.timestamp_s = 0.1;
  const Result& second = estimator.Process(empty);
  ASSERT_EQ(second.status, ScanStatus::kNoSensorUpdate);
  EXPECT_EQ(second.times.rasterize_us, 0.0);
  EXPECT_EQ(second.times.fuse_us, 0.0);
  EXPECT_GT(second.times.insight_us, 0.0);
}

}  // namespace
}  // namespace freespace
