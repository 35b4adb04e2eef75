// OpenClBackend's construction: buffers, kernels and work sizes set up once, so that a scan only
// enqueues (plus the job upload and the stop-cell read-back). Kernel arguments that are buffers
// are set here, each stage's in its own file (Bind*Args()), and again only when the job buffer
// grows; per call only scalars change. The stages themselves live in the files with the kernels'
// stems (rasterize.cpp, fuse.cpp, classify.cpp, insight.cpp, shift.cpp, rays.cpp), what they
// enqueue with in commands.cpp.
#include "opencl/backend.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <sstream>

#include "backend_internal.hpp"
#include "freespace/errors.hpp"

namespace freespace {
namespace {

using opencl::Check;
using opencl::RoundUp;

// Work-group sizes. Kernels over cells run one work-item per row on a CPU (it loops over the
// row's 16-cell vectors) and about one per vector elsewhere.
constexpr std::size_t kCpuRowsPerGroup = 4;
constexpr std::size_t kGpuGroup = 64;
constexpr std::size_t kGpuRowGroup = 256;  // at most this many work-items for one row
constexpr std::size_t kEdgeGroup = 16;     // rasterize_edges, rays_cast: uneven loop lengths
constexpr std::size_t kCastGroup = 16;     // insight_cast
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
  // -w: a compiler's warnings are not the library's to print, and PoCL prints them on stderr
  // (on CPUs without AVX-512, clang warns that int16 arguments change the ABI of its own
  // builtins). Errors still fail the build with the compiler's log.
  o << "-cl-std=CL1.2 -w -DWIDTH=" << p.width << " -DHEIGHT=" << p.height
    << " -DPAD_X=" << layout.pad_x << " -DPAD_Y=" << layout.pad_y << " -DSTRIDE=" << layout.stride
    << " -DVECTORS_PER_ITEM=" << vectors_per_item << " -DL_FREE=(" << p.l_free << ") -DL_OCCUPIED=("
    << p.l_occupied << ") -DL_MIN=(" << p.l_min << ") -DL_MAX=(" << p.l_max << ") -DT_LOW=("
    << p.t_low << ") -DT_HIGH=(" << p.t_high << ") -DOPENING_RADIUS=" << p.opening_radius
    << " -DFIXED_BITS=" << kFixedBits << " -DUPDATE_NONE=" << int(kUpdateNone)
    << " -DUPDATE_FREE=" << int(kUpdateFree) << " -DUPDATE_OCCUPIED=" << int(kUpdateOccupied)
    << " -DRASTER_GROUP=" << raster_group << " -DRASTER_SERIAL=" << (bands ? 1 : 0)
    << " -DMARGIN_CELLS=" << p.margin_cells << " -DCONE_COS=(" << p.cone_cos << ") -DCONE_SIN=("
    << p.cone_sin << ") -DMARGIN_ALL=" << (p.margin_all ? 1 : 0);
  // The opening's disk (classify.cl): its distinct row half-widths as bits, and each |dy|'s.
  const OpeningRows opening = MakeOpeningRows(p.opening_radius);
  std::uint64_t stops[2] = {0, 0};
  for (const int w : opening.widths) stops[w / 64] |= std::uint64_t{1} << (w % 64);
  std::string index;
  for (const int i : opening.index) index += (index.empty() ? "" : ",") + std::to_string(i);
  o << " -DOPENING_KINDS=" << opening.widths.size() << " -DOPENING_STOPS_LO=" << stops[0]
    << "UL -DOPENING_STOPS_HI=" << stops[1] << "UL -DOPENING_INDEX=" << index;
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
  if (params.width < 1 || params.height < 1 || params.opening_radius < 0) {
    throw BackendError("backend opencl: bad map size " + std::to_string(params.width) + " x " +
                       std::to_string(params.height));
  }
  cl_int status = CL_SUCCESS;
  queue_.reset(clCreateCommandQueue(device_->context(), device_->device(),
                                    CL_QUEUE_PROFILING_ENABLE, &status));
  Check(status, "clCreateCommandQueue");
  const DeviceLimits limits = ChooseWorkShape(shape);
  layout_ = MakeLayout(params);
  BuildKernels();
  MakeLanes();
  AllocateBuffers();
  unknown_off_levels_ = params.t_high < 0;
  // The buffer arguments, set once (the job buffer's in GrowJob()).
  BindRasterizeArgs();
  BindFuseArgs();
  BindRaysArgs();
  BindClassifyArgs();
  BindInSightArgs();
  BindShiftArgs();
  ChooseWorkSizes(limits);
  SetUpMask();
  Finish();
}

OpenClBackend::DeviceLimits OpenClBackend::ChooseWorkShape(WorkShape shape) {
  const cl_device_id device = device_->device();
  DeviceLimits limits;
  cl_device_type type = 0;
  Check(clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof limits.max_group,
                        &limits.max_group, nullptr),
        "clGetDeviceInfo");
  Check(clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_ITEM_SIZES, sizeof limits.max_items,
                        limits.max_items, nullptr),
        "clGetDeviceInfo");
  Check(clGetDeviceInfo(device, CL_DEVICE_TYPE, sizeof type, &type, nullptr), "clGetDeviceInfo");
  cl_uint units = 1;
  Check(clGetDeviceInfo(device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, nullptr),
        "clGetDeviceInfo");
  compute_units_ = std::max<cl_uint>(units, 1);
  cpu_device_ = (type & CL_DEVICE_TYPE_CPU) != 0;
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
  const std::size_t row_vectors = RoundUp(std::size_t(params_.width), 16) / 16;
  const std::size_t row_cap = std::min({kGpuRowGroup, limits.max_group, limits.max_items[0]});
  vectors_per_item_ = cpu ? int(row_vectors) : int((row_vectors + row_cap - 1) / row_cap);
  row_items_ = (row_vectors + vectors_per_item_ - 1) / vectors_per_item_;
  const std::size_t words = (std::size_t(params_.width) + 31) / 32;
  const std::size_t raster_cap = std::min({kMaxRasterGroup, limits.max_group, limits.max_items[0]});
  while (!cpu && std::size_t(raster_group_) < words &&
         std::size_t(raster_group_) * 2 <= raster_cap) {
    raster_group_ *= 2;
  }
  return limits;
}

