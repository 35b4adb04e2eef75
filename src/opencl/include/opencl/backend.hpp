// The OpenCL backend: every kernel stage as the kernels of kernels/*.cl, run on the device the
// config (or the environment) chooses. The map and every per-scan buffer stay resident on the
// device between scans; a scan uploads its raster (or ray) job and reads back only the stop
// cells of the border rays, from which the host builds C_Edge.
// Stages are enqueued without waiting; InSight() waits for its result (blocking or spinning, as
// BackendConfig::opencl_wait says), Finish() for everything.
// Bit-identical to the host backend (host/), which is its oracle in the tests.
// With BackendConfig::opencl_devices = n > 1 (CPU devices only) the row pass, classification and
// in-sight scan of each scan are split into parts over n devices of one context, device d
// driven by thread d of a Crew (the caller is thread 0); every other command runs on the first.
// Each stage's host side lives in the file with its kernel file's stem (src/opencl/rasterize.cpp
// for kernels/rasterize.cl, ...), beside the named argument indices of its kernels; backend.cpp
// builds and binds everything once, commands.cpp holds what every stage enqueues with.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/backend.hpp"
#include "core/crew.hpp"
#include "opencl/runtime.hpp"
#include "opencl/wait_policy.hpp"

namespace freespace {

class OpenClBackend final : public Backend {
 public:
  // How kernels over cells split the map: as suits the device (one work-item per row on a CPU,
  // about one per 16-cell vector, with work-groups per row in rasterize_rows, elsewhere), or one
  // of the two forced, so that the tests run the GPU shape on a CPU device too.
  enum class WorkShape { kDevice, kRowPerItem, kVectorPerItem };

  // Chooses the device (BackendConfig::opencl_platform / opencl_device, overridden by
  // FREESPACE_OPENCL_PLATFORM / FREESPACE_OPENCL_DEVICE), builds the kernels for `params` (or
  // takes them from the cache) and allocates every buffer. Throws BackendError.
  OpenClBackend(const KernelParams& params, const BackendConfig& config,
                WorkShape shape = WorkShape::kDevice);
  ~OpenClBackend() override;

  // "opencl: <device name>".
  std::string name() const override { return name_; }
  bool KernelsOnHostCores() const override { return cpu_device_; }
  CrewRequest WantedCrew() const override;
  void UseCrew(Crew* crew) override { crew_ = crew; }

  void Rasterize(const RasterJob& job) override;                            // rasterize.cl
  void Fuse(int row_begin, int row_end) override;                           // fuse.cl
  void CastRays(const RayJob& job) override;                                // rays.cl
  void FuseRays(int row_begin, int row_end) override;                       // rays.cl
  void Classify() override;                                                 // classify.cl
  void SetEchoes(const std::int32_t* cells, int count) override;            // mask.cl
  void Mask(const SensorCell& sensor, const MarginViews& views) override;   // mask.cl
  void InSightExact(const SensorCell& sensor, std::vector<RayStop>* stops,  // insight.cl
                    std::vector<CellIndex>* edges) override;
  void ReadMaskBits(int row_begin, int row_end, std::uint64_t* dst) override;
  void InSight(CellIndex vehicle, std::vector<CellIndex>* edges) override;  // insight.cl
  void Shift(int dx, int dy) override;                                      // shift.cl
  void Clear() override;
  void Finish() override;
  // The face layer's two bitsets (mask.cl).
  void SetFaces(const std::int32_t* near, int near_count, const std::int32_t* seen,
                int seen_count) override;

  void ReadLogOdds(LogOdds* dst) override;
  void WriteLogOdds(const LogOdds* src) override;
  void ReadUpdateMask(std::uint8_t* dst) override;
  void WriteUpdateMask(const std::uint8_t* src) override;
  void ReadFree(std::uint8_t* dst) override;
  void ReadRayDelta(std::int32_t* dst) override;
  void WriteFree(const std::uint8_t* src) override;

  // Device times from OpenCL event profiling, each from the start of a stage's first command to
  // the end of its last. rasterize_us: the job upload and rasterize_edges (GPU shape; the CPU
  // shape does the edges in the row pass), plus the row pass when it ran on its own; fuse_us:
  // the row pass of stage 1 with the fusion (and a deferred map shift) folded in, or fuse.
  // Conventional model: ray upload + rays_cast, and rays_fuse. classify_us: the classify
  // kernels (classify_levels included when it ran). insight_us: insight_cast (split:
  // insight_claim) and reading the stop cells back. Each measurement is reported once; stages
  // that did not run since the last call keep the caller's values.
  bool KernelTimes(StageTimes* times) const override;

