// Where the tests and benchmarks find their files: the recorded logs (../shared/data) and the
// project's own files (configs/, docs/), so that a suite loads configs/indoor.yaml instead of
// re-coding it, and checks docs/ against the code.
#pragma once

#include <string>

#include "freespace/config.hpp"

namespace freespace::test {

// The recorded data folder: FREESPACE_DATA_DIR when set and a folder, else the one configured at
// build time (tests/data, the excerpts); empty when neither exists.
std::string DataDir();

// The full recordings (the shipped data's excerpts come from them): FREESPACE_FULL_DATA_DIR when
// set and a folder, else ../shared/data beside the source tree; empty when neither exists.
std::string FullDataDir();

// `relative` (e.g. "docs/configuration.md") in the source tree this build was configured from.
std::string SourcePath(const std::string& relative);

// The text of the source tree's file `relative`. Throws std::runtime_error when it cannot be read.
std::string ReadSourceFile(const std::string& relative);

// The project's config `name` from configs/ (e.g. "indoor.yaml"), read and validated.
// Throws ConfigError.
Config LoadProjectConfig(const std::string& name);

}  // namespace freespace::test
