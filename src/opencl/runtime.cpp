// The OpenCL runtime: device choice, shared contexts and the program cache
// (see opencl/runtime.hpp). The disk cache of compiled kernels is the driver's own (PoCL keeps
// one in POCL_CACHE_DIR, by default under ~/.cache/pocl), so a second process skips the compiler.
#include "opencl/runtime.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <system_error>
#include <vector>

#include "freespace/errors.hpp"
#include "opencl/pocl.hpp"

namespace freespace::opencl {
namespace {

std::string PlatformString(cl_platform_id platform, cl_platform_info what) {
  std::size_t size = 0;
  if (clGetPlatformInfo(platform, what, 0, nullptr, &size) != CL_SUCCESS || size == 0) return "?";
  std::string text(size, '\0');
  clGetPlatformInfo(platform, what, size, text.data(), nullptr);
  text.resize(text.find('\0') == std::string::npos ? size : text.find('\0'));
  return text;
}

std::string DeviceString(cl_device_id device, cl_device_info what) {
  std::size_t size = 0;
  if (clGetDeviceInfo(device, what, 0, nullptr, &size) != CL_SUCCESS || size == 0) return "?";
  std::string text(size, '\0');
  clGetDeviceInfo(device, what, size, text.data(), nullptr);
  text.resize(text.find('\0') == std::string::npos ? size : text.find('\0'));
  return text;
}

// A filter from the config, replaced by the environment variable when that is set and not empty.
std::string Filter(const std::string& configured, const char* env, std::string* origin) {
  const char* value = std::getenv(env);
  if (value != nullptr && *value != '\0') {
    *origin = env;
    return value;
  }
  *origin = "config";
  return configured;
}

// An exclusive flock on a file for the object's life; without effect when the file cannot be
// opened. Closing the descriptor releases the lock, also when the process dies.
class FileLock {
 public:
  explicit FileLock(const std::string& path) {
    if (path.empty()) return;
    // Writable: where flock is emulated with fcntl locks (NFS), LOCK_EX needs it.
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd_ < 0) return;
    while (::flock(fd_, LOCK_EX) != 0) {
      if (errno != EINTR) {
        ::close(fd_);
        fd_ = -1;
        return;
      }
    }
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace

std::string BuildLockPath(cl_device_id device) {
  cl_platform_id platform = nullptr;
  if (clGetDeviceInfo(device, CL_DEVICE_PLATFORM, sizeof platform, &platform, nullptr) !=
          CL_SUCCESS ||
      PlatformString(platform, CL_PLATFORM_NAME).find("Portable Computing Language") ==
          std::string::npos) {
    return "";
  }
  // PoCL keeps its kernel cache in POCL_CACHE_DIR, else under $XDG_CACHE_HOME/pocl,
  // $HOME/.cache/pocl or, without HOME, /tmp/pocl: every process sharing that cache finds the
  // same lock file.
  std::filesystem::path dir;
  const auto set = [](const char* name) {
    const char* value = std::getenv(name);
    return value != nullptr && *value != '\0' ? value : nullptr;
  };
  if (const char* cache = set("POCL_CACHE_DIR")) {
    dir = cache;
  } else if (const char* xdg = set("XDG_CACHE_HOME")) {
    dir = std::filesystem::path(xdg) / "pocl";
  } else if (const char* home = set("HOME")) {
    dir = std::filesystem::path(home) / ".cache" / "pocl";
  } else {
    dir = "/tmp/pocl";
  }
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) return "";
  return (dir / "freespace-build.lock").string();
}

void ListDevices(const BackendConfig& config, DeviceList* list,
                 std::vector<DeviceChoice>* handles) {
  // One enumeration at a time: PoCL answers a second thread's clGetDeviceIDs with
  // CL_DEVICE_NOT_FOUND while the first one initializes it, so two estimators created at once
  // as the process's first OpenCL use would see no device.
  static std::mutex enumeration;
  const std::lock_guard<std::mutex> lock(enumeration);
  list->platform_filter = Filter(config.opencl_platform, kPlatformEnv, &list->platform_origin);
  list->device_filter = Filter(config.opencl_device, kDeviceEnv, &list->device_origin);
  list->platforms.clear();
  list->error.clear();
  if (handles != nullptr) handles->clear();

  cl_uint platform_count = 0;
  const cl_int status = clGetPlatformIDs(0, nullptr, &platform_count);
  if (status == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ ||
      (status == CL_SUCCESS && platform_count == 0)) {
    list->error = "backend opencl: no OpenCL platform (ICD loader found none)";
    return;
  }
  Check(status, "clGetPlatformIDs");
  std::vector<cl_platform_id> platforms(platform_count);
  Check(clGetPlatformIDs(platform_count, platforms.data(), nullptr), "clGetPlatformIDs");

  bool chosen = false;
  std::ostringstream seen;
  for (cl_platform_id platform : platforms) {
    ComputePlatform& entry = list->platforms.emplace_back();
    entry.name = PlatformString(platform, CL_PLATFORM_NAME);
    entry.version = PlatformString(platform, CL_PLATFORM_VERSION);
    seen << "\n  platform \"" << entry.name << "\":";
    cl_uint device_count = 0;
    if (clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 0, nullptr, &device_count) != CL_SUCCESS ||
        device_count == 0) {
      seen << " no devices";
      continue;
    }
    std::vector<cl_device_id> devices(device_count);
    if (clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, device_count, devices.data(), nullptr) !=
        CL_SUCCESS) {
      seen << " no devices";  // a platform that fails here must not hide the others
      continue;
    }
    const bool platform_matches = entry.name.find(list->platform_filter) != std::string::npos;
    for (cl_device_id device : devices) {
      ComputeDevice& d = entry.devices.emplace_back();
      d.name = DeviceString(device, CL_DEVICE_NAME);
      d.version = DeviceString(device, CL_DEVICE_VERSION);
      d.driver_version = DeviceString(device, CL_DRIVER_VERSION);
      d.opencl_c_version = DeviceString(device, CL_DEVICE_OPENCL_C_VERSION);
      cl_device_type type = 0;
      cl_uint units = 0;
      std::size_t group = 0;
      cl_ulong memory = 0;
      cl_bool available = CL_FALSE, compiler = CL_FALSE;
      clGetDeviceInfo(device, CL_DEVICE_TYPE, sizeof type, &type, nullptr);
      clGetDeviceInfo(device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, nullptr);
      clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof group, &group, nullptr);
      clGetDeviceInfo(device, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof memory, &memory, nullptr);
      clGetDeviceInfo(device, CL_DEVICE_AVAILABLE, sizeof available, &available, nullptr);
      clGetDeviceInfo(device, CL_DEVICE_COMPILER_AVAILABLE, sizeof compiler, &compiler, nullptr);
      d.type = (type & CL_DEVICE_TYPE_GPU)           ? "gpu"
               : (type & CL_DEVICE_TYPE_CPU)         ? "cpu"
               : (type & CL_DEVICE_TYPE_ACCELERATOR) ? "accelerator"
                                                     : "other";
      d.compute_units = int(units);
      d.max_work_group = group;
      d.global_memory_bytes = memory;
      d.available = available != CL_FALSE;
      d.compiler = compiler != CL_FALSE;
      seen << " device \"" << d.name << "\"";
      if (!d.available) seen << " (not available)";
      if (!d.compiler) seen << " (no compiler)";
      if (!chosen && platform_matches && d.available && d.compiler &&
          d.name.find(list->device_filter) != std::string::npos) {
        d.chosen = chosen = true;
      }
      if (handles != nullptr) handles->push_back({platform, device, entry.name, d.name});
    }
    if (PoclHidesBasicDevice(entry)) {
      entry.note =
          "PoCL's \"basic\" device, which runs the kernels on the calling thread, is listed "
          "with POCL_DEVICES=\"pthread basic\"";
    }
  }
  if (!chosen) {
    std::ostringstream message;
    message << "backend opencl: no usable OpenCL device matches platform \""
            << list->platform_filter << "\" (" << list->platform_origin << ") and device \""
            << list->device_filter << "\" (" << list->device_origin << "); found:" << seen.str();
    if (list->device_filter.find("basic") != std::string::npos) {
      for (const ComputePlatform& p : list->platforms) {
        if (!PoclHidesBasicDevice(p)) continue;
        message << "\n  (PoCL lists its basic device only when POCL_DEVICES names it: "
                   "POCL_DEVICES=\"pthread basic\")";
        break;
      }
    }
    list->error = message.str();
  }
}

