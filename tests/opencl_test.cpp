// The OpenCL runtime itself: device choice by config and environment, the errors it gives
// (the devices it saw, the compiler's build log), the program cache and the event timings. The
// stages against the host: work_shape_test.cpp.
// Compiled only when the OpenCL backend is; each test skips when no OpenCL device exists here.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "freespace/estimator.hpp"
#include "host/host_backend.hpp"
#include "opencl/backend.hpp"
#include "opencl/pocl.hpp"
#include "opencl/runtime.hpp"
#include "opencl_device.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

// Sets an environment variable (unsets it, for a null value) for the life of the object.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    if (value != nullptr) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
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

// Without FREESPACE_OPENCL_PLATFORM / FREESPACE_OPENCL_DEVICE for the life of the object: the
// tests of the config's own filters hold when the suite runs with a device chosen by those.
struct NoEnvOverrides {
  ScopedEnv platform{opencl::kPlatformEnv, nullptr};
  ScopedEnv device{opencl::kDeviceEnv, nullptr};
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
  const NoEnvOverrides no_overrides;
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

// Asking for PoCL's basic device where PoCL lists only its pthread one: the error says how to
// list it; where the basic device is listed, the filter takes it.
TEST(OpenClRuntime, PoclBasicDeviceIsTakenOrTheErrorSaysHowToListIt) {
  const NoEnvOverrides no_overrides;
  FREESPACE_DEVICE_OR_SKIP(found);
  const DeviceList list = ListComputeDevices(BackendConfig{});
  bool pocl = false, hidden = false;
  for (const ComputePlatform& p : list.platforms) {
    pocl = pocl || p.name == kPoclPlatform;
    hidden = hidden || PoclHidesBasicDevice(p);
  }
  if (!pocl) GTEST_SKIP() << "no PoCL platform here (found " << found.platform_name << ")";
  BackendConfig config;
  config.opencl_platform = kPoclPlatform;
  config.opencl_device = "basic-";
  const std::string message = ErrorOf(config);
  if (hidden) {
    EXPECT_NE(message.find("POCL_DEVICES=\"pthread basic\""), std::string::npos) << message;
    EXPECT_NE(message.find("no usable OpenCL device matches"), std::string::npos) << message;
  } else {
    EXPECT_TRUE(message.empty()) << message;
    EXPECT_EQ(opencl::ChooseDevice(config).device_name.rfind("basic-", 0), 0u);
  }
  // Any other filter that matches nothing gets no such hint.
  config.opencl_device = "no-such-device";
  EXPECT_EQ(ErrorOf(config).find("POCL_DEVICES"), std::string::npos);
}

TEST(OpenClRuntime, PlatformFilterMatchingNothingThrows) {
  const NoEnvOverrides no_overrides;
  FREESPACE_DEVICE_OR_SKIP(found);
  BackendConfig config;
  config.opencl_platform = "no-such-platform";
  const std::string message = ErrorOf(config);
  EXPECT_NE(message.find("\"no-such-platform\" (config)"), std::string::npos) << message;
  EXPECT_NE(message.find(found.device_name), std::string::npos) << message;
}

TEST(OpenClRuntime, EnvironmentOverridesTheConfiguredDevice) {
  const NoEnvOverrides no_overrides;
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

// The public listing marks exactly the device the backend takes, lists the rest, and says why
// when nothing matches, with the filters and where they came from.
TEST(OpenClRuntime, DeviceListMarksTheDeviceTheBackendTakes) {
  const NoEnvOverrides no_overrides;
  FREESPACE_DEVICE_OR_SKIP(found);
  const DeviceList list = ListComputeDevices(BackendConfig{});
  EXPECT_TRUE(list.opencl_built);
  EXPECT_TRUE(list.error.empty()) << list.error;
  EXPECT_EQ(list.device_origin, "config");
  std::vector<std::string> chosen;
  std::string first_usable;  // with empty filters the rule takes the first usable device
  int devices = 0;
  for (const ComputePlatform& p : list.platforms) {
    EXPECT_FALSE(p.name.empty());
    for (const ComputeDevice& d : p.devices) {
      ++devices;
      if (first_usable.empty() && d.available && d.compiler) first_usable = p.name + " / " + d.name;
      EXPECT_FALSE(d.name.empty());
      EXPECT_TRUE(d.type == "cpu" || d.type == "gpu" || d.type == "accelerator" ||
                  d.type == "other")
          << d.type;
      if (!d.available) continue;  // an unavailable device may answer nothing more
      EXPECT_GE(d.compute_units, 1) << d.name;
      EXPECT_GE(d.max_work_group, 1u) << d.name;
      EXPECT_EQ(d.opencl_c_version.rfind("OpenCL C ", 0), 0u) << d.opencl_c_version;
      if (d.chosen) chosen.push_back(p.name + " / " + d.name);
    }
  }
  EXPECT_EQ(chosen, std::vector<std::string>{found.platform_name + " / " + found.device_name});
  EXPECT_EQ(chosen, std::vector<std::string>{first_usable});

  // Nothing matches: every device is still listed, none marked, and the error is the backend's.
  BackendConfig none;
  none.opencl_device = "no-such-device";
  const DeviceList unmatched = ListComputeDevices(none);
  int listed = 0;
  for (const ComputePlatform& p : unmatched.platforms) {
    for (const ComputeDevice& d : p.devices) {
      ++listed;
      EXPECT_FALSE(d.chosen) << d.name;
    }
  }
  EXPECT_EQ(listed, devices);
  EXPECT_EQ(unmatched.error, ErrorOf(none));
  EXPECT_EQ(unmatched.device_filter, "no-such-device");

  // The environment replaces the configured filter, and the listing says so.
  const ScopedEnv env(opencl::kDeviceEnv, found.device_name.c_str());
  const DeviceList overridden = ListComputeDevices(none);
  EXPECT_EQ(overridden.device_filter, found.device_name);
  EXPECT_EQ(overridden.device_origin, "FREESPACE_OPENCL_DEVICE");
  EXPECT_TRUE(overridden.error.empty()) << overridden.error;
}

// NVIDIA's compiler ignores #line: its log for the broken program below (as its driver 580
// printed it) numbers the joined source, "<kernel>:6:10". The runtime names the file and line.
TEST(OpenClRuntime, LogLinesOfTheJoinedSourceNameTheirFile) {
  const opencl::KernelFile files[] = {
      {"good.cl", "__kernel void good(__global int* x) { x[0] = 1; }\n"},
      {"broken.cl", "__kernel void broken(__global int* x) {\n  x[0] = no_such_name;\n}\n"},
      {"last.cl", "// no newline at the end"}};
  const auto name = [&](const std::string& log) { return opencl::NameJoinedLines(log, files, 3); };
  EXPECT_EQ(name("<kernel>:6:10: error: use of undeclared identifier 'no_such_name'\n"),
            "broken.cl:2:10: error: use of undeclared identifier 'no_such_name'\n");
  // Joined line 2 is good.cl's only line; 10 is the comment, last.cl's only line.
  EXPECT_EQ(name("<source>:2:1: warning: a\n<kernel>:10:3: note: b"),
            "good.cl:1:1: warning: a\nlast.cl:1:3: note: b");
  // The directives' own lines (1, 4, 9) and lines past the end belong to no file; a log that
  // names files already, and text that only looks like a location, stay as they are.
  for (const std::string kept :
       {"<kernel>:1:1: x", "<kernel>:4:1: x", "<kernel>:9:2: x", "<kernel>:11:1: x",
        "broken.cl:2:10: error", "a <b> c", "<kernel>:12", "<kernel>::3:", "<",
        "x <kernel>:", "<built-in>:3:9: note: previous definition is here"}) {
    EXPECT_EQ(name(kept), kept);
  }
  // A compiler that honours #line (PoCL's Clang) names the files; its "<built-in>" and any
  // other bracketed name are not lines of the joined source.
  const std::string clang =
      "broken.cl:2:10: error: use of undeclared identifier\n<kernel>:3:9: note: x\n";
  EXPECT_EQ(name(clang), clang);
}

TEST(OpenClRuntime, BrokenKernelThrowsWithTheCompilersLog) {
  FREESPACE_DEVICE_OR_SKIP(found);
  const auto context = opencl::DeviceContext::Get(found);
  const opencl::KernelFile broken[] = {
      {"good.cl", "__kernel void good(__global int* x) { x[0] = 1; }\n"},
      {"broken.cl", "__kernel void broken(__global int* x) {\n  x[0] = no_such_name;\n}\n"}};
  try {
    opencl::BuildProgram(context->context(), context->devices(), broken, 2, "-cl-std=CL1.2");
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
  EXPECT_NO_THROW(opencl::BuildProgram(context->context(), context->devices(), opencl::kKernelFiles,
                                       opencl::kKernelFileCount,
                                       OpenClBackend::BuildOptions(params, 1, 1, true)));
}

// A kernel the compiler warns about, built with the backend's options, prints nothing: PoCL puts
// its compiler's warnings on stderr (the ABI warnings on int16 arguments of CPUs without AVX-512
// came on a cold kernel cache), and the library never prints.
TEST(OpenClRuntime, CompilerWarningsAreNotPrinted) {
  FREESPACE_DEVICE_OR_SKIP(found);
  const auto context = opencl::DeviceContext::Get(found);
  // A text of its own each run, so that no kernel cache holds it.
  const std::string text =
      "__kernel void warned(__global short16* x, __global const int16* y) {\n"
      "  x[0] = convert_short16(y[0] + (int16)(" +
      std::to_string(std::chrono::steady_clock::now().time_since_epoch().count() & 0xffffff) +
      "));\n  x[1] = 1 << 40;\n}\n";
  const opencl::KernelFile file[] = {{"warned.cl", text.c_str()}};
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  EXPECT_NO_THROW(
      opencl::BuildProgram(context->context(), context->devices(), file, 1,
                           OpenClBackend::BuildOptions(test::SmallParams(7, 5, 1), 1, 1, true)));
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(out, "");
}

TEST(OpenClRuntime, ProgramBuildsWaitForPoclsCacheLock) {
  FREESPACE_DEVICE_OR_SKIP(found);
  const auto context = opencl::DeviceContext::Get(found);
  const std::string path = opencl::BuildLockPath(context->device());
  if (path.empty()) {
    GTEST_SKIP()
        << "builds take no lock here: not a PoCL device, or no cache directory to hold one";
  }
  const opencl::KernelFile file[] = {
      {"lock.cl", "__kernel void lock_test(__global int* x) { x[0] = 3; }\n"}};
  const auto build = [&] {
    opencl::BuildProgram(context->context(), context->devices(), file, 1, "-cl-std=CL1.2");
  };
  build();  // now in PoCL's cache: building it again takes milliseconds
  // Another holder of the lock (a separate open file, as another process would have).
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) GTEST_SKIP() << "cannot create " << path << ": builds run without the lock here";
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  std::atomic<bool> done{false};
  std::string error;
  std::thread builder([&] {
    try {
      build();
    } catch (const std::exception& e) {
      error = e.what();
    }
    done = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const bool done_while_held = done.load();
  ::flock(fd, LOCK_UN);
  ::close(fd);
  builder.join();
  EXPECT_FALSE(done_while_held) << "the build did not wait for " << path;
  EXPECT_TRUE(error.empty()) << error;
}

TEST(OpenClRuntime, ProgramsAreBuiltOncePerOptions) {
  FREESPACE_DEVICE_OR_SKIP(found);
  const auto context = opencl::DeviceContext::Get(found);
  EXPECT_EQ(context, opencl::DeviceContext::Get(found));
  const KernelParams a = test::SmallParams(9, 4), b = test::SmallParams(4, 9);
  const cl_program pa = context->EmbeddedProgram(OpenClBackend::BuildOptions(a, 1, 1, true));
  EXPECT_EQ(pa, context->EmbeddedProgram(OpenClBackend::BuildOptions(a, 1, 1, true)));
  EXPECT_NE(pa, context->EmbeddedProgram(OpenClBackend::BuildOptions(b, 1, 1, true)));
  const std::string options = OpenClBackend::BuildOptions(a, 1, 1, true);
  EXPECT_NE(options.find("-DWIDTH=9 -DHEIGHT=4"), std::string::npos) << options;
  EXPECT_NE(options.find("-DL_FREE=(" + std::to_string(a.l_free) + ")"), std::string::npos);
}

TEST(OpenClRuntime, AutoTakesOpenClWhenADeviceExists) {
  FREESPACE_DEVICE_OR_SKIP(found);
  BackendConfig config;
  config.kind = BackendKind::kAuto;
  const auto backend = CreateBackend(config, test::SmallParams(5, 5));
  const int devices = opencl::DeviceCount(config);
  EXPECT_EQ(backend->name(),
            "opencl: " + found.device_name + (devices > 1 ? " x " + std::to_string(devices) : ""));
}

TEST(OpenClRuntime, SaysWhetherItsKernelsRunOnTheHostsCores) {
  // The estimator runs host work beside a stage only where the kernels leave the host's cores
  // to it or share them: not beside an OpenCL CPU device's threads.
  FREESPACE_DEVICE_OR_SKIP(found);
  cl_device_type type = 0;
  ASSERT_EQ(clGetDeviceInfo(found.device, CL_DEVICE_TYPE, sizeof type, &type, nullptr), CL_SUCCESS);
  BackendConfig config;
  config.kind = BackendKind::kOpenCl;
  EXPECT_EQ(CreateBackend(config, test::SmallParams(5, 5))->KernelsOnHostCores(),
            (type & CL_DEVICE_TYPE_CPU) != 0)
      << found.device_name;
  config.kind = BackendKind::kTbb;
  EXPECT_FALSE(CreateBackend(config, test::SmallParams(5, 5))->KernelsOnHostCores());
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

namespace freespace {
namespace {

constexpr const char* kFirstUseEnv = "FREESPACE_TEST_FIRST_OPENCL_USE";

// Two estimators created at once as the process's first OpenCL use both find the device: PoCL
// answers an enumeration with no device while another thread's first one initializes it, so
// the runtime enumerates one thread at a time. The first use needs a fresh process: this test
// binary again, running this case alone with kFirstUseEnv set, creates the two and exits 0 when
// both were made.
TEST(OpenClRuntime, TwoEstimatorsCreatedAtOnceAsTheFirstUseBothFindTheDevice) {
  if (std::getenv(kFirstUseEnv) != nullptr) {
    Config config;
    config.backend.kind = BackendKind::kOpenCl;
    std::string errors[2];
    std::thread threads[2];
    for (int k = 0; k < 2; ++k) {
      threads[k] = std::thread([&, k] {
        try {
          Estimator estimator(config);
        } catch (const std::exception& e) {
          errors[k] = e.what();
        }
      });
    }
    for (std::thread& t : threads) t.join();
    for (const std::string& e : errors) {
      if (!e.empty()) std::fprintf(stderr, "estimator: %s\n", e.c_str());
    }
    std::fflush(stderr);
    std::_Exit(errors[0].empty() && errors[1].empty() ? 0 : 1);
  }
  FREESPACE_DEVICE_OR_SKIP(found);
  char self[4096] = {};
  ASSERT_GT(::readlink("/proc/self/exe", self, sizeof self - 1), 0);
  std::string quoted = "'";  // the path in single quotes, any quote in it escaped
  for (const char* c = self; *c != '\0'; ++c)
    quoted += *c == '\'' ? std::string("'\\''") : std::string(1, *c);
  quoted += "'";
  // Not sharded out of the one case it names (a sharded run's environment is inherited).
  const std::string command =
      "env -u GTEST_SHARD_INDEX -u GTEST_TOTAL_SHARDS " + std::string(kFirstUseEnv) + "=1 " +
      quoted + " --gtest_filter=OpenClRuntime.TwoEstimatorsCreatedAtOnceAsTheFirstUse* >/dev/null";
  for (int run = 0; run < 3; ++run) EXPECT_EQ(std::system(command.c_str()), 0) << "run " << run;
}

}  // namespace
}  // namespace freespace
