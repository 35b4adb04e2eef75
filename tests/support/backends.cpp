// Backends made or skipped with the reason, each with its crew.
#include "support/backends.hpp"

#include <map>

#include "core/crew.hpp"
#include "engine/backend_factory.hpp"
#include "freespace/errors.hpp"

namespace freespace::test {

void AttachCrew(Backend* backend) {
  // A backend split over several devices gets its helpers, so that the split runs on threads as
  // it does in an estimator.
  static std::map<int, std::unique_ptr<Crew>> crews;
  const Backend::CrewRequest request = backend->WantedCrew();
  if (request.helpers <= 0) return;
  std::unique_ptr<Crew>& crew = crews[request.helpers];
  if (!crew) crew = std::make_unique<Crew>(request.helpers, request.linger, request.window);
  backend->UseCrew(crew.get());
}

std::unique_ptr<Backend> MakeBackend(const BackendConfig& config, const KernelParams& params,
                                     std::string* why) {
  if (config.kind != BackendKind::kTbb && !OpenClCompiledIn()) {
    *why = "this build has no OpenCL backend (FREESPACE_WITH_OPENCL off or not found)";
    return nullptr;
  }
  try {
    std::unique_ptr<Backend> made = CreateBackend(config, params);
    AttachCrew(made.get());
    return made;
  } catch (const BackendError& e) {
    *why = std::string("no usable OpenCL device: ") + e.what();
    return nullptr;
  }
}

std::unique_ptr<Backend> MakeBackend(BackendKind kind, const KernelParams& params,
                                     std::string* why) {
  BackendConfig config;
  config.kind = kind;
  return MakeBackend(config, params, why);
}

}  // namespace freespace::test
