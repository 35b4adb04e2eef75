// Helpers shared by the test files: where the recorded data is, the backends every stage test
// runs on, and small scan builders.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/backend.hpp"
#include "engine/backend_factory.hpp"
#include "freespace/freespace.hpp"

namespace freespace::test {

// ../shared/data (FREESPACE_DATA_DIR overrides); empty when absent.
inline std::string DataDir() {
  if (const char* env = std::getenv("FREESPACE_DATA_DIR")) {
    if (std::filesystem::is_directory(env)) return env;
  }
  if (std::filesystem::is_directory(FREESPACE_TEST_DATA_DIR)) return FREESPACE_TEST_DATA_DIR;
  return "";
}

// Skips the calling test, with the reason, when the recorded log is not there.
#define FREESPACE_REQUIRE_DATA(relative, path_var)                                  \
  const std::string path_var = ::freespace::test::DataDir() + "/" + (relative);     \
  if (::freespace::test::DataDir().empty() || !std::filesystem::exists(path_var)) { \
    GTEST_SKIP() << "recorded data not found: " << (relative)                       \
                 << " (set FREESPACE_DATA_DIR to the shared data folder)";          \
  }

// The backends every kernel-stage test runs on.
inline std::vector<BackendKind> AllBackends() { return {BackendKind::kTbb, BackendKind::kOpenCl}; }

inline std::string BackendParamName(const ::testing::TestParamInfo<BackendKind>& info) {
  return info.param == BackendKind::kTbb ? "tbb" : "opencl";
}

// Creates a backend of `kind` for `params`; on OpenCL, when no device or no OpenCL build is
// available, sets `skip_reason` and returns null.
std::unique_ptr<Backend> MakeBackend(BackendKind kind, const KernelParams& params,
                                     std::string* skip_reason);

// Gives `backend` the helper threads it asks for (Backend::WantedCrew), from crews that live as
// long as the test process.
void AttachCrew(Backend* backend);

// A config whose map is width x height and that stays valid for tiny maps.
Config SmallConfig(int width, int height, double resolution = 0.2);

// Kernel params with the default probabilities for a width x height map.
KernelParams SmallParams(int width, int height, int opening_radius = 0);

// A single-layer scan: beams at `angles_deg` with `ranges` (negative = no echo).
Scan MakeScan(double t, Pose2D pose, const std::vector<double>& angles_deg,
              const std::vector<double>& ranges);

}  // namespace freespace::test

// Runs the rest of a backend test only where the backend exists; otherwise skips with why.
#define FREESPACE_BACKEND_OR_SKIP(var, kind, params)                 \
  std::string var##_skip;                                            \
  std::unique_ptr<::freespace::Backend> var =                        \
      ::freespace::test::MakeBackend((kind), (params), &var##_skip); \
  if (!var) GTEST_SKIP() << var##_skip;
