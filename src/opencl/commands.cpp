// What every stage of OpenClBackend enqueues with: kernel launches (on device 0's queue or, split
// over devices, on another device's), the job upload, fills, the waits, the reads and writes of
// the tests and the snapshots, and the device times of each stage from event profiling.
#include <algorithm>
#include <chrono>
#include <cstdint>

#include "backend_internal.hpp"
#include "freespace/errors.hpp"
#include "opencl/backend.hpp"

namespace freespace {
namespace {

using opencl::Check;
using opencl::RoundUp;

}  // namespace

cl_kernel OpenClBackend::Twin(cl_kernel kernel, int d) const {
  if (d == 0) return kernel;
  for (const auto& [original, twin] : lanes_[std::size_t(d - 1)].twins) {
    if (original == kernel) return twin.get();
  }
  return nullptr;
}

void OpenClBackend::Launch(cl_kernel kernel, cl_uint dims, const std::size_t* global,
                           const std::size_t* local, cl_event* event) {
  Launch(queue_.get(), kernel, dims, global, local, event);
}

void OpenClBackend::Launch(cl_command_queue queue, cl_kernel kernel, cl_uint dims,
                           const std::size_t* global, const std::size_t* local, cl_event* event) {
  const cl_int status =
      clEnqueueNDRangeKernel(queue, kernel, dims, nullptr, global, local, 0, nullptr, event);
  if (status == CL_SUCCESS) return;
  char name[128] = "?";
  clGetKernelInfo(kernel, CL_KERNEL_FUNCTION_NAME, sizeof name, name, nullptr);
  throw BackendError(std::string("backend opencl: enqueueing kernel ") + name + ": " +
                     opencl::ErrorName(status) + " (" + std::to_string(status) + ")");
}

void OpenClBackend::RowsLaunch(cl_kernel kernel, int rows, cl_event* event) {
  const std::size_t global[2] = {row_items_, RoundUp(std::size_t(rows), rows_local_[1])};
  Launch(kernel, 2, global, rows_local_, event);
}

void OpenClBackend::BitsLaunch(cl_kernel kernel, int rows, cl_event* event) {
  const std::size_t global[2] = {bit_items_, RoundUp(std::size_t(rows), bits_local_[1])};
  Launch(kernel, 2, global, bits_local_, event);
}

std::int32_t* OpenClBackend::Staging(std::size_t ints) {
  if (ints > job_capacity_) GrowJob(ints);
  if (upload_done_) {
    // Normally long finished: the scan that made it ended with a blocking read.
    const cl_event wait = upload_done_.get();
    Check(clWaitForEvents(1, &wait), "clWaitForEvents");
  }
  return job_host_.data();
}

void OpenClBackend::Upload(std::size_t ints, opencl::Event* event) {
  Check(clEnqueueWriteBuffer(queue_.get(), job_.get(), CL_FALSE, 0, ints * 4, job_host_.data(), 0,
                             nullptr, event->out()),
        "clEnqueueWriteBuffer");
  upload_done_ = opencl::Retained(event->get());
}

void OpenClBackend::Fill(cl_mem buffer, std::size_t bytes) {
  const cl_uchar zero = 0;
  Check(clEnqueueFillBuffer(queue_.get(), buffer, &zero, 1, 0, bytes, 0, nullptr, nullptr),
        "clEnqueueFillBuffer");
}

void OpenClBackend::SetStage(Stage stage, opencl::Event begin, opencl::Event end) {
  begin_[stage] = std::move(begin);
  end_[stage] = std::move(end);
  more_[stage].clear();
  more_[stage].swap(split_parts_);
}

void OpenClBackend::WaitForResult(cl_event event) {
  // A blocking wait puts this thread to sleep until a thread of the device's driver wakes it;
  // on a CPU device that is one more thread to schedule, and the wake-up can cost more than a
  // small map's whole scan. Spinning avoids it but keeps a core busy that the device's threads
  // might use, which can cost more than the wake-up; WaitPolicy chooses.
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const auto waited_us = [&] {
    return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
  };
  if (wait_.Next()) {
    const double limit_us = wait_.SpinLimitUs();
    Check(clFlush(queue_.get()), "clFlush");
    cl_int status = CL_QUEUED;
    for (unsigned i = 1;; ++i) {
      Check(
          clGetEventInfo(event, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status, nullptr),
          "clGetEventInfo");
      if (status <= CL_COMPLETE) break;  // done, or failed (clWaitForEvents reports it)
      CpuRelax();
      if (limit_us >= 0 && i % 64 == 0 && waited_us() >= limit_us) break;
    }
  }
  Check(clWaitForEvents(1, &event), "clWaitForEvents");
  wait_.Record(waited_us());
}

void OpenClBackend::Flush() {
  FlushShift();
  FlushRows();
}

void OpenClBackend::Clear() {
  Flush();
  levels_valid_ = false;
  Fill(map_[current_].get(), layout_.cells * sizeof(LogOdds));
  known_[current_] = {};
  Fill(free_.get(), free_host_.size() * 8);
  free_rows_ = {};
}

void OpenClBackend::Finish() {
  Flush();
  Check(clFinish(queue_.get()), "clFinish");
}

void OpenClBackend::ReadCells(cl_mem buffer, std::size_t element, void* dst) {
  Flush();
  const std::size_t origin[3] = {std::size_t(layout_.pad_x) * element, std::size_t(layout_.pad_y),
                                 0};
  const std::size_t host_origin[3] = {0, 0, 0};
  const std::size_t region[3] = {std::size_t(params_.width) * element, std::size_t(params_.height),
                                 1};
  Check(clEnqueueReadBufferRect(queue_.get(), buffer, CL_TRUE, origin, host_origin, region,
                                std::size_t(layout_.stride) * element, 0, region[0], 0, dst, 0,
                                nullptr, nullptr),
        "clEnqueueReadBufferRect");
}

void OpenClBackend::WriteCells(cl_mem buffer, std::size_t element, const void* src) {
  Flush();
  const std::size_t origin[3] = {std::size_t(layout_.pad_x) * element, std::size_t(layout_.pad_y),
                                 0};
  const std::size_t host_origin[3] = {0, 0, 0};
  const std::size_t region[3] = {std::size_t(params_.width) * element, std::size_t(params_.height),
                                 1};
  Check(clEnqueueWriteBufferRect(queue_.get(), buffer, CL_TRUE, origin, host_origin, region,
                                 std::size_t(layout_.stride) * element, 0, region[0], 0, src, 0,
                                 nullptr, nullptr),
        "clEnqueueWriteBufferRect");
}

// Flush() before choosing the map buffer: a deferred shift moves the map to the other one.
void OpenClBackend::ReadLogOdds(LogOdds* dst) {
  Flush();
  ReadCells(map_[current_].get(), sizeof(LogOdds), dst);
}
void OpenClBackend::WriteLogOdds(const LogOdds* src) {
  Flush();
  levels_valid_ = false;
  known_[current_] = {0, params_.height};
  WriteCells(map_[current_].get(), sizeof(LogOdds), src);
}
void OpenClBackend::ReadUpdateMask(std::uint8_t* dst) { ReadCells(update_.get(), 1, dst); }
void OpenClBackend::WriteUpdateMask(const std::uint8_t* src) { WriteCells(update_.get(), 1, src); }
void OpenClBackend::ReadFree(std::uint8_t* dst) {
  Flush();
  Check(clEnqueueReadBuffer(queue_.get(), free_.get(), CL_TRUE, 0, free_host_.size() * 8,
                            free_host_.data(), 0, nullptr, nullptr),
        "clEnqueueReadBuffer");
  const int width = params_.width, nw = BitWords();
  for (int r = 0; r < params_.height; ++r) {
    for (int c = 0; c < width; ++c) {
      dst[std::size_t(r) * width + c] = (free_host_[std::size_t(r) * nw + c / 64] >> (c % 64)) & 1;
    }
  }
}
void OpenClBackend::ReadRayDelta(std::int32_t* dst) {
  ReadCells(delta_.get(), sizeof(std::int32_t), dst);
}
void OpenClBackend::WriteFree(const std::uint8_t* src) {
  Flush();
  const int width = params_.width, nw = BitWords();
  std::fill(free_host_.begin(), free_host_.end(), std::uint64_t{0});
  free_rows_ = {0, params_.height};
  for (int r = 0; r < params_.height; ++r) {
    for (int c = 0; c < width; ++c) {
      if (src[std::size_t(r) * width + c]) {
        free_host_[std::size_t(r) * nw + c / 64] |= std::uint64_t{1} << (c % 64);
      }
    }
  }
  Check(clEnqueueWriteBuffer(queue_.get(), free_.get(), CL_TRUE, 0, free_host_.size() * 8,
                             free_host_.data(), 0, nullptr, nullptr),
        "clEnqueueWriteBuffer");
}

bool OpenClBackend::KernelTimes(StageTimes* times) const {
  double* fields[kStageCount] = {&times->rasterize_us, &times->fuse_us, &times->classify_us,
                                 &times->insight_us, &times->mask_us};
  bool any = false;
  for (int s = 0; s < kStageCount; ++s) {
    if (!begin_[s] || !end_[s]) continue;
    const cl_event last = end_[s].get();
    cl_ulong start = 0, stop = 0;
    if (clWaitForEvents(1, &last) == CL_SUCCESS &&
        clGetEventProfilingInfo(begin_[s].get(), CL_PROFILING_COMMAND_START, sizeof start, &start,
                                nullptr) == CL_SUCCESS &&
        clGetEventProfilingInfo(last, CL_PROFILING_COMMAND_END, sizeof stop, &stop, nullptr) ==
            CL_SUCCESS &&
        stop >= start) {
      for (const opencl::Event& part : more_[s]) {
        cl_ulong a = 0, b = 0;
        if (clGetEventProfilingInfo(part.get(), CL_PROFILING_COMMAND_START, sizeof a, &a,
                                    nullptr) == CL_SUCCESS &&
            clGetEventProfilingInfo(part.get(), CL_PROFILING_COMMAND_END, sizeof b, &b, nullptr) ==
                CL_SUCCESS) {
          start = std::min(start, a);
          stop = std::max(stop, b);
        }
      }
      *fields[s] = double(stop - start) * 1e-3;
      any = true;
    }
    begin_[s].reset();
    end_[s].reset();
    more_[s].clear();
  }
  return any;
}

}  // namespace freespace
