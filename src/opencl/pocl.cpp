// PoCL's device listing rules (opencl/pocl.hpp).
#include "opencl/pocl.hpp"

namespace freespace {

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
