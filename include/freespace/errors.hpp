// Exceptions thrown at the API boundary. Each carries a message that says what was wrong
// and where (config field and value, file and line).
#pragma once

#include <stdexcept>
#include <string>

namespace freespace {

// A configuration value is missing, unknown or out of range. The message names the field.
class ConfigError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// An input file could not be read or parsed. The message names the file and line.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An output file could not be created or written in full (a full disk, a directory where the
// file should go). The message names the file and the system's reason.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The requested compute backend cannot run here (no OpenCL platform, a kernel that failed to
// build). The message names what was found, or carries the build log.
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace freespace
