// OpenClBackend: buffers, kernels and work sizes set up once; per scan, only enqueues (plus the
// job upload and the stop-cell read-back). Kernel arguments that are buffers are set at
// construction (and again only when the job buffer grows); per call only scalars change.
#include "opencl/backend.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
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

// Work-group sizes. Kernels over cells run one work-item per row on a CPU (it loops over the
// row's 16-cell vectors) and about one per vector elsewhere.
constexpr std::size_t kCpuRowsPerGroup = 4;
constexpr std::size_t kGpuGroup = 64;
constexpr std::size_t kGpuRowGroup = 256;  // at most this many work-items for one row
constexpr std::size_t kEdgeGroup = 16;     // rasterize_edges, rays_cast: uneven loop lengths
constexpr std::size_t kCastGroup = 16;     // insight_cast
// insight_claim (the in-sight scan split over devices): about this many chunks of labels per
// device, so that the devices even out within a chunk's time (at 1500 x 1500 cells, 94 rays:
// a few microseconds) for a few dozen claims of the shared counter.
constexpr std::size_t kClaimsPerDevice = 32;
constexpr std::size_t kBandsPerUnit = 1;  // rasterize_bands
// classify_bands: more bands than compute units, so that a unit that starts late still finds
// work; each band recomputes 4 OPENING_RADIUS rows of its neighbours'.
constexpr std::size_t kClassifyBandsPerUnit = 2;
constexpr std::size_t kMaxRasterGroup = 256;

// How long the threads that drive the other devices of a split keep polling after a scan's
// in-sight stage: long enough for the host's stages between two scans back to back (the
// polygon, then the next scan's preprocessing: 25-130 us on the development machine), so that
// the next scan's first split stage finds them awake (a wake-up there costs 10-50 us); scans
// further apart pay the wake-up instead of a core kept busy.
constexpr std::chrono::microseconds kCrewLinger(300);
// And after any stage call: a caller that stops between stages (or throws) leaves them polling
// for this long at most.
constexpr std::chrono::microseconds kCrewWindow(2000);

// Initial capacity of the job buffer, in ints: a ScaLa scan (581 beams, ~2000 echoes) fits.
constexpr std::size_t kInitialJobInts = 8 + 2 * 4096 + 8192 + 8193;

}  // namespace

template <typename T>
void OpenClBackend::SetArgAll(cl_kernel kernel, cl_uint index, const T& value) {
  SetArg(kernel, index, value);
  for (int d = 1; d < devices_; ++d) {
    if (const cl_kernel twin = Twin(kernel, d)) SetArg(twin, index, value);
  }
}

cl_kernel OpenClBackend::Twin(cl_kernel kernel, int d) const {
  if (d == 0) return kernel;
  for (const auto& [original, twin] : lanes_[std::size_t(d - 1)].twins) {
    if (original == kernel) return twin.get();
  }
  return nullptr;
}

template <typename Enqueue>
void OpenClBackend::SplitRun(int parts, const Enqueue& enqueue) {
  // The parts read what device 0's queue wrote; the CPU devices of one context share the
  // buffers' memory, and each part's queue is finished before Run returns.
  Check(clFinish(queue_.get()), "clFinish");
  split_parts_.clear();
  split_parts_.resize(std::size_t(parts));  // within the capacity reserved at construction
  const auto run = [&](int part, int d) {
    enqueue(part, d, split_parts_[std::size_t(part)].out());
    Check(clFinish(QueueOf(d)), "clFinish");
  };
  if (crew_ != nullptr) {
    crew_->Run(parts, run);
  } else {
    for (int part = 0; part < parts; ++part) run(part, part % devices_);
  }
}

OpenClBackend::Layout OpenClBackend::MakeLayout(const KernelParams& p) {
  // Room for the opening window and the +-1 of the hysteresis on every side; 64-aligned rows,
  // so that the kernels can store 16 or 64 cells at once.
  const int pad = std::max(p.opening_radius, 1);
  Layout layout;
  layout.pad_x = int(RoundUp(std::size_t(pad), 64));
  layout.pad_y = pad;
  layout.stride =
      int(RoundUp(std::size_t(layout.pad_x) + RoundUp(std::size_t(p.width), 16) + pad, 64));
  layout.cells = std::size_t(layout.stride) * std::size_t(p.height + 2 * pad);
  return layout;
}

