// OpenClBackend: buffers, kernels and work sizes set up once; per scan, only enqueues (plus the
// job upload and the C_Edge read-back). Kernel arguments that are buffers are set at
// construction (and again only when the job buffer grows); per call only scalars change.
#include "opencl_backend.hpp"

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "freespace/errors.hpp"

namespace freespace {
namespace {

using opencl::Check;

std::size_t RoundUp(std::size_t n, std::size_t multiple) {
  return (n + multiple - 1) / multiple * multiple;
}

template <typename T>
void SetArg(cl_kernel kernel, cl_uint index, const T& value) {
  Check(clSetKernelArg(kernel, index, sizeof(T), &value), "clSetKernelArg");
}

// A second reference to `event`, for a stage whose first command is also its last.
opencl::Event Retained(cl_event event) {
  Check(clRetainEvent(event), "clRetainEvent");
  return opencl::Event(event);
}

// Preferred work-group sizes on the CPU (PoCL), all small enough for any GPU.
constexpr std::size_t kGridColumns = 64;  // classify and shift rows of work-items
constexpr std::size_t kCellGroup = 256;   // fuse, rays_fuse
constexpr std::size_t kEdgeGroup = 16;    // rasterize_edges, rays_cast: uneven loop lengths
constexpr std::size_t kCastGroup = 16;    // insight_cast
constexpr std::size_t kCompactGroup = 256;
constexpr std::size_t kMaxRasterGroup = 256;

// Initial capacity of the job buffer, in ints: a ScaLa scan (581 beams, ~2000 echoes) fits.
constexpr std::size_t kInitialJobInts = 4 + 2 * 4096 + 8192;

}  // namespace

std::string OpenClBackend::BuildOptions(const KernelParams& p, int raster_group) {
  std::ostringstream o;
  o << "-cl-std=CL1.2 -DWIDTH=" << p.width << " -DHEIGHT=" << p.height << " -DL_FREE=(" << p.l_free
    << ") -DL_OCCUPIED=(" << p.l_occupied << ") -DL_MIN=(" << p.l_min << ") -DL_MAX=(" << p.l_max
    << ") -DT_LOW=(" << p.t_low << ") -DT_HIGH=(" << p.t_high
    << ") -DOPENING_RADIUS=" << p.opening_radius << " -DFIXED_BITS=" << kFixedBits
    << " -DUPDATE_NONE=" << int(kUpdateNone) << " -DUPDATE_FREE=" << int(kUpdateFree)
    << " -DUPDATE_OCCUPIED=" << int(kUpdateOccupied) << " -DRASTER_GROUP=" << raster_group;
  return o.str();
}

OpenClBackend::OpenClBackend(const KernelParams& params, const BackendConfig& config)
    : Backend(params),
      device_(opencl::DeviceContext::Get(opencl::ChooseDevice(config))),
      name_("opencl: " + device_->choice().device_name) {
  const int width = params.width, height = params.height, h = params.opening_radius;
  if (width < 1 || height < 1 || h < 0) {
    throw BackendError("backend opencl: bad map size " + std::to_string(width) + " x " +
                       std::to_string(height));
  }
  const cl_context context = device_->context();
  const cl_device_id device = device_->device();
  cl_int status = CL_SUCCESS;
  queue_.reset(clCreateCommandQueue(context, device, CL_QUEUE_PROFILING_ENABLE, &status));
  Check(status, "clCreateCommandQueue");

  // One work-group per row in rasterize_rows: enough work-items for one word each, a power of
  // two the device allows.
  std::size_t max_group = 1, max_items[3] = {1, 1, 1};
  Check(
      clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof max_group, &max_group, nullptr),
      "clGetDeviceInfo");
  Check(
      clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_ITEM_SIZES, sizeof max_items, max_items, nullptr),
      "clGetDeviceInfo");
  const std::size_t words = (std::size_t(width) + 31) / 32;
  const std::size_t raster_cap = std::min({kMaxRasterGroup, max_group, max_items[0]});
  while (std::size_t(raster_group_) < words && std::size_t(raster_group_) * 2 <= raster_cap) {
    raster_group_ *= 2;
  }
  program_ = device_->EmbeddedProgram(BuildOptions(params, raster_group_));

  rasterize_edges_ = MakeKernel("rasterize_edges");
  rasterize_rows_ = MakeKernel("rasterize_rows");
  insight_cast_ = MakeKernel("insight_cast");
  insight_compact_ = MakeKernel("insight_compact");
  rays_cast_ = MakeKernel("rays_cast");
  erode_rows_ = MakeKernel("classify_erode_rows");
  erode_cols_ = MakeKernel("classify_erode_cols");
  dilate_rows_ = MakeKernel("classify_dilate_rows");
  dilate_cols_ = MakeKernel("classify_dilate_cols");
  for (int k = 0; k < 2; ++k) {
    fuse_[k] = MakeKernel("fuse");
    rays_fuse_[k] = MakeKernel("rays_fuse");
    hysteresis_[k] = MakeKernel("classify_hysteresis");
    shift_[k] = MakeKernel("shift_map");
  }
  if (LocalSize(rasterize_rows_.get(), raster_group_) < std::size_t(raster_group_)) {
    throw BackendError("backend opencl: rasterize_rows cannot run work-groups of " +
                       std::to_string(raster_group_) + " on this device");
  }

  // Buffers.
  auto buffer = [&](std::size_t bytes) {
    opencl::Mem mem(clCreateBuffer(context, CL_MEM_READ_WRITE, std::max<std::size_t>(bytes, 4),
                                   nullptr, &status));
    Check(status, "clCreateBuffer");
    return mem;
  };
  const std::size_t labels = std::size_t(BorderLabelCount(height, width));
  const std::size_t padded = std::size_t(width + 2 * h) * std::size_t(height + 2 * h);
  const std::size_t bit_words = words * std::size_t(height);
  for (opencl::Mem& map : map_) map = buffer(cells() * sizeof(LogOdds));
  update_ = buffer(cells());
  toggles_ = buffer(bit_words * 4);
  occupied_ = buffer(bit_words * 4);
  pass_a_ = buffer(padded);
  pass_b_ = buffer(padded);
  free_ = buffer(cells());
  label_ = buffer(cells() * 4);
  stop_ = buffer(labels * 4);
  edges_ = buffer((labels + 1) * 4);
  delta_ = buffer(cells() * 4);
  GrowJob(kInitialJobInts);
  edges_host_.assign(labels + 1, 0);

  // Initial contents: the map unknown, the bit planes and the padded borders zero, T empty.
  for (opencl::Mem& map : map_) Fill(map.get(), cells() * sizeof(LogOdds));
  Fill(update_.get(), cells());
  Fill(toggles_.get(), bit_words * 4);
  Fill(occupied_.get(), bit_words * 4);
  Fill(pass_a_.get(), padded);
  Fill(pass_b_.get(), padded);
  Fill(free_.get(), cells());
  Fill(delta_.get(), cells() * 4);
  const cl_int none = INT_MAX;
  Check(clEnqueueFillBuffer(queue_.get(), label_.get(), &none, sizeof none, 0, cells() * 4, 0,
                            nullptr, nullptr),
        "clEnqueueFillBuffer");

  // Buffer arguments, set once.
  const cl_kernel edges = rasterize_edges_.get(), rows = rasterize_rows_.get();
  SetArg(edges, 1, toggles_.get());
  SetArg(edges, 2, occupied_.get());
  SetArg(edges, 3, update_.get());
  SetArg(rows, 1, toggles_.get());
  SetArg(rows, 2, occupied_.get());
  SetArg(rows, 3, update_.get());
  SetArg(rays_cast_.get(), 1, delta_.get());
  SetArg(erode_rows_.get(), 0, pass_a_.get());
  SetArg(erode_rows_.get(), 1, pass_b_.get());
  SetArg(erode_cols_.get(), 0, pass_b_.get());
  SetArg(erode_cols_.get(), 1, pass_a_.get());
  SetArg(dilate_rows_.get(), 0, pass_a_.get());
  SetArg(dilate_rows_.get(), 1, pass_b_.get());
  SetArg(dilate_cols_.get(), 0, pass_b_.get());
  SetArg(dilate_cols_.get(), 1, free_.get());
  SetArg(insight_cast_.get(), 0, free_.get());
  SetArg(insight_cast_.get(), 1, label_.get());
  SetArg(insight_cast_.get(), 2, stop_.get());
  SetArg(insight_compact_.get(), 0, stop_.get());
  SetArg(insight_compact_.get(), 1, label_.get());
  SetArg(insight_compact_.get(), 2, edges_.get());
  for (int k = 0; k < 2; ++k) {
    SetArg(fuse_[k].get(), 0, map_[k].get());
    SetArg(fuse_[k].get(), 1, update_.get());
    SetArg(rays_fuse_[k].get(), 0, map_[k].get());
    SetArg(rays_fuse_[k].get(), 1, delta_.get());
    SetArg(hysteresis_[k].get(), 0, map_[k].get());
    SetArg(hysteresis_[k].get(), 1, pass_a_.get());
    SetArg(shift_[k].get(), 0, map_[k].get());
    SetArg(shift_[k].get(), 1, map_[1 - k].get());
  }

  // Work sizes. Global sizes are rounded up to whole work-groups; the kernels skip the extra
  // work-items, so no size has to divide the map.
  grid_local_[0] = LocalSize(erode_rows_.get(), kGridColumns);
  for (const cl_kernel k : {erode_cols_.get(), dilate_rows_.get(), dilate_cols_.get(),
                            hysteresis_[0].get(), shift_[0].get()}) {
    grid_local_[0] = std::min(grid_local_[0], LocalSize(k, kGridColumns));
  }
  grid_local_[0] = std::min(grid_local_[0], max_items[0]);
  grid_global_[0] = RoundUp(std::size_t(width), grid_local_[0]);
  grid_global_[1] = std::size_t(height);
  cell_local_ =
      std::min(LocalSize(fuse_[0].get(), kCellGroup), LocalSize(rays_fuse_[0].get(), kCellGroup));
  edge_local_ = std::min(LocalSize(rasterize_edges_.get(), kEdgeGroup),
                         LocalSize(rays_cast_.get(), kEdgeGroup));
  cast_local_ = LocalSize(insight_cast_.get(), kCastGroup);
  cast_global_ = RoundUp(labels, cast_local_);
  compact_size_ = LocalSize(insight_compact_.get(), kCompactGroup);
  Check(clSetKernelArg(insight_compact_.get(), 3, compact_size_ * sizeof(cl_int), nullptr),
        "clSetKernelArg");

  Finish();
}