  // The padded cell layout of the device buffers (kernels/common.cl): PAD_Y zero rows above
  // and below the map, PAD_X zero columns left of it, rows `stride` cells apart.
  struct Layout {
    int pad_x = 0;
    int pad_y = 0;
    int stride = 0;
    std::size_t cells = 0;  // stride * (height + 2 pad_y)
  };
  static Layout MakeLayout(const KernelParams& params);

  // The -D build options of the kernels (the program cache's key). `vectors_per_item`: 16-cell
  // vectors of a row per work-item; `raster_group`: work-group size of rasterize_rows; `bands`:
  // stage 1 as rasterize_bands (the CPU shape).
  static std::string BuildOptions(const KernelParams& params, int vectors_per_item,
                                  int raster_group, bool bands);

 private:
  enum Stage { kRasterStage, kFuseStage, kClassifyStage, kInSightStage, kMaskStage, kStageCount };

  std::size_t cells() const { return std::size_t(params_.width) * params_.height; }
  std::size_t labels() const {
    return std::size_t(BorderLabelCount(params_.height, params_.width));
  }
  int BitWords() const { return (params_.width + 63) / 64; }  // bitset words per row

  // The steps of construction (backend.cpp), in the constructor's order. ChooseWorkShape() sets
  // bands_, vectors_per_item_, row_items_ and raster_group_ and returns the device's work-group
  // limits, which ChooseWorkSizes() needs once the kernels exist.
  struct DeviceLimits {
    std::size_t max_group = 1;             // CL_DEVICE_MAX_WORK_GROUP_SIZE
    std::size_t max_items[3] = {1, 1, 1};  // CL_DEVICE_MAX_WORK_ITEM_SIZES
  };
  DeviceLimits ChooseWorkShape(WorkShape shape);
  void BuildKernels();
  void MakeLanes();  // the split over devices: a queue and the kernels' copies per device
  void AllocateBuffers();
  // The buffer arguments, set once (the job buffer's whenever it grows: Bind*Job()), in the file
  // of each stage beside the kernel's named argument indices.
  void BindRasterizeArgs();  // rasterize.cpp
  void BindRasterizeJob();   // rasterize.cpp
  void BindFuseArgs();       // fuse.cpp
  void BindClassifyArgs();   // classify.cpp
  void BindInSightArgs();    // insight.cpp
  void BindShiftArgs();      // shift.cpp
  void BindRaysArgs();       // rays.cpp
  void BindRaysJob();        // rays.cpp
  void SetUpMask();          // mask.cpp: stage 3b's and the exact rays' kernels and buffers
  // A per-scan bitset of cells the host builds from a list and uploads (mask.cpp).
  struct CellLayer {
    opencl::Mem bits;                 // bitset rows on the device
    std::vector<std::uint64_t> host;  // their staging
    std::vector<std::int32_t> cells;  // the cells set, to clear them for the next scan
    RowSpan rows;                     // the rows of `host` with a set bit
    opencl::Event upload;             // the last upload from `host`
  };
  // Replaces the layer's cells with `cells` and uploads the rows that changed.
  void UploadCells(CellLayer* layer, const std::int32_t* cells, int count);
  // Enqueues the veto (this scan's echoes out of the free mask) on rows `rows`; its event
  // becomes `*end` (mask.cpp).
  void VetoEchoes(RowSpan rows, opencl::Event* end);
  void ChooseWorkSizes(const DeviceLimits& limits);
  opencl::Kernel MakeKernel(const char* name) const;
  std::size_t LocalSize(cl_kernel kernel, std::size_t preferred) const;
  void GrowJob(std::size_t ints);

  // Commands (commands.cpp).
  void Launch(cl_kernel kernel, cl_uint dims, const std::size_t* global, const std::size_t* local,
              cl_event* event);
  void Launch(cl_command_queue queue, cl_kernel kernel, cl_uint dims, const std::size_t* global,
              const std::size_t* local, cl_event* event);
  // The staging area for an upload of `ints` ints, once the previous upload is done with it.
  std::int32_t* Staging(std::size_t ints);
  // Writes the first `ints` ints of the staging area into the job buffer, not blocking; the
  // write's event becomes `*event` (and upload_done_).
  void Upload(std::size_t ints, opencl::Event* event);
  void Fill(cl_mem buffer, std::size_t bytes);
  // Copies the map's cells of a padded buffer of `element`-byte cells to or from host memory
  // (width * height elements, row-major).
  void ReadCells(cl_mem buffer, std::size_t element, void* dst);
  void WriteCells(cl_mem buffer, std::size_t element, const void* src);
  // Global and local sizes of a kernel over `rows` rows of 16-cell vectors, or of bitset words.
  void RowsLaunch(cl_kernel kernel, int rows, cl_event* event);
  void BitsLaunch(cl_kernel kernel, int rows, cl_event* event);
  // Also hands the stage the events in split_parts_ (a split's parts; their span counts too),
  // leaving split_parts_ empty.
  void SetStage(Stage stage, opencl::Event begin, opencl::Event end);
  // Waits for `event`, the last command of a scan, as BackendConfig::opencl_wait says.
  void WaitForResult(cl_event event);
  // Enqueues the deferred shift and row pass on their own.
  void Flush();