std::string OpenClBackend::BuildOptions(const KernelParams& p, int vectors_per_item,
                                        int raster_group, bool bands) {
  const Layout layout = MakeLayout(p);
  std::ostringstream o;
  o << "-cl-std=CL1.2 -DWIDTH=" << p.width << " -DHEIGHT=" << p.height
    << " -DPAD_X=" << layout.pad_x << " -DPAD_Y=" << layout.pad_y << " -DSTRIDE=" << layout.stride
    << " -DVECTORS_PER_ITEM=" << vectors_per_item << " -DL_FREE=(" << p.l_free << ") -DL_OCCUPIED=("
    << p.l_occupied << ") -DL_MIN=(" << p.l_min << ") -DL_MAX=(" << p.l_max << ") -DT_LOW=("
    << p.t_low << ") -DT_HIGH=(" << p.t_high << ") -DOPENING_RADIUS=" << p.opening_radius
    << " -DFIXED_BITS=" << kFixedBits << " -DUPDATE_NONE=" << int(kUpdateNone)
    << " -DUPDATE_FREE=" << int(kUpdateFree) << " -DUPDATE_OCCUPIED=" << int(kUpdateOccupied)
    << " -DRASTER_GROUP=" << raster_group << " -DRASTER_SERIAL=" << (bands ? 1 : 0);
  return o.str();
}