OpenClBackend::~OpenClBackend() {
  // Pending commands may still read job_host_; never throw from here.
  if (queue_) clFinish(queue_.get());
}

opencl::Kernel OpenClBackend::MakeKernel(const char* name) const {
  cl_int status = CL_SUCCESS;
  opencl::Kernel kernel(clCreateKernel(program_, name, &status));
  if (status != CL_SUCCESS) {
    throw BackendError(std::string("backend opencl: kernel ") + name + ": " +
                       opencl::ErrorName(status) + " (" + std::to_string(status) + ")");
  }
  return kernel;
}

std::size_t OpenClBackend::LocalSize(cl_kernel kernel, std::size_t preferred) const {
  std::size_t most = 1;
  Check(clGetKernelWorkGroupInfo(kernel, device_->device(), CL_KERNEL_WORK_GROUP_SIZE, sizeof most,
                                 &most, nullptr),
        "clGetKernelWorkGroupInfo");
  return std::max<std::size_t>(1, std::min(preferred, most));
}

void OpenClBackend::Launch(cl_kernel kernel, cl_uint dims, const std::size_t* global,
                           const std::size_t* local, cl_event* event) {
  const cl_int status =
      clEnqueueNDRangeKernel(queue_.get(), kernel, dims, nullptr, global, local, 0, nullptr, event);
  if (status == CL_SUCCESS) return;
  char name[128] = "?";
  clGetKernelInfo(kernel, CL_KERNEL_FUNCTION_NAME, sizeof name, name, nullptr);
  throw BackendError(std::string("backend opencl: enqueueing kernel ") + name + ": " +
                     opencl::ErrorName(status) + " (" + std::to_string(status) + ")");
}

