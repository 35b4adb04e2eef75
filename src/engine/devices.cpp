// ListComputeDevices (freespace/devices.hpp): the OpenCL runtime's listing, or an empty one
// that says so in a build without the OpenCL backend.
#include "freespace/devices.hpp"

#include "engine/backend_factory.hpp"

#ifdef FREESPACE_WITH_OPENCL
#include "opencl/runtime.hpp"
#endif

namespace freespace {

DeviceList ListComputeDevices(const BackendConfig& config) {
  DeviceList list;
#ifdef FREESPACE_WITH_OPENCL
  list.opencl_built = true;
  opencl::ListDevices(config, &list);
#else
  (void)config;
  list.error = kNoOpenClBuild;
#endif
  return list;
}

}  // namespace freespace