OpenClBackend::OpenClBackend(const KernelParams& params, const BackendConfig& config,
                             WorkShape shape)
    : Backend(params),
      device_(opencl::DeviceContext::Get(opencl::ChooseDevices(config))),
      name_("opencl: " + device_->choice().device_name),
      wait_(config.opencl_wait, config.opencl_spin_us),
      devices_(int(device_->devices().size())) {
  if (devices_ > 1) name_ += " x " + std::to_string(devices_);
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

  std::size_t max_group = 1, max_items[3] = {1, 1, 1};
  cl_device_type type = 0;
  Check(
      clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof max_group, &max_group, nullptr),
      "clGetDeviceInfo");
  Check(
      clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_ITEM_SIZES, sizeof max_items, max_items, nullptr),
      "clGetDeviceInfo");
  Check(clGetDeviceInfo(device, CL_DEVICE_TYPE, sizeof type, &type, nullptr), "clGetDeviceInfo");
  cl_uint units = 1;
  Check(clGetDeviceInfo(device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, nullptr),
        "clGetDeviceInfo");
  compute_units_ = std::max<cl_uint>(units, 1);
  const bool cpu = shape == WorkShape::kDevice ? (type & CL_DEVICE_TYPE_CPU) != 0
                                               : shape == WorkShape::kRowPerItem;

  // A CPU runs a work-group's items one after the other, so it gets one work-item per row that
  // loops over the row, and stage 1 as rasterize_bands, one work-item per band of rows. A GPU
  // gets about one work-item per 16-cell vector, and stage 1 as rasterize_edges (one work-item
  // per edge) and rasterize_rows (one work-group per row with enough work-items for one 32-cell
  // word each). Either way all work-items of a row are in one work-group (classify.cl relies on
  // it).
  bands_ = cpu;
  if (devices_ > 1 && !bands_) {
    throw BackendError("backend opencl: opencl_devices = " + std::to_string(devices_) +
                       " splits the kernels of the CPU shape only; \"" +
                       device_->choice().device_name + "\" runs the GPU shape");
  }
  layout_ = MakeLayout(params);
  const std::size_t row_vectors = RoundUp(std::size_t(width), 16) / 16;
  const std::size_t row_cap = std::min({kGpuRowGroup, max_group, max_items[0]});
  vectors_per_item_ = cpu ? int(row_vectors) : int((row_vectors + row_cap - 1) / row_cap);
  row_items_ = (row_vectors + vectors_per_item_ - 1) / vectors_per_item_;
  const std::size_t words = (std::size_t(width) + 31) / 32;
  const std::size_t raster_cap = std::min({kMaxRasterGroup, max_group, max_items[0]});
  while (!cpu && std::size_t(raster_group_) < words &&
         std::size_t(raster_group_) * 2 <= raster_cap) {
    raster_group_ *= 2;
  }
  program_ =
      device_->EmbeddedProgram(BuildOptions(params, vectors_per_item_, raster_group_, bands_));

  const char* row_pass = bands_ ? "rasterize_bands" : "rasterize_rows";
  rasterize_edges_ = MakeKernel("rasterize_edges");
  row_mask_ = MakeKernel(row_pass);
  insight_cast_ = MakeKernel("insight_cast");
  insight_claim_ = MakeKernel("insight_claim");
  rays_cast_ = MakeKernel("rays_cast");
  erode_dilate_ = MakeKernel("classify_erode_cols_dilate_rows");
  dilate_cols_ = MakeKernel("classify_dilate_cols");
  for (int k = 0; k < 2; ++k) {
    fuse_[k] = MakeKernel("fuse");
    rays_fuse_[k] = MakeKernel("rays_fuse");
    levels_[k] = MakeKernel("classify_levels");
    shift_[k] = MakeKernel("shift_map");
    hysteresis_[k] = MakeKernel("classify_hysteresis_erode_rows");
    classify_bands_[k] = MakeKernel("classify_bands");
    row_fuse_[k][0] = MakeKernel(row_pass);
    row_fuse_[k][1] = MakeKernel(row_pass);
  }
  // Split over devices: a queue and copies of the kernels that split for every device but the
  // first (kernel objects are not shared between threads).
  for (int d = 1; d < devices_; ++d) {
    Lane& lane = lanes_.emplace_back();
    lane.queue.reset(clCreateCommandQueue(context, device_->devices()[std::size_t(d)],
                                          CL_QUEUE_PROFILING_ENABLE, &status));
    Check(status, "clCreateCommandQueue");
    std::vector<cl_kernel> split = {row_mask_.get(), insight_claim_.get()};
    for (int k = 0; k < 2; ++k) {
      split.push_back(classify_bands_[k].get());
      split.push_back(row_fuse_[k][0].get());
      split.push_back(row_fuse_[k][1].get());
    }
    for (const cl_kernel kernel : split) {
      char name[128] = "";
      Check(clGetKernelInfo(kernel, CL_KERNEL_FUNCTION_NAME, sizeof name, name, nullptr),
            "clGetKernelInfo");
      lane.twins.emplace_back(kernel, MakeKernel(name));
    }
  }
  split_parts_.reserve(std::size_t(devices_));
  for (std::vector<opencl::Event>& more : more_) more.reserve(std::size_t(devices_));

  // Buffers.
  auto buffer = [&](std::size_t bytes) {
    opencl::Mem mem(clCreateBuffer(context, CL_MEM_READ_WRITE, std::max<std::size_t>(bytes, 4),
                                   nullptr, &status));
    Check(status, "clCreateBuffer");
    return mem;
  };
  const std::size_t labels = std::size_t(BorderLabelCount(height, width));
  const std::size_t padded = layout_.cells;
  const std::size_t bit_words = words * std::size_t(height);
  const std::size_t mask_bytes = std::size_t(BitWords()) * height * 8;
  for (opencl::Mem& map : map_) map = buffer(padded * sizeof(LogOdds));
  update_ = buffer(padded);
  toggles_ = buffer(bit_words * 4);
  occupied_ = buffer(bit_words * 4);
  const std::size_t level_bytes = std::size_t(2 * BitWords()) * height * 4;
  for (int k = 0; k < 2; ++k) {
    strong_[k] = buffer(level_bytes);
    weak_[k] = buffer(level_bytes);
  }
  // The three-kernel stage 3's intermediates; classify_bands (the CPU shape) keeps its rows in
  // band_rows_ instead.
  const std::size_t between_bytes = bands_ ? 8 : mask_bytes;
  bits_a_ = buffer(between_bytes);
  bits_b_ = buffer(between_bytes);
  bits_c_ = buffer(between_bytes);
  free_ = buffer(mask_bytes);
  // classify_bands: at most kClassifyBandsPerUnit bands of whole rows per compute unit, each
  // CLASSIFY_BAND_ROWS (classify.cl) bitset rows of scratch, in the CPU shape only.
  const std::size_t classify_bands =
      std::max<std::size_t>(kClassifyBandsPerUnit * compute_units_, std::size_t(devices_));
  band_rows_ =
      buffer(bands_ ? classify_bands * std::size_t(4 * h + 3) * std::size_t(BitWords()) * 8 : 8);
  stop_ = buffer(labels * 4);
  claims_ = buffer(4);
  delta_ = buffer(padded * 4);
  GrowJob(kInitialJobInts);
  stop_host_.assign(labels, 0);
  edge_seen_.assign((cells() + 63) / 64, 0);
  free_host_.assign(mask_bytes / 8, 0);
  row_counts_.assign(std::size_t(height) + 1, 0);

  // Initial contents: every cell buffer zero (the map unknown, the padding zero for good), the
  // bit planes and masks zero.
  for (opencl::Mem& map : map_) Fill(map.get(), padded * sizeof(LogOdds));
  Fill(update_.get(), padded);
  Fill(toggles_.get(), bit_words * 4);
  Fill(occupied_.get(), bit_words * 4);
  for (int k = 0; k < 2; ++k) {
    Fill(strong_[k].get(), level_bytes);
    Fill(weak_[k].get(), level_bytes);
  }
  Fill(bits_a_.get(), between_bytes);
  Fill(bits_b_.get(), between_bytes);
  Fill(bits_c_.get(), between_bytes);
  Fill(free_.get(), mask_bytes);
  Fill(delta_.get(), padded * 4);

  // Buffer arguments, set once.
  const cl_kernel edges = rasterize_edges_.get();
  SetArg(edges, 1, toggles_.get());
  SetArg(edges, 2, occupied_.get());
  SetArg(edges, 3, update_.get());
  // The row pass: the mask only (no map), in place on map_[k], or map_[k] shifted into the
  // other buffer, with the level bitsets of the buffer it writes (and reads).
  const cl_mem no_map = nullptr;
  const cl_uint levels_arg = bands_ ? 11 : 10;
  for (int k = 0; k < 2; ++k) {
    const cl_kernel kernels[3] = {row_mask_.get(), row_fuse_[k][0].get(), row_fuse_[k][1].get()};
    const cl_mem src[3] = {no_map, map_[k].get(), map_[k].get()};
    const cl_mem dst[3] = {no_map, map_[k].get(), map_[1 - k].get()};
    const int to[3] = {k, k, 1 - k};
    for (int i = 0; i < 3; ++i) {
      SetArgAll(kernels[i], 1, toggles_.get());
      SetArgAll(kernels[i], 2, occupied_.get());
      SetArgAll(kernels[i], 3, update_.get());
      SetArgAll(kernels[i], 4, src[i]);
      SetArgAll(kernels[i], 5, dst[i]);
      SetArgAll(kernels[i], levels_arg, strong_[to[i]].get());
      SetArgAll(kernels[i], levels_arg + 1, weak_[to[i]].get());
      SetArgAll(kernels[i], levels_arg + 2, strong_[k].get());
      SetArgAll(kernels[i], levels_arg + 3, weak_[k].get());
      SetArgAll(kernels[i], levels_arg + 4, cl_int(0));
      if (bands_) SetArgAll(kernels[i], levels_arg + 5, cl_int(0));  // first_band
    }
  }
  unknown_off_levels_ = params.t_high < 0;
  SetArg(rays_cast_.get(), 1, delta_.get());
  SetArg(erode_dilate_.get(), 0, bits_b_.get());
  SetArg(erode_dilate_.get(), 1, bits_a_.get());
  SetArg(erode_dilate_.get(), 2, bits_c_.get());
  SetArg(dilate_cols_.get(), 0, bits_c_.get());
  SetArg(dilate_cols_.get(), 1, free_.get());
  SetArg(insight_cast_.get(), 0, free_.get());
  SetArg(insight_cast_.get(), 1, stop_.get());
  SetArgAll(insight_claim_.get(), 0, free_.get());
  SetArgAll(insight_claim_.get(), 1, stop_.get());
  SetArgAll(insight_claim_.get(), 4, claims_.get());
  SetArgAll(insight_claim_.get(), 5,
            cl_int((labels + kClaimsPerDevice * devices_ - 1) / (kClaimsPerDevice * devices_)));
  for (int k = 0; k < 2; ++k) {
    SetArg(fuse_[k].get(), 0, map_[k].get());
    SetArg(fuse_[k].get(), 1, update_.get());
    SetArg(rays_fuse_[k].get(), 0, map_[k].get());
    SetArg(rays_fuse_[k].get(), 1, delta_.get());
    SetArg(levels_[k].get(), 0, map_[k].get());
    SetArg(levels_[k].get(), 1, strong_[k].get());
    SetArg(levels_[k].get(), 2, weak_[k].get());
    SetArg(hysteresis_[k].get(), 0, strong_[k].get());
    SetArg(hysteresis_[k].get(), 1, weak_[k].get());
    SetArg(hysteresis_[k].get(), 2, bits_a_.get());
    SetArg(hysteresis_[k].get(), 3, bits_b_.get());
    SetArgAll(classify_bands_[k].get(), 0, strong_[k].get());
    SetArgAll(classify_bands_[k].get(), 1, weak_[k].get());
    SetArgAll(classify_bands_[k].get(), 2, band_rows_.get());
    SetArgAll(classify_bands_[k].get(), 3, free_.get());
    SetArgAll(classify_bands_[k].get(), 7, cl_int(0));  // first_band
    SetArg(shift_[k].get(), 0, map_[k].get());
    SetArg(shift_[k].get(), 1, map_[1 - k].get());
  }

  // Work sizes. Global sizes are rounded up to whole work-groups; the kernels skip the extra
  // work-items, so no size has to divide the map.
  std::size_t most = max_group;
  for (const cl_kernel k : {erode_dilate_.get(), dilate_cols_.get(), hysteresis_[0].get(),
                            shift_[0].get(), fuse_[0].get(), rays_fuse_[0].get()}) {
    most = std::min(most, LocalSize(k, max_group));
  }
  if (row_items_ > most) {
    throw BackendError("backend opencl: a row of " + std::to_string(width) +
                       " cells needs work-groups of " + std::to_string(row_items_) +
                       " work-items; the kernels allow " + std::to_string(most));
  }
  rows_local_[0] = row_items_;
  rows_local_[1] = std::max<std::size_t>(
      1,
      std::min({cpu ? kCpuRowsPerGroup : kGpuGroup / row_items_, most / row_items_, max_items[1]}));
  // Bitset kernels: words of 64 cells, BIT_WORDS_PER_ITEM of them per work-item (common.cl).
  const std::size_t words_per_item = (std::size_t(vectors_per_item_) + 3) / 4;
  bit_items_ = (std::size_t(BitWords()) + words_per_item - 1) / words_per_item;
  bits_local_[0] = bit_items_;
  bits_local_[1] = std::max<std::size_t>(
      1,
      std::min({cpu ? kCpuRowsPerGroup : kGpuGroup / bit_items_, most / bit_items_, max_items[1]}));
  if (raster_group_ == 1) {
    raster_local_[0] = 1;
    raster_local_[1] = std::min(kCpuRowsPerGroup, LocalSize(row_mask_.get(), max_group));
  } else {
    if (LocalSize(row_mask_.get(), raster_group_) < std::size_t(raster_group_)) {
      throw BackendError("backend opencl: rasterize_rows cannot run work-groups of " +
                         std::to_string(raster_group_) + " on this device");
    }
    raster_local_[0] = std::size_t(raster_group_);
    raster_local_[1] = 1;
  }
  edge_local_ = std::min(LocalSize(rasterize_edges_.get(), kEdgeGroup),
                         LocalSize(rays_cast_.get(), kEdgeGroup));
  cast_local_ = LocalSize(insight_cast_.get(), kCastGroup);
  cast_global_ = RoundUp(labels, cast_local_);

  Finish();
}