void OpenClBackend::GrowJob(std::size_t ints) {
  // The previous upload may still be reading the staging area.
  if (upload_done_) {
    const cl_event wait = upload_done_.get();
    Check(clWaitForEvents(1, &wait), "clWaitForEvents");
  }
  job_capacity_ = std::max(ints, 2 * job_capacity_);
  job_host_.assign(job_capacity_, 0);
  cl_int status = CL_SUCCESS;
  // Commands already enqueued keep the old buffer alive until they finish.
  job_.reset(
      clCreateBuffer(device_->context(), CL_MEM_READ_ONLY, job_capacity_ * 4, nullptr, &status));
  Check(status, "clCreateBuffer");
  SetArg(rasterize_edges_.get(), 0, job_.get());
  SetArg(rasterize_rows_.get(), 0, job_.get());
  SetArg(rays_cast_.get(), 0, job_.get());
}

void OpenClBackend::Upload(const std::int32_t (&header)[4], const std::int32_t* a,
                           std::size_t a_count, const std::int32_t* b, std::size_t b_count,
                           opencl::Event* event) {
  const std::size_t total = 4 + a_count + b_count;
  if (total > job_capacity_) GrowJob(total);
  if (upload_done_) {
    // Normally long finished: the scan that made it ended with a blocking read.
    const cl_event wait = upload_done_.get();
    Check(clWaitForEvents(1, &wait), "clWaitForEvents");
  }
  std::int32_t* staging = job_host_.data();
  std::memcpy(staging, header, sizeof header);
  if (a_count > 0) std::memcpy(staging + 4, a, a_count * 4);
  if (b_count > 0) std::memcpy(staging + 4 + a_count, b, b_count * 4);
  Check(clEnqueueWriteBuffer(queue_.get(), job_.get(), CL_FALSE, 0, total * 4, staging, 0, nullptr,
                             event->out()),
        "clEnqueueWriteBuffer");
  upload_done_ = Retained(event->get());
}