  // Split over devices (backend_internal.hpp, commands.cpp): sets an argument of `kernel` and of
  // its copies for the other devices.
  template <typename T>
  void SetArgAll(cl_kernel kernel, cl_uint index, const T& value);
  // The copy of `kernel` (a kernel of device 0 that splits) for device d.
  cl_kernel Twin(cl_kernel kernel, int d) const;
  // Runs `parts` parts on the crew once device 0's queue is done: enqueue(part, d, &event)
  // enqueues one part on device d's queue (the thread's own), which is then finished. The
  // parts' events, in part order, go to split_parts_ (SetStage() hands them to the stage).
  template <typename Enqueue>
  void SplitRun(int parts, const Enqueue& enqueue);
  cl_command_queue QueueOf(int d) const {
    return d == 0 ? queue_.get() : lanes_[d - 1].queue.get();
  }

  // The row pass of stage 1 (rasterize.cpp). RowPass() enqueues a row-pass kernel over rows
  // [first, end) with a map shift of (dx, dy); split over devices, `*event` is the first part's
  // (and split_parts_ holds every part's). FlushRows() runs the deferred row pass on its own,
  // FlushRowsWithFusion() with the fusion of its rows (and the deferred shift) folded in.
  void RowPass(cl_kernel kernel, int dx, int dy, int first, int end, cl_event* event);
  void FlushRows();
  void FlushRowsWithFusion();
  void FlushShift();  // shift.cpp
  // strong_ / weak_ [current_] were just computed from the whole map (classify.cpp).
  void LevelsWritten();

  std::shared_ptr<opencl::DeviceContext> device_;
  std::string name_;
  opencl::Queue queue_;
  cl_program program_ = nullptr;  // owned by device_'s cache
  Layout layout_;
  int vectors_per_item_ = 1;
  int raster_group_ = 1;
  bool bands_ = false;       // stage 1 as rasterize_bands (the CPU shape)
  bool cpu_device_ = false;  // CL_DEVICE_TYPE_CPU
  std::size_t compute_units_ = 1;
  WaitPolicy wait_;  // BackendConfig::opencl_wait, opencl_spin_us

  // Device buffers, per-cell ones in the padded layout. The map lives in map_[current_]; the
  // shift writes the other one and flips current_. Kernels that touch the map exist once per
  // buffer, so no argument is re-set.
  opencl::Mem map_[2];
  int current_ = 0;
  opencl::Mem update_;            // stage 1 -> stage 2, uchar per cell
  opencl::Mem toggles_;           // stage 1 bit planes, one bit per cell, rows of whole words
  opencl::Mem occupied_;          //
  opencl::Mem strong_[2];         // level bitsets of map_[k], stage 1 or 3 -> stage 3
  opencl::Mem weak_[2];           //
  opencl::Mem bits_a_;            // stage 3 intermediates (GPU shape), bitsets (common.cl)
  opencl::Mem bits_b_;            //
  opencl::Mem bits_c_;            //
  opencl::Mem free_;              // stage 3 output, stage 4 input: bitset
  opencl::Mem band_rows_;         // classify_bands: the rows each band keeps (classify.cl)
  opencl::Mem stop_;              // stage 4 output: stop cell per label
  opencl::Mem claims_;            // insight_claim's counter of the chunks claimed, one int
  opencl::Mem delta_;             // conventional model: per-cell sum of one scan's rays
  opencl::Mem job_;               // the raster or ray job (rasterize.cl, rays.cl)
  std::size_t job_capacity_ = 0;  // ints

  opencl::Kernel rasterize_edges_, insight_cast_, insight_claim_, rays_cast_;
  opencl::Kernel erode_dilate_, dilate_cols_;
  std::array<opencl::Kernel, 2> fuse_, rays_fuse_, levels_, shift_, hysteresis_,
      classify_bands_;  // per map buffer
  // The row pass of stage 1 (rasterize_rows, or rasterize_bands on a CPU): the mask only, and
  // per map buffer k with the fusion, [k][0] in place on map_[k], [k][1] shifting map_[k] into
  // map_[1 - k] on the way (and the level bitsets of map_[k] into those of map_[1 - k]).
  opencl::Kernel row_mask_;
  std::array<std::array<opencl::Kernel, 2>, 2> row_fuse_;