Backend::CrewRequest OpenClBackend::WantedCrew() const {
  CrewRequest request;
  if (devices_ > 1) request = {devices_ - 1, kCrewLinger, kCrewWindow};
  return request;
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
  SetArgAll(row_mask_.get(), 0, job_.get());
  SetArg(rays_cast_.get(), 0, job_.get());
  for (const auto& pair : row_fuse_) {
    for (const opencl::Kernel& k : pair) SetArgAll(k.get(), 0, job_.get());
  }
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
  upload_done_ = Retained(event->get());
}

void OpenClBackend::SetStage(Stage stage, opencl::Event begin, opencl::Event end) {
  begin_[stage] = std::move(begin);
  end_[stage] = std::move(end);
  more_[stage].clear();
  more_[stage].swap(split_parts_);
}

void OpenClBackend::Rasterize(const RasterJob& job) {
  if (crew_) crew_->Wake();  // the split stages of this scan follow
  FlushRows();  // a pending shift may wait: the upload and rasterize_edges leave the map alone
  const int r0 = std::max(job.row_begin, 0);
  const int r1 = std::min(job.row_end, params_.height);
  if (r0 >= r1) return;
  const int n = std::max(job.vertex_count, 0), listed = std::max(job.occupied_count, 0);
  const int width = params_.width, rows = r1 - r0;

  // The occupied cells sorted by row (a counting sort), so that a band of rows finds its own:
  // count[j] becomes the first cell of row r0 + j, then the next free place of that row.
  std::int32_t* count = row_counts_.data();
  std::fill(count, count + rows + 1, 0);
  int other = 0;
  for (int i = 0; i < listed; ++i) {
    const int r = job.occupied[i] / width;
    if (r >= r0 && r < r1) {
      ++count[r - r0 + 1];
    } else {
      ++other;
    }
  }
  for (int j = 1; j <= rows; ++j) count[j] += count[j - 1];
  const int m = count[rows];
  const std::size_t ints =
      8 + 2 * std::size_t(n) + std::size_t(m) + std::size_t(rows) + 1 + std::size_t(other);
  std::int32_t* staging = Staging(ints);
  const std::int32_t header[8] = {n, m, r0, r1, other, 0, 0, 0};
  std::memcpy(staging, header, sizeof header);
  if (n > 0) std::memcpy(staging + 8, job.vertices, 2 * std::size_t(n) * 4);
  std::int32_t* cells = staging + 8 + 2 * std::size_t(n);
  std::int32_t* offsets = cells + m;
  std::int32_t* others = offsets + rows + 1;
  std::memcpy(offsets, count, (std::size_t(rows) + 1) * 4);
  for (int i = 0, o = 0; i < listed; ++i) {
    const std::int32_t cell = job.occupied[i];
    const int r = cell / width;
    if (r >= r0 && r < r1) {
      cells[count[r - r0]++] = cell;
    } else {
      others[o++] = cell;
    }
  }
  opencl::Event begin, end;
  Upload(ints, &begin);
  if (!bands_ && n + listed > 0) {  // rasterize_bands does the edges in its row pass
    const std::size_t global = RoundUp(std::size_t(n + listed), edge_local_);
    Launch(rasterize_edges_.get(), 1, &global, &edge_local_, end.out());
  } else {
    end = Retained(begin.get());
  }
  SetStage(kRasterStage, std::move(begin), std::move(end));
  rows_pending_ = true;
  pending_begin_ = r0;
  pending_end_ = r1;
}