void OpenClBackend::SetStage(Stage stage, opencl::Event begin, opencl::Event end) {
  begin_[stage] = std::move(begin);
  end_[stage] = std::move(end);
}

void OpenClBackend::Rasterize(const RasterJob& job) {
  const int r0 = std::max(job.row_begin, 0);
  const int r1 = std::min(job.row_end, params_.height);
  if (r0 >= r1) return;
  const int n = std::max(job.vertex_count, 0), occupied = std::max(job.occupied_count, 0);
  const std::int32_t header[4] = {n, occupied, r0, r1};
  opencl::Event begin, end;
  Upload(header, job.vertices, 2 * std::size_t(n), job.occupied, std::size_t(occupied), &begin);
  if (n + occupied > 0) {
    const std::size_t global = RoundUp(std::size_t(n + occupied), edge_local_);
    Launch(rasterize_edges_.get(), 1, &global, &edge_local_, nullptr);
  }
  const std::size_t group = std::size_t(raster_group_);
  const std::size_t global[2] = {group, std::size_t(r1 - r0)};
  const std::size_t local[2] = {group, 1};
  Launch(rasterize_rows_.get(), 2, global, local, end.out());
  SetStage(kRasterStage, std::move(begin), std::move(end));
}

void OpenClBackend::Fuse(int row_begin, int row_end) {
  const int r0 = std::max(row_begin, 0), r1 = std::min(row_end, params_.height);
  if (r0 >= r1) return;
  const cl_kernel kernel = fuse_[current_].get();
  const cl_int first = r0 * params_.width, count = (r1 - r0) * params_.width;
  SetArg(kernel, 2, first);
  SetArg(kernel, 3, count);
  const std::size_t global = RoundUp(std::size_t(count), cell_local_);
  opencl::Event event;
  Launch(kernel, 1, &global, &cell_local_, event.out());
  opencl::Event again = Retained(event.get());
  SetStage(kFuseStage, std::move(event), std::move(again));
}

void OpenClBackend::CastRays(const RayJob& job) {
  const int n = std::max(job.ray_count, 0);
  if (n == 0) return;
  const std::int32_t header[4] = {n, job.origin_col, job.origin_row, 0};
  opencl::Event begin, end;
  Upload(header, job.ends, 2 * std::size_t(n), nullptr, 0, &begin);
  const std::size_t global = RoundUp(std::size_t(n), edge_local_);
  Launch(rays_cast_.get(), 1, &global, &edge_local_, end.out());
  SetStage(kRasterStage, std::move(begin), std::move(end));
}

void OpenClBackend::FuseRays(int row_begin, int row_end) {
  const int r0 = std::max(row_begin, 0), r1 = std::min(row_end, params_.height);
  if (r0 >= r1) return;
  const cl_kernel kernel = rays_fuse_[current_].get();
  const cl_int first = r0 * params_.width, count = (r1 - r0) * params_.width;
  SetArg(kernel, 2, first);
  SetArg(kernel, 3, count);
  const std::size_t global = RoundUp(std::size_t(count), cell_local_);
  opencl::Event event;
  Launch(kernel, 1, &global, &cell_local_, event.out());
  opencl::Event again = Retained(event.get());
  SetStage(kFuseStage, std::move(event), std::move(again));
}

