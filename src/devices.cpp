// ListComputeDevices (freespace/devices.hpp): the OpenCL runtime's listing, or an empty one
// that says so in a build without the OpenCL backend.
#include "freespace/devices.hpp"

#include "backend.hpp"

#ifdef FREESPACE_WITH_OPENCL
#include "opencl_runtime.hpp"
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

bool PoclHidesBasicDevice(const ComputePlatform& platform) {
  if (platform.name != kPoclPlatform) return false;
  bool pthread = false, basic = false;
  for (const ComputeDevice& d : platform.devices) {
    pthread = pthread || d.name.rfind("pthread-", 0) == 0;
    basic = basic || d.name.rfind("basic-", 0) == 0;
  }
  return pthread && !basic;
}

}  // namespace freespace
