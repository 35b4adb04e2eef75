// The OpenCL devices this build of the engine can see, and the one `backend: opencl` would take
// with a given config (the same rule as the backend: platform and device filters from the config,
// replaced by FREESPACE_OPENCL_PLATFORM / FREESPACE_OPENCL_DEVICE when those are set). For
// choosing a backend by configuration; `freespace devices` prints it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "freespace/config.hpp"

namespace freespace {

struct ComputeDevice {
  std::string name;              // CL_DEVICE_NAME
  std::string type;              // "cpu", "gpu", "accelerator" or "other"
  std::string version;           // CL_DEVICE_VERSION
  std::string driver_version;    // CL_DRIVER_VERSION
  std::string opencl_c_version;  // CL_DEVICE_OPENCL_C_VERSION
  int compute_units = 0;
  std::uint64_t max_work_group = 0;
  std::uint64_t global_memory_bytes = 0;
  bool available = false;  // CL_DEVICE_AVAILABLE
  bool compiler = false;   // CL_DEVICE_COMPILER_AVAILABLE (the kernels are built from source)
  bool chosen = false;     // the device `backend: opencl` takes with this config
};

struct ComputePlatform {
  std::string name;     // CL_PLATFORM_NAME
  std::string version;  // CL_PLATFORM_VERSION
  std::vector<ComputeDevice> devices;
  // What else the platform can list when told to (e.g. a device that an environment variable
  // enables); empty when nothing.
  std::string note;
};

struct DeviceList {
  bool opencl_built = false;  // whether this build has the OpenCL backend at all
  // The filters the choice used and where each came from ("config" or the variable's name).
  std::string platform_filter, platform_origin;
  std::string device_filter, device_origin;
  std::vector<ComputePlatform> platforms;
  // Empty when a device was chosen; otherwise why not, in the words `backend: opencl` throws.
  std::string error;
};

// Lists every OpenCL platform and device and marks the one the OpenCL backend would choose
// with `config`. Never throws for a missing platform or device: that is `error`.
DeviceList ListComputeDevices(const BackendConfig& config);

}  // namespace freespace