void OpenClBackend::FlushRows() {
  if (!rows_pending_) return;
  rows_pending_ = false;
  RowPass(row_mask_.get(), 0, 0, pending_begin_, pending_end_, end_[kRasterStage].out());
  more_[kRasterStage].clear();
  more_[kRasterStage].swap(split_parts_);
}

void OpenClBackend::RowPass(cl_kernel kernel, int dx, int dy, int first, int end, cl_event* event) {
  SetArgAll(kernel, 6, cl_int(dx));
  SetArgAll(kernel, 7, cl_int(dy));
  SetArgAll(kernel, 8, cl_int(first));
  SetArgAll(kernel, 9, cl_int(end));
  const std::size_t rows = std::size_t(end - first);
  if (bands_ && devices_ > 1) {
    // One band per part, the parts over the devices; every command has one work-item.
    const int count = int(std::min<std::size_t>(rows, std::size_t(devices_)));
    const std::size_t band = (rows + std::size_t(count) - 1) / std::size_t(count);
    SetArgAll(kernel, 10, cl_int(band));
    SplitRun(count, [&](int part, int d, cl_event* e) {
      const cl_kernel twin = Twin(kernel, d);
      SetArg(twin, 16, cl_int(part));  // first_band
      const std::size_t one = 1;
      Launch(QueueOf(d), twin, 1, &one, &one, e);
    });
    Check(clRetainEvent(split_parts_[0].get()), "clRetainEvent");
    *event = split_parts_[0].get();
    return;
  }
  if (bands_) {
    // One band per compute unit: every band walks every edge of the polygon (a ScaLa scan has
    // over 2000), which costs more than the imbalance of uneven bands saves.
    const std::size_t bands = std::min<std::size_t>(rows, kBandsPerUnit * compute_units_);
    const std::size_t band = (rows + bands - 1) / bands;
    SetArg(kernel, 10, cl_int(band));
    const std::size_t global = (rows + band - 1) / band, local = 1;
    Launch(kernel, 1, &global, &local, event);
  } else {
    const std::size_t global[2] = {raster_local_[0], RoundUp(rows, raster_local_[1])};
    Launch(kernel, 2, global, raster_local_, event);
  }
}

