// The OpenCL runtime under the OpenCL backend: owning handles, error checks that throw
// BackendError, the device choice (config, overridden by the environment), one context per
// device shared by every backend on it, and the embedded kernels built once per
// (context, device, options) and cached for the life of the process.
#pragma once

#ifndef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 120
#endif
#include <CL/cl.h>

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "freespace/config.hpp"
#include "freespace/devices.hpp"
#include "opencl/kernels.hpp"

namespace freespace::opencl {

// The name of an OpenCL error code, e.g. "CL_OUT_OF_RESOURCES".
const char* ErrorName(cl_int code);

// Throws BackendError "OpenCL <what>: <name> (<code>)" unless `code` is CL_SUCCESS.
void Check(cl_int code, const char* what);

// Owns one reference to an OpenCL object.
template <typename T, cl_int (*Release)(T)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(T handle) : handle_(handle) {}
  ~Handle() { reset(); }
  Handle(Handle&& other) noexcept : handle_(other.handle_) { other.handle_ = nullptr; }
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = other.handle_;
      other.handle_ = nullptr;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  T get() const { return handle_; }
  explicit operator bool() const { return handle_ != nullptr; }
  // Drops the current reference; for APIs that return a new object through a pointer.
  T* out() {
    reset();
    return &handle_;
  }
  void reset(T handle = nullptr) {
    if (handle_ != nullptr) Release(handle_);
    handle_ = handle;
  }

 private:
  T handle_ = nullptr;
};

using Context = Handle<cl_context, clReleaseContext>;
using Queue = Handle<cl_command_queue, clReleaseCommandQueue>;
using Program = Handle<cl_program, clReleaseProgram>;
using Kernel = Handle<cl_kernel, clReleaseKernel>;
using Mem = Handle<cl_mem, clReleaseMemObject>;
using Event = Handle<cl_event, clReleaseEvent>;

// Names of the environment variables that override BackendConfig::opencl_platform and
// opencl_device when set and not empty.
inline constexpr const char* kPlatformEnv = "FREESPACE_OPENCL_PLATFORM";
inline constexpr const char* kDeviceEnv = "FREESPACE_OPENCL_DEVICE";
// Overrides BackendConfig::opencl_devices (and so --opencl-devices) when set and not empty (a
// number in [1, 16]).
inline constexpr const char* kDevicesEnv = "FREESPACE_OPENCL_DEVICES";

struct DeviceChoice {
  cl_platform_id platform = nullptr;
  cl_device_id device = nullptr;
  std::string platform_name;
  std::string device_name;
};

// Every platform and device with the one ChooseDevice takes marked `chosen` (fills all of `list`
// but `opencl_built`); `handles`, when given, gets the device ids in listing order.
void ListDevices(const BackendConfig& config, DeviceList* list,
                 std::vector<DeviceChoice>* handles = nullptr);

// The first available device, in platform then device order, whose platform name contains the
// platform filter and whose name contains the device filter (empty filters match all). The
// filters are config.opencl_platform / opencl_device, replaced by the environment variables
// above when those are set. Throws BackendError naming the filters and every platform and
// device seen, or "no OpenCL platform (ICD loader found none)".
DeviceChoice ChooseDevice(const BackendConfig& config);

// config.opencl_devices, or FREESPACE_OPENCL_DEVICES when set. Throws BackendError when the
// variable is not a number in [1, 16].
int DeviceCount(const BackendConfig& config);

// ChooseDevice's device followed by the next DeviceCount(config) - 1 devices of its platform
// with the same name, in listing order. Throws BackendError, naming how many there are, when
// there are fewer.
std::vector<DeviceChoice> ChooseDevices(const BackendConfig& config);

// Builds the OpenCL C `files` (one program, in order) for `devices` (all of them in `context`)
// with `options`. Each file
// starts with a #line directive, so the compiler's messages name the file. Throws BackendError
// carrying the build log when the compiler rejects the program. On PoCL the build holds an
// exclusive lock on BuildLockPath(device) (flock), so that processes sharing PoCL's disk cache
// build one at a time: PoCL 3.1 can abort a process (an assertion where it reads the cached
// program.bc) when two processes build the same program into the cache at once.
Program BuildProgram(cl_context context, const std::vector<cl_device_id>& devices,
                     const KernelFile* files, int count, const std::string& options);

// The lock file BuildProgram holds for `device`: freespace-build.lock in POCL_CACHE_DIR, else in
// $XDG_CACHE_HOME/pocl, else in $HOME/.cache/pocl, else in /tmp/pocl (where PoCL keeps its
// kernel cache; created when missing), for a device of PoCL's platform; "" (no lock) for any
// other driver or where the directory cannot be made.
std::string BuildLockPath(cl_device_id device);

// A build log with the joined source's line numbers turned into file names and lines. A compiler
// that ignores #line (NVIDIA's does) numbers the joined program from 1 under a name of its own in
// angle brackets, "<kernel>:6:10: error: ..."; each "<name>:LINE:" whose LINE falls inside one of
// `files` (laid out as BuildProgram joins them) becomes "file.cl:line:". Everything else is kept:
// "<built-in>" references, and the whole log when it names one of the files already.
std::string NameJoinedLines(const std::string& log, const KernelFile* files, int count);

// A context on one device (or on a list of devices of one platform), shared by every backend on
// that device (list), with a cache of the embedded kernels built for each options string. Created
// on first use and kept until the process ends (releasing OpenCL objects from static destructors
// races the ICD loader's own teardown).
class DeviceContext {
 public:
  // The shared context of `choice.device`. Throws BackendError.
  static std::shared_ptr<DeviceContext> Get(const DeviceChoice& choice);
  // The shared context of all of `choices` (one platform). Throws BackendError.
  static std::shared_ptr<DeviceContext> Get(const std::vector<DeviceChoice>& choices);

  explicit DeviceContext(const std::vector<DeviceChoice>& choices);
  DeviceContext(const DeviceContext&) = delete;
  DeviceContext& operator=(const DeviceContext&) = delete;

  cl_context context() const { return context_.get(); }
  // The first device and its choice.
  cl_device_id device() const { return choices_[0].device; }
  const DeviceChoice& choice() const { return choices_[0]; }
  const std::vector<cl_device_id>& devices() const { return devices_; }

  // kernels/*.cl built with `options`: built on the first request, then the cached program.
  // Thread-safe. Throws BackendError with the build log.
  cl_program EmbeddedProgram(const std::string& options);

 private:
  std::vector<DeviceChoice> choices_;
  std::vector<cl_device_id> devices_;
  Context context_;
  std::mutex mutex_;
  std::map<std::string, Program> programs_;
};

}  // namespace freespace::opencl
