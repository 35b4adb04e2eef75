// The backend factory: the TBB host backend or the OpenCL backend, as configured; `auto` takes
// OpenCL when a device is usable and says which it took through the log callback
// (freespace/log.hpp).
#include "engine/backend_factory.hpp"

#include "core/log.hpp"
#include "freespace/errors.hpp"
#include "host/host_backend.hpp"

#ifdef FREESPACE_WITH_OPENCL
#include "opencl/backend.hpp"
#endif

namespace freespace {

bool OpenClCompiledIn() {
#ifdef FREESPACE_WITH_OPENCL
  return true;
#else
  return false;
#endif
}

std::unique_ptr<Backend> CreateBackend(const Config& config) {
  return CreateBackend(config.backend, MakeKernelParams(config));
}

std::unique_ptr<Backend> CreateBackend(const BackendConfig& backend, const KernelParams& params) {
  switch (backend.kind) {
    case BackendKind::kTbb:
      return std::make_unique<HostBackend>(params, backend.threads);
    case BackendKind::kOpenCl:
#ifdef FREESPACE_WITH_OPENCL
      return std::make_unique<OpenClBackend>(params, backend);
#else
      throw BackendError(kNoOpenClBuild);
#endif
    case BackendKind::kAuto:
#ifdef FREESPACE_WITH_OPENCL
      try {
        auto opencl = std::make_unique<OpenClBackend>(params, backend);
        Log(LogLevel::kInfo, "backend auto: using " + opencl->name());
        return opencl;
      } catch (const BackendError& e) {
        Log(LogLevel::kWarning,
            std::string("backend auto: OpenCL not usable (") + e.what() + "); using tbb");
      }
#else
      Log(LogLevel::kWarning, "backend auto: built without OpenCL; using tbb");
#endif
      return std::make_unique<HostBackend>(params, backend.threads);
  }
  throw BackendError("unknown backend kind");
}

}  // namespace freespace