void OpenClBackend::Classify() {
  opencl::Event begin, end;
  Launch(hysteresis_[current_].get(), 2, grid_global_, grid_local_, begin.out());
  Launch(erode_rows_.get(), 2, grid_global_, grid_local_, nullptr);
  Launch(erode_cols_.get(), 2, grid_global_, grid_local_, nullptr);
  Launch(dilate_rows_.get(), 2, grid_global_, grid_local_, nullptr);
  Launch(dilate_cols_.get(), 2, grid_global_, grid_local_, end.out());
  SetStage(kClassifyStage, std::move(begin), std::move(end));
}

void OpenClBackend::InSight(CellIndex vehicle, std::vector<CellIndex>* edges) {
  const cl_kernel cast = insight_cast_.get();
  SetArg(cast, 3, cl_int(vehicle.col));
  SetArg(cast, 4, cl_int(vehicle.row));
  opencl::Event begin, end;
  Launch(cast, 1, &cast_global_, &cast_local_, begin.out());
  Launch(insight_compact_.get(), 1, &compact_size_, &compact_size_, nullptr);
  Check(clEnqueueReadBuffer(queue_.get(), edges_.get(), CL_TRUE, 0, edges_host_.size() * 4,
                            edges_host_.data(), 0, nullptr, end.out()),
        "clEnqueueReadBuffer");
  SetStage(kInSightStage, std::move(begin), std::move(end));
  const int width = params_.width;
  const int count = edges_host_[0];
  edges->clear();
  for (int i = 1; i <= count; ++i)
    edges->push_back({edges_host_[i] / width, edges_host_[i] % width});
}

void OpenClBackend::Shift(int dx, int dy) {
  if (dx == 0 && dy == 0) return;
  if (std::abs(dx) >= params_.width || std::abs(dy) >= params_.height) {
    Fill(map_[current_].get(), cells() * sizeof(LogOdds));
    return;
  }
  const cl_kernel kernel = shift_[current_].get();
  SetArg(kernel, 2, cl_int(dx));
  SetArg(kernel, 3, cl_int(dy));
  Launch(kernel, 2, grid_global_, grid_local_, nullptr);
  current_ = 1 - current_;
}

void OpenClBackend::Clear() {
  Fill(map_[current_].get(), cells() * sizeof(LogOdds));
  Fill(free_.get(), cells());
}

void OpenClBackend::Finish() { Check(clFinish(queue_.get()), "clFinish"); }

void OpenClBackend::Fill(cl_mem buffer, std::size_t bytes) {
  const cl_uchar zero = 0;
  Check(clEnqueueFillBuffer(queue_.get(), buffer, &zero, 1, 0, bytes, 0, nullptr, nullptr),
        "clEnqueueFillBuffer");
}

void OpenClBackend::Read(cl_mem buffer, std::size_t bytes, void* dst) {
  Check(clEnqueueReadBuffer(queue_.get(), buffer, CL_TRUE, 0, bytes, dst, 0, nullptr, nullptr),
        "clEnqueueReadBuffer");
}

void OpenClBackend::Write(cl_mem buffer, std::size_t bytes, const void* src) {
  Check(clEnqueueWriteBuffer(queue_.get(), buffer, CL_TRUE, 0, bytes, src, 0, nullptr, nullptr),
        "clEnqueueWriteBuffer");
}

void OpenClBackend::ReadLogOdds(LogOdds* dst) {
  Read(map_[current_].get(), cells() * sizeof(LogOdds), dst);
}
void OpenClBackend::WriteLogOdds(const LogOdds* src) {
  Write(map_[current_].get(), cells() * sizeof(LogOdds), src);
}
void OpenClBackend::ReadUpdateMask(std::uint8_t* dst) { Read(update_.get(), cells(), dst); }
void OpenClBackend::WriteUpdateMask(const std::uint8_t* src) { Write(update_.get(), cells(), src); }
void OpenClBackend::ReadFree(std::uint8_t* dst) { Read(free_.get(), cells(), dst); }
void OpenClBackend::ReadRayDelta(std::int32_t* dst) {
  Read(delta_.get(), cells() * sizeof(std::int32_t), dst);
}
void OpenClBackend::WriteFree(const std::uint8_t* src) { Write(free_.get(), cells(), src); }

bool OpenClBackend::KernelTimes(StageTimes* times) const {
  double* fields[kStageCount] = {&times->rasterize_us, &times->fuse_us, &times->classify_us,
                                 &times->insight_us};
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
      *fields[s] = double(stop - start) * 1e-3;
      any = true;
    }
    begin_[s].reset();
    end_[s].reset();
  }
  return any;
}

}  // namespace freespace