int DeviceCount(const BackendConfig& config) {
  const char* env = std::getenv(kDevicesEnv);
  if (env == nullptr || *env == '\0') return config.opencl_devices;
  char* end = nullptr;
  const long n = std::strtol(env, &end, 10);
  if (*end != '\0' || n < 1 || n > 16) {
    throw BackendError(std::string("backend opencl: ") + kDevicesEnv + "=\"" + env +
                       "\" is not a number of devices in [1, 16]");
  }
  return int(n);
}

namespace {

// The chosen device and up to count - 1 more of its platform with the same name, in listing
// order.
std::vector<DeviceChoice> ChosenDevices(const BackendConfig& config, int count) {
  DeviceList list;
  std::vector<DeviceChoice> handles;
  ListDevices(config, &list, &handles);
  if (!list.error.empty()) throw BackendError(list.error);
  std::vector<DeviceChoice> chosen;
  std::size_t index = 0;
  for (const ComputePlatform& platform : list.platforms) {
    for (const ComputeDevice& device : platform.devices) {
      const DeviceChoice& handle = handles[index++];
      if (chosen.empty() ? device.chosen
                         : int(chosen.size()) < count && device.available && device.compiler &&
                               handle.platform == chosen[0].platform &&
                               handle.device_name == chosen[0].device_name) {
        chosen.push_back(handle);
      }
    }
  }
  // ListDevices sets error instead.
  if (chosen.empty()) throw BackendError("backend opencl: no device chosen");
  return chosen;
}

}  // namespace

