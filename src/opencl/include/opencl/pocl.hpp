// What the OpenCL backend knows of PoCL, the CPU implementation the project runs its kernels on:
// its platform name, and which of its CPU devices it lists (docs/opencl.md, "PoCL's two CPU
// devices").
#pragma once

#include "freespace/devices.hpp"

namespace freespace {

// The name PoCL gives its platform.
inline constexpr const char* kPoclPlatform = "Portable Computing Language";

// Whether `platform` is PoCL listing its pthread CPU device but not its basic one, which PoCL
// lists only when POCL_DEVICES names it (POCL_DEVICES="pthread basic").
bool PoclHidesBasicDevice(const ComputePlatform& platform);

}  // namespace freespace
