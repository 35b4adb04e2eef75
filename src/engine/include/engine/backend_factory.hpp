// The backend factory, above both backends (DESIGN.md: one interface, the backend chosen by
// configuration; a fallback is explicit and logged, never silent).
#pragma once

#include <memory>

#include "core/backend.hpp"
#include "freespace/config.hpp"

namespace freespace {

// Creates the configured backend. kAuto takes OpenCL when a device is found and TBB
// otherwise, and says which through the log callback (freespace/log.hpp). Throws BackendError
// when an explicitly requested backend cannot run.
std::unique_ptr<Backend> CreateBackend(const Config& config);
// The same with explicit kernel parameters (tests and benchmarks of single stages).
std::unique_ptr<Backend> CreateBackend(const BackendConfig& backend, const KernelParams& params);

// True when the library was built with the OpenCL backend.
bool OpenClCompiledIn();

// What `backend: opencl` says in a build without the OpenCL backend.
inline constexpr const char* kNoOpenClBuild =
    "backend opencl: this build of freespace has no OpenCL backend (configure with the OpenCL "
    "headers and ICD loader installed)";

}  // namespace freespace