void OpenClBackend::BuildKernels() {
  program_ =
      device_->EmbeddedProgram(BuildOptions(params_, vectors_per_item_, raster_group_, bands_));
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
}

void OpenClBackend::MakeLanes() {
  // A queue and copies of the kernels that split for every device but the first (kernel
  // objects are not shared between threads).
  for (int d = 1; d < devices_; ++d) {
    Lane& lane = lanes_.emplace_back();
    cl_int status = CL_SUCCESS;
    lane.queue.reset(clCreateCommandQueue(device_->context(), device_->devices()[std::size_t(d)],
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
}

void OpenClBackend::AllocateBuffers() {
  auto buffer = [&](std::size_t bytes) {
    cl_int status = CL_SUCCESS;
    opencl::Mem mem(clCreateBuffer(device_->context(), CL_MEM_READ_WRITE,
                                   std::max<std::size_t>(bytes, 4), nullptr, &status));
    Check(status, "clCreateBuffer");
    return mem;
  };
  const std::size_t height = std::size_t(params_.height);
  const std::size_t padded = layout_.cells;
  const std::size_t bit_words = (std::size_t(params_.width) + 31) / 32 * height;  // bit planes
  const std::size_t mask_bytes = std::size_t(BitWords()) * height * 8;
  for (opencl::Mem& map : map_) map = buffer(padded * sizeof(LogOdds));
  update_ = buffer(padded);
  toggles_ = buffer(bit_words * 4);
  occupied_ = buffer(2 * bit_words * 4);  // the occupied plane, then the outline plane
  const std::size_t level_bytes = std::size_t(2 * BitWords()) * height * 4;
  for (int k = 0; k < 2; ++k) {
    strong_[k] = buffer(level_bytes);
    weak_[k] = buffer(level_bytes);
  }
  // The three-kernel stage 3's intermediates; classify_bands (the CPU shape) keeps its rows in
  // band_rows_ instead.
  // b and c hold a plane per distinct row half-width of the opening's element.
  const std::size_t kinds = MakeOpeningRows(params_.opening_radius).widths.size();
  const std::size_t between_bytes = bands_ ? 8 : mask_bytes;
  const std::size_t planes_bytes = bands_ ? 8 : kinds * mask_bytes;
  bits_a_ = buffer(between_bytes);
  bits_b_ = buffer(planes_bytes);
  bits_c_ = buffer(planes_bytes);
  free_ = buffer(mask_bytes);
  // classify_bands: at most kClassifyBandsPerUnit bands of whole rows per compute unit, each
  // CLASSIFY_BAND_ROWS (classify.cl) bitset rows of scratch, in the CPU shape only.
  const std::size_t classify_bands =
      std::max<std::size_t>(opencl::kClassifyBandsPerUnit * compute_units_, std::size_t(devices_));
  const std::size_t band_rows = 2 * std::size_t(2 * params_.opening_radius + 1) * kinds + 1;
  band_rows_ = buffer(bands_ ? classify_bands * band_rows * std::size_t(BitWords()) * 8 : 8);
  stop_ = buffer(labels() * 4);
  claims_ = buffer(4);
  delta_ = buffer(padded * 4);
  GrowJob(kInitialJobInts);
  stop_host_.assign(labels(), 0);
  edge_seen_.assign((cells() + 63) / 64, 0);
  free_host_.assign(mask_bytes / 8, 0);
  row_counts_.assign(height + 1, 0);

  // Initial contents: every cell buffer zero (the map unknown, the padding zero for good), the
  // bit planes and masks zero.
  for (opencl::Mem& map : map_) Fill(map.get(), padded * sizeof(LogOdds));
  Fill(update_.get(), padded);
  Fill(toggles_.get(), bit_words * 4);
  Fill(occupied_.get(), 2 * bit_words * 4);
  for (int k = 0; k < 2; ++k) {
    Fill(strong_[k].get(), level_bytes);
    Fill(weak_[k].get(), level_bytes);
  }
  Fill(bits_a_.get(), between_bytes);
  Fill(bits_b_.get(), planes_bytes);
  Fill(bits_c_.get(), planes_bytes);
  Fill(free_.get(), mask_bytes);
  Fill(delta_.get(), padded * 4);
}

void OpenClBackend::ChooseWorkSizes(const DeviceLimits& limits) {
  // Global sizes are rounded up to whole work-groups; the kernels skip the extra work-items, so
  // no size has to divide the map.
  const std::size_t max_group = limits.max_group;
  std::size_t most = max_group;
  for (const cl_kernel k : {erode_dilate_.get(), dilate_cols_.get(), hysteresis_[0].get(),
                            shift_[0].get(), fuse_[0].get(), rays_fuse_[0].get()}) {
    most = std::min(most, LocalSize(k, max_group));
  }
  if (row_items_ > most) {
    throw BackendError("backend opencl: a row of " + std::to_string(params_.width) +
                       " cells needs work-groups of " + std::to_string(row_items_) +
                       " work-items; the kernels allow " + std::to_string(most));
  }
  const bool cpu = bands_;
  rows_local_[0] = row_items_;
  rows_local_[1] =
      std::max<std::size_t>(1, std::min({cpu ? kCpuRowsPerGroup : kGpuGroup / row_items_,
                                         most / row_items_, limits.max_items[1]}));
  // Bitset kernels: words of 64 cells, BIT_WORDS_PER_ITEM of them per work-item (common.cl).
  const std::size_t words_per_item = (std::size_t(vectors_per_item_) + 3) / 4;
  bit_items_ = (std::size_t(BitWords()) + words_per_item - 1) / words_per_item;
  bits_local_[0] = bit_items_;
  bits_local_[1] =
      std::max<std::size_t>(1, std::min({cpu ? kCpuRowsPerGroup : kGpuGroup / bit_items_,
                                         most / bit_items_, limits.max_items[1]}));
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
  cast_global_ = RoundUp(labels(), cast_local_);
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
  BindRasterizeJob();
  BindRaysJob();
}

}  // namespace freespace