  // Deferred work. Shift() records the shift, Rasterize() enqueues the upload and
  // rasterize_edges and records the row pass; the Fuse() of the same rows then does the row
  // pass, the shift and the fusion in one pass over the map (rasterize_rows_fuse). Any other
  // call first runs what is pending on its own (Flush()), so results never depend on it.
  bool shift_pending_ = false;
  int pending_dx_ = 0, pending_dy_ = 0;
  bool rows_pending_ = false;
  int pending_begin_ = 0, pending_end_ = 0;
  // True while strong_ / weak_ [current_] hold the level bits of the map: the row pass that
  // fuses writes them for the rows it writes, so Classify() needs no pass over the map of its
  // own unless the map changed some other way (a shift or fusion on its own, a fill, a write).
  // The row pass that shifts then shifts the level bits of the rows it does not fuse instead of
  // recomputing them from the map, which is exact when an unknown cell (0, what a shift brings
  // in) is on no level: unknown_off_levels_.
  bool levels_valid_ = false;
  bool unknown_off_levels_ = false;
  // Every row of map_[k] with a non-zero cell lies in known_[k], and every row of strong_[k] /
  // weak_[k] with a set bit in level_rows_[k]. With unknown_off_levels_ the row pass that
  // shifts runs over the rows that can differ from unknown only (RowSpan, core/backend.hpp).
  RowSpan known_[2];
  RowSpan level_rows_[2];
  // Every row of free_ with a set bit.
  RowSpan free_rows_;

  // Work sizes, fixed at construction.
  std::size_t row_items_ = 1;                     // work-items per row of kernels over cells
  std::size_t rows_local_[2] = {1, 1};            // their work-group
  std::size_t bit_items_ = 1;                     // work-items per row of bitset kernels
  std::size_t bits_local_[2] = {1, 1};            // their work-group
  std::size_t raster_local_[2] = {1, 1};          // rasterize_rows
  std::size_t edge_local_ = 1;                    // rasterize_edges, rays_cast
  std::size_t cast_local_ = 1, cast_global_ = 1;  // insight_cast

  // Split over devices: devices 1 .. n - 1, each with its queue and its copies of the kernels
  // that split (Twin()), and the threads that drive them.
  struct Lane {
    opencl::Queue queue;
    std::vector<std::pair<cl_kernel, opencl::Kernel>> twins;  // device 0's kernel -> copy
  };
  std::vector<Lane> lanes_;
  Crew* crew_ = nullptr;  // the estimator's (UseCrew); none: the caller runs every part
  int devices_ = 1;
  std::vector<opencl::Event> split_parts_;  // the last split's events (room for devices_)

  std::vector<std::int32_t> job_host_;    // staging of the job upload
  std::vector<std::int32_t> stop_host_;   // stage 4: stop cells as read back
  std::vector<std::uint64_t> edge_seen_;  // stage 4: stop cells already in C_Edge (bitset)
  std::vector<std::uint64_t> free_host_;  // the free mask for ReadFree() / WriteFree()
  std::vector<std::int32_t> row_counts_;  // counting sort of the occupied cells by row
  opencl::Event upload_done_;             // the last upload from job_host_

  // Stage 3b and the exact rays (mask.cpp, kernels/mask.cl, insight_exact in insight.cl).
  opencl::Kernel mask_veto_, mask_unconfirmed_, mask_rows_, insight_exact_;
  CellLayer echo_;                // this scan's echo cells (SetEchoes)
  CellLayer face_near_;           // the face layer (SetFaces): near a face
  CellLayer face_seen_;           // and touched by the outline
  opencl::Mem unconfirmed_bits_;  // the margin's sources: the map's log-odds >= 0, bitset rows
  opencl::Mem mask_;              // the polygon mask, bitset rows
  opencl::Mem exact_stops_;       // the exact rays' stops, 3 ints a label
  RowSpan mask_span_;             // the rows of mask_ with a set bit
  std::vector<std::int32_t> exact_host_;  // the stops as read back
  std::size_t exact_local_ = 1, exact_global_ = 1;
  std::size_t row_local_ = 1;  // the work-group of the kernels with a work-item per row

  mutable std::array<opencl::Event, kStageCount> begin_, end_;
  mutable std::array<std::vector<opencl::Event>, kStageCount> more_;
};

}  // namespace freespace