void OpenClBackend::Fuse(int row_begin, int row_end) {
  if (crew_) crew_->Wake();
  const int r0 = std::max(row_begin, 0), r1 = std::min(row_end, params_.height);
  if (rows_pending_ && r0 == pending_begin_ && r1 == pending_end_) {
    // The row pass, the pending shift (the rows that can hold a known cell) or none (the
    // rasterized rows), the fusion.
    opencl::Event event;
    if (shift_pending_) {
      // Rows outside `rows` are unknown before and after (and on no level), so the pass
      // leaves them alone.
      const int to = 1 - current_;
      const RowSpan fused{r0, r1};
      const RowSpan next = known_[current_].Shifted(pending_dy_, params_.height).Hull(fused);
      const RowSpan rows = unknown_off_levels_ ? next.Hull(known_[to]).Hull(level_rows_[to])
                                               : RowSpan{0, params_.height};
      const cl_kernel kernel = row_fuse_[current_][1].get();
      SetArgAll(kernel, bands_ ? 15 : 14, cl_int(levels_valid_ && unknown_off_levels_));
      RowPass(kernel, pending_dx_, pending_dy_, rows.begin, rows.end, event.out());
      levels_valid_ = true;  // it wrote every row with a level bit
      known_[to] = next;
      // The rows it wrote outside `next` got no level bit (their map rows are unknown).
      level_rows_[to] = unknown_off_levels_ ? next : rows;
    } else {
      RowPass(row_fuse_[current_][0].get(), 0, 0, r0, r1, event.out());
      known_[current_] = known_[current_].Hull({r0, r1});
      level_rows_[current_] = level_rows_[current_].Hull({r0, r1});
    }
    if (shift_pending_) current_ = 1 - current_;
    shift_pending_ = rows_pending_ = false;
    opencl::Event again = Retained(event.get());
    SetStage(kFuseStage, std::move(event), std::move(again));
    return;
  }
  Flush();
  if (r0 >= r1) return;
  const cl_kernel kernel = fuse_[current_].get();
  levels_valid_ = false;
  known_[current_] = known_[current_].Hull({r0, r1});
  SetArg(kernel, 2, cl_int(r0));
  SetArg(kernel, 3, cl_int(r1));
  opencl::Event event;
  RowsLaunch(kernel, r1 - r0, event.out());
  opencl::Event again = Retained(event.get());
  SetStage(kFuseStage, std::move(event), std::move(again));
}

