// What the benchmarks add to the testing library (tests/support: real scans from ../shared/data,
// the engine state of a KITTI frame cut into a ScaLa-like 4-layer scan, backends with their
// crews, the project's configs): the backends to compare.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "core/backend.hpp"
#include "engine/backend_factory.hpp"
#include "freespace/freespace.hpp"
#include "support/backends.hpp"
#include "support/inputs.hpp"
#include "support/paths.hpp"

namespace freespace::bench {

// The testing library's inputs and backends (tests/support), shared with the tests.
using test::LoadProjectConfig;
using test::LoadScans;
using test::MakeBackend;
using test::MakeStageInput;
using test::StageInput;

// The backends the benchmarks compare, by their `backend` argument:
//   0  TBB;
//   1  OpenCL on the device the engine's rule takes, except that where PoCL lists its pthread
//      device (a worker pool) that one is taken;
//   2  OpenCL on PoCL's basic device (the kernels run on the thread that enqueues them); a case
//      says why it cannot run where PoCL does not list it;
//   3  as 2, split over two basic devices (opencl_devices: 2), where PoCL lists two.
// FREESPACE_OPENCL_PLATFORM / FREESPACE_OPENCL_DEVICE replace these filters, as in the engine.
BackendConfig BenchBackend(std::int64_t arg);

// The median of `v` (0 when empty).
double Median(std::vector<double> v);

// Per-iteration times of two setups timed in turn within one benchmark loop (BM_*Pair): the
// machine's speed, which on a shared VM moves by up to 50 % within minutes, then weighs on both
// alike. Publish() sets the counters `<a>` and `<b>` (medians, us) and `ratio` (b / a).
class PairedTimes {
 public:
  void Add(double a_us, double b_us) {
    a_.push_back(a_us);
    b_.push_back(b_us);
  }
  void Publish(benchmark::State& state, const char* a, const char* b,
               const char* ratio = "ratio") const;

 private:
  std::vector<double> a_, b_;
};

}  // namespace freespace::bench