std::vector<DeviceChoice> ChooseDevices(const BackendConfig& config) {
  const int count = DeviceCount(config);
  std::vector<DeviceChoice> chosen = ChosenDevices(config, count);
  if (int(chosen.size()) < count) {
    std::ostringstream message;
    const char* env = std::getenv(kDevicesEnv);
    message << "backend opencl: opencl_devices = " << count << " ("
            << (env != nullptr && *env != '\0' ? kDevicesEnv : "config") << ") needs " << count
            << " devices named \"" << chosen[0].device_name << "\" on platform \""
            << chosen[0].platform_name << "\"; it lists " << chosen.size();
    if (chosen[0].platform_name.find("Portable Computing Language") != std::string::npos) {
      message << " (PoCL lists a device once per time POCL_DEVICES names it: "
                 "POCL_DEVICES=\"basic basic\" gives two basic devices)";
    }
    throw BackendError(message.str());
  }
  return chosen;
}

DeviceChoice ChooseDevice(const BackendConfig& config) { return ChosenDevices(config, 1)[0]; }

std::string NameJoinedLines(const std::string& log, const KernelFile* files, int count) {
  // The joined line of each file's #line directive: its text starts on the next line, and the
  // newline BuildProgram adds after it ends the text's last line, so a text holding n newlines
  // spans the joined lines [first, first + n] (the last one empty when the text ends with one).
  std::vector<long> directive(count);
  long line = 1;
  for (int i = 0; i < count; ++i) {
    directive[i] = line;
    line += 2 + long(std::count(files[i].text, files[i].text + std::strlen(files[i].text), '\n'));
  }
  // A log that names the files already came from a compiler that honours #line; its other
  // "<name>:" references (Clang's "<built-in>") are not in the joined source.
  for (int i = 0; i < count; ++i) {
    if (log.find(std::string(files[i].name) + ":") != std::string::npos) return log;
  }
  std::string out;
  std::size_t at = 0;
  while (at < log.size()) {
    const std::size_t open = log.find('<', at);
    if (open == std::string::npos) break;
    std::size_t close = open + 1;
    while (close < log.size() && log[close] != '>' &&
           !std::isspace(static_cast<unsigned char>(log[close]))) {
      ++close;
    }
    std::size_t digits = close + 2, end = digits;
    while (end < log.size() && std::isdigit(static_cast<unsigned char>(log[end]))) ++end;
    int file = -1;
    long joined = 0;
    if (close < log.size() && log[close] == '>' && close + 1 < log.size() &&
        log.compare(open, close + 1 - open, "<built-in>") != 0 && log[close + 1] == ':' &&
        end > digits && end - digits < 10 && end < log.size() && log[end] == ':') {
      joined = std::stol(log.substr(digits, end - digits));
      for (int i = count - 1; i >= 0 && file < 0; --i) {
        if (joined > directive[i]) file = i;
      }
      if (file >= 0 && (file + 1 < count ? joined >= directive[file + 1] : joined >= line)) {
        file = -1;
      }
    }
    if (file < 0) {
      out.append(log, at, open + 1 - at);
      at = open + 1;
      continue;
    }
    out.append(log, at, open - at);
    out += files[file].name;
    out += ':';
    out += std::to_string(joined - directive[file]);
    at = end;
  }
  out.append(log, at, std::string::npos);
  return out;
}

