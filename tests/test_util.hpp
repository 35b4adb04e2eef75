// Helpers shared by the test files: the GoogleTest side of the testing library (tests/support:
// data and project files, backends, scans and stage inputs): skipping a case, with the reason,
// where its recorded data or its backend is absent, and the backends every stage test runs on.
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
#include "support/backends.hpp"
#include "support/inputs.hpp"
#include "support/paths.hpp"

namespace freespace::test {

// Skips the calling test, with the reason, when the recorded log is not there.
#define FREESPACE_REQUIRE_DATA(relative, path_var)                                      \
  const std::string path_var = ::freespace::test::DataDir() + "/" + (relative);         \
  if (::freespace::test::DataDir().empty() || !std::filesystem::exists(path_var)) {     \
    GTEST_SKIP() << "recorded data not found: " << (relative)                           \
                 << " (tests/data, or set FREESPACE_DATA_DIR to a folder that has it)"; \
  }

// The same for a full recording (FullDataDir()).
#define FREESPACE_REQUIRE_FULL_DATA(relative, path_var)                                          \
  const std::string path_var = ::freespace::test::FullDataDir() + "/" + (relative);              \
  if (::freespace::test::FullDataDir().empty() || !std::filesystem::exists(path_var)) {          \
    GTEST_SKIP() << "full recording not found: " << (relative)                                   \
                 << " (../shared/data, or set FREESPACE_FULL_DATA_DIR to a folder that has it)"; \
  }

// The backends every kernel-stage test runs on.
inline std::vector<BackendKind> AllBackends() { return {BackendKind::kTbb, BackendKind::kOpenCl}; }

inline std::string BackendParamName(const ::testing::TestParamInfo<BackendKind>& info) {
  return info.param == BackendKind::kTbb ? "tbb" : "opencl";
}

}  // namespace freespace::test

// Runs the rest of a backend test only where the backend exists; otherwise skips with why.
#define FREESPACE_BACKEND_OR_SKIP(var, kind, params)                 \
  std::string var##_skip;                                            \
  std::unique_ptr<::freespace::Backend> var =                        \
      ::freespace::test::MakeBackend((kind), (params), &var##_skip); \
  if (!var) GTEST_SKIP() << var##_skip;