void OpenClBackend::CastRays(const RayJob& job) {
  if (crew_) crew_->Wake();
  Flush();
  const int n = std::max(job.ray_count, 0);
  if (n == 0) return;
  const std::size_t ints = 8 + 2 * std::size_t(n);
  std::int32_t* staging = Staging(ints);
  const std::int32_t header[8] = {n, job.origin_col, job.origin_row, 0, 0, 0, 0, 0};
  std::memcpy(staging, header, sizeof header);
  std::memcpy(staging + 8, job.ends, 2 * std::size_t(n) * 4);
  opencl::Event begin, end;
  Upload(ints, &begin);
  const std::size_t global = RoundUp(std::size_t(n), edge_local_);
  Launch(rays_cast_.get(), 1, &global, &edge_local_, end.out());
  SetStage(kRasterStage, std::move(begin), std::move(end));
}

void OpenClBackend::FuseRays(int row_begin, int row_end) {
  Flush();
  const int r0 = std::max(row_begin, 0), r1 = std::min(row_end, params_.height);
  if (r0 >= r1) return;
  const cl_kernel kernel = rays_fuse_[current_].get();
  levels_valid_ = false;
  known_[current_] = known_[current_].Hull({r0, r1});
  SetArg(kernel, 2, cl_int(r0));
  SetArg(kernel, 3, cl_int(r1));
  opencl::Event event;
  RowsLaunch(kernel, r1 - r0, event.out());
  opencl::Event again = Retained(event.get());
  SetStage(kFuseStage, std::move(event), std::move(again));
}

void OpenClBackend::LevelsWritten() {
  levels_valid_ = true;
  level_rows_[current_] = unknown_off_levels_ ? known_[current_] : RowSpan{0, params_.height};
}

void OpenClBackend::Classify() {
  if (crew_) crew_->Wake();
  Flush();
  opencl::Event begin, end;
  const int height = params_.height;
  const bool levels = !levels_valid_;
  if (levels) {
    BitsLaunch(levels_[current_].get(), height, begin.out());
    LevelsWritten();
  }
  // With unknown_off_levels_ a row without a level bit has no free0 bit and no eroded one, so
  // the free mask is empty outside level_rows_ widened by the opening radius.
  const int h = params_.opening_radius;
  const RowSpan set =
      unknown_off_levels_ ? level_rows_[current_].Widened(h, height) : RowSpan{0, height};
  if (bands_) {
    // The rows the free mask can have bits on, and those it had: the others stay empty.
    RowSpan rows = set.Hull(free_rows_);
    if (rows.empty()) rows = {0, 1};  // one row, so that the stage has its command
    const std::size_t count = std::size_t(rows.end - rows.begin);
    if (devices_ > 1) {
      // One band per part, the parts over the devices; every command has one work-item.
      const int parts = int(std::min(count, std::size_t(devices_)));
      const std::size_t band = (count + std::size_t(parts) - 1) / std::size_t(parts);
      const cl_kernel kernel = classify_bands_[current_].get();
      SetArgAll(kernel, 4, cl_int(band));
      SetArgAll(kernel, 5, cl_int(rows.begin));
      SetArgAll(kernel, 6, cl_int(rows.end));
      SplitRun(parts, [&](int part, int d, cl_event* e) {
        const cl_kernel twin = Twin(kernel, d);
        SetArg(twin, 7, cl_int(part));  // first_band
        const std::size_t one = 1;
        Launch(QueueOf(d), twin, 1, &one, &one, e);
      });
      if (!levels) begin = Retained(split_parts_[0].get());
      end = Retained(split_parts_[0].get());
      free_rows_ = set;
      SetStage(kClassifyStage, std::move(begin), std::move(end));
      return;
    }
    const std::size_t bands = std::min(count, kClassifyBandsPerUnit * compute_units_);
    const std::size_t band = (count + bands - 1) / bands, global = (count + band - 1) / band;
    const std::size_t one = 1;
    const cl_kernel kernel = classify_bands_[current_].get();
    SetArg(kernel, 4, cl_int(band));
    SetArg(kernel, 5, cl_int(rows.begin));
    SetArg(kernel, 6, cl_int(rows.end));
    Launch(kernel, 1, &global, &one, levels ? end.out() : begin.out());
    if (!levels) end = Retained(begin.get());
  } else {
    BitsLaunch(hysteresis_[current_].get(), height, levels ? nullptr : begin.out());
    BitsLaunch(erode_dilate_.get(), height, nullptr);
    BitsLaunch(dilate_cols_.get(), height, end.out());
  }
  free_rows_ = set;
  SetStage(kClassifyStage, std::move(begin), std::move(end));
}