Program BuildProgram(cl_context context, const std::vector<cl_device_id>& devices,
                     const KernelFile* files, int count, const std::string& options) {
  // A #line directive before each file makes the compiler's messages name it (NameJoinedLines
  // does it for a compiler that ignores the directive).
  std::vector<std::string> lines(count);
  std::vector<const char*> texts;
  for (int i = 0; i < count; ++i) {
    lines[i] = std::string("#line 1 \"") + files[i].name + "\"\n";
    texts.push_back(lines[i].c_str());
    texts.push_back(files[i].text);
    texts.push_back("\n");
  }
  cl_int status = CL_SUCCESS;
  Program program(
      clCreateProgramWithSource(context, cl_uint(texts.size()), texts.data(), nullptr, &status));
  Check(status, "clCreateProgramWithSource");
  {
    const FileLock lock(BuildLockPath(devices.at(0)));
    status = clBuildProgram(program.get(), cl_uint(devices.size()), devices.data(), options.c_str(),
                            nullptr, nullptr);
  }
  if (status == CL_SUCCESS) return program;
  // The log of the first device whose build failed.
  cl_device_id device = devices[0];
  for (cl_device_id d : devices) {
    cl_build_status built = CL_BUILD_NONE;
    if (clGetProgramBuildInfo(program.get(), d, CL_PROGRAM_BUILD_STATUS, sizeof built, &built,
                              nullptr) == CL_SUCCESS &&
        built == CL_BUILD_ERROR) {
      device = d;
      break;
    }
  }

  std::size_t size = 0;
  std::string log;
  if (clGetProgramBuildInfo(program.get(), device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size) ==
          CL_SUCCESS &&
      size > 0) {
    log.resize(size);
    clGetProgramBuildInfo(program.get(), device, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
    log.resize(log.find('\0') == std::string::npos ? size : log.find('\0'));
  }
  std::ostringstream message;
  message << "backend opencl: the OpenCL kernels failed to build on \""
          << DeviceString(device, CL_DEVICE_NAME) << "\": " << ErrorName(status) << " (" << status
          << ")\n  options: " << options << "\n  build log:\n"
          << (log.empty() ? "(empty)" : NameJoinedLines(log, files, count));
  throw BackendError(message.str());
}

DeviceContext::DeviceContext(const std::vector<DeviceChoice>& choices) : choices_(choices) {
  if (choices_.empty()) throw BackendError("backend opencl: a context needs a device");
  for (const DeviceChoice& choice : choices_) devices_.push_back(choice.device);
  const cl_context_properties properties[] = {
      CL_CONTEXT_PLATFORM, reinterpret_cast<cl_context_properties>(choices_[0].platform), 0};
  cl_int status = CL_SUCCESS;
  context_.reset(clCreateContext(properties, cl_uint(devices_.size()), devices_.data(), nullptr,
                                 nullptr, &status));
  Check(status, "clCreateContext");
}

std::shared_ptr<DeviceContext> DeviceContext::Get(const DeviceChoice& choice) {
  return Get(std::vector<DeviceChoice>{choice});
}

std::shared_ptr<DeviceContext> DeviceContext::Get(const std::vector<DeviceChoice>& choices) {
  // Never destroyed: see the class comment.
  static std::mutex* mutex = new std::mutex;
  static auto* contexts = new std::map<std::vector<cl_device_id>, std::shared_ptr<DeviceContext>>;
  std::vector<cl_device_id> key;
  for (const DeviceChoice& choice : choices) key.push_back(choice.device);
  const std::lock_guard<std::mutex> lock(*mutex);
  std::shared_ptr<DeviceContext>& context = (*contexts)[key];
  if (!context) context = std::make_shared<DeviceContext>(choices);
  return context;
}

cl_program DeviceContext::EmbeddedProgram(const std::string& options) {
  const std::lock_guard<std::mutex> lock(mutex_);
  auto found = programs_.find(options);
  if (found != programs_.end()) return found->second.get();
  Program program = BuildProgram(context(), devices_, kKernelFiles, kKernelFileCount, options);
  const cl_program handle = program.get();
  programs_.emplace(options, std::move(program));
  return handle;
}

}  // namespace freespace::opencl
