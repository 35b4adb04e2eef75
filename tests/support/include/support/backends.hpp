// Backends for single-stage tests and benchmarks, made as an estimator would make them (its crew
// of helper threads attached), or null with the reason they cannot run here: the suites skip
// such cases and say why (FREESPACE_BACKEND_OR_SKIP in tests/test_util.hpp).
#pragma once

#include <memory>
#include <string>

#include "core/backend.hpp"
#include "freespace/config.hpp"

namespace freespace::test {

// Creates the backend `config` asks for with `params`, its crew attached; null, with the reason
// in `why`, when this build or this machine cannot run it (no OpenCL build, no device).
std::unique_ptr<Backend> MakeBackend(const BackendConfig& config, const KernelParams& params,
                                     std::string* why);

// The same for a backend kind with the default device choice.
std::unique_ptr<Backend> MakeBackend(BackendKind kind, const KernelParams& params,
                                     std::string* why);

// Gives `backend` the helper threads it asks for (Backend::WantedCrew), from crews that live as
// long as the process: one per size, as an estimator owns one.
void AttachCrew(Backend* backend);

}  // namespace freespace::test