void OpenClBackend::InSight(CellIndex vehicle, std::vector<CellIndex>* edges) {
  if (crew_) crew_->Wake();
  Flush();
  opencl::Event begin, end;
  if (devices_ > 1) {
    // One work-item per device, each claiming chunks of labels until none is left (the rays'
    // lengths differ by side and by map, the devices' speeds by what else runs); the claim
    // counter starts at 0 (the fill runs at SplitRun's finish of queue_).
    const cl_kernel claim = insight_claim_.get();
    SetArgAll(claim, 2, cl_int(vehicle.col));
    SetArgAll(claim, 3, cl_int(vehicle.row));
    Fill(claims_.get(), 4);
    SplitRun(devices_, [&](int, int d, cl_event* e) {
      const std::size_t one = 1;
      Launch(QueueOf(d), Twin(claim, d), 1, &one, &one, e);
    });
    begin = Retained(split_parts_[0].get());
  } else {
    const cl_kernel cast = insight_cast_.get();
    SetArg(cast, 2, cl_int(vehicle.col));
    SetArg(cast, 3, cl_int(vehicle.row));
    Launch(cast, 1, &cast_global_, &cast_local_, begin.out());
  }
  Check(clEnqueueReadBuffer(queue_.get(), stop_.get(), CL_FALSE, 0, stop_host_.size() * 4,
                            stop_host_.data(), 0, nullptr, end.out()),
        "clEnqueueReadBuffer");
  WaitForResult(end.get());
  if (crew_) crew_->Rest();  // until the next scan
  SetStage(kInSightStage, std::move(begin), std::move(end));
  CollectEdges(stop_host_.data(), int(stop_host_.size()), params_.width, edge_seen_.data(), edges);
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

void OpenClBackend::Shift(int dx, int dy) {
  if (crew_) crew_->Wake();  // the split stages of this scan follow
  Flush();
  if (dx == 0 && dy == 0) return;
  if (std::abs(dx) >= params_.width || std::abs(dy) >= params_.height) {
    levels_valid_ = false;
    Fill(map_[current_].get(), layout_.cells * sizeof(LogOdds));
    known_[current_] = {};
    return;
  }
  // Deferred: two shifts in a row do not compose (the first one clips), so a second one
  // flushes the first.
  shift_pending_ = true;
  pending_dx_ = dx;
  pending_dy_ = dy;
}

void OpenClBackend::FlushShift() {
  if (!shift_pending_) return;
  shift_pending_ = false;
  const cl_kernel kernel = shift_[current_].get();
  SetArg(kernel, 2, cl_int(pending_dx_));
  SetArg(kernel, 3, cl_int(pending_dy_));
  RowsLaunch(kernel, params_.height, nullptr);
  known_[1 - current_] = known_[current_].Shifted(pending_dy_, params_.height);
  current_ = 1 - current_;
  levels_valid_ = false;
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

void OpenClBackend::Fill(cl_mem buffer, std::size_t bytes) {
  const cl_uchar zero = 0;
  Check(clEnqueueFillBuffer(queue_.get(), buffer, &zero, 1, 0, bytes, 0, nullptr, nullptr),
        "clEnqueueFillBuffer");
}

void OpenClBackend::RowsLaunch(cl_kernel kernel, int rows, cl_event* event) {
  const std::size_t global[2] = {row_items_, RoundUp(std::size_t(rows), rows_local_[1])};
  Launch(kernel, 2, global, rows_local_, event);
}

void OpenClBackend::BitsLaunch(cl_kernel kernel, int rows, cl_event* event) {
  const std::size_t global[2] = {bit_items_, RoundUp(std::size_t(rows), bits_local_[1])};
  Launch(kernel, 2, global, bits_local_, event);
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
