// Private to the files of OpenClBackend (backend.cpp, commands.cpp and one file per kernel stage
// with the kernel file's stem): setting kernel arguments, work sizes, the constants more than one
// of them uses, and the member templates of the split over devices.
#pragma once

#include <cstddef>

#include "opencl/backend.hpp"
#include "opencl/runtime.hpp"

namespace freespace {
namespace opencl {

inline std::size_t RoundUp(std::size_t n, std::size_t multiple) {
  return (n + multiple - 1) / multiple * multiple;
}

// `index` is a named argument index of the kernel (the `<kernel>_arg` namespaces beside each
// stage's host code list a kernel's parameters in the order of its signature in kernels/*.cl).
template <typename T>
void SetArg(cl_kernel kernel, cl_uint index, const T& value) {
  Check(clSetKernelArg(kernel, index, sizeof(T), &value), "clSetKernelArg");
}

// A second reference to `event`, for a stage whose first command is also its last.
inline Event Retained(cl_event event) {
  Check(clRetainEvent(event), "clRetainEvent");
  return Event(event);
}

// classify_bands (the CPU shape): more bands than compute units, so that a unit that starts late
// still finds work; each band recomputes 4 OPENING_RADIUS rows of its neighbours'.
constexpr std::size_t kClassifyBandsPerUnit = 2;

}  // namespace opencl

template <typename T>
void OpenClBackend::SetArgAll(cl_kernel kernel, cl_uint index, const T& value) {
  opencl::SetArg(kernel, index, value);
  for (int d = 1; d < devices_; ++d) {
    if (const cl_kernel twin = Twin(kernel, d)) opencl::SetArg(twin, index, value);
  }
}

template <typename Enqueue>
void OpenClBackend::SplitRun(int parts, const Enqueue& enqueue) {
  // The parts read what device 0's queue wrote; the CPU devices of one context share the
  // buffers' memory, and each part's queue is finished before Run returns.
  opencl::Check(clFinish(queue_.get()), "clFinish");
  split_parts_.clear();
  split_parts_.resize(std::size_t(parts));  // within the capacity reserved at construction
  const auto run = [&](int part, int d) {
    enqueue(part, d, split_parts_[std::size_t(part)].out());
    opencl::Check(clFinish(QueueOf(d)), "clFinish");
  };
  if (crew_ != nullptr) {
    crew_->Run(parts, run);
  } else {
    for (int part = 0; part < parts; ++part) run(part, part % devices_);
  }
}

}  // namespace freespace
