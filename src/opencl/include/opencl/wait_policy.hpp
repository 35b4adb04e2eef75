// How the OpenCL backend waits for a scan's result (BackendConfig::opencl_wait), kept apart
// from OpenCL so that its choices can be tested on their own. With `auto`, spinning and
// blocking are timed separately: a spinning host takes a core that a CPU device's threads
// would use, so one way's waits say little about the other's, and a single mean of both swings
// between them where the spun waits are longer than the blocked ones.
#pragma once

#include "freespace/config.hpp"

namespace freespace {

class WaitPolicy {
 public:
  // One wait in this many goes the way that has been slower (auto), so that a change in the
  // map or the load shows.
  static constexpr unsigned kProbeEvery = 32;

  WaitPolicy(OpenClWait wait, double spin_us) : wait_(wait), spin_us_(spin_us) {}

  // The way to wait next: spin (true) or block. With auto, each way once first, then the way
  // whose recent waits were shorter, the other one for every kProbeEvery-th wait.
  bool Next();
  // How long the spin of the wait Next() chose may take before it blocks, microseconds: none
  // (< 0) unless auto, else opencl_spin_us or the blocked waits' mean if that is shorter, which
  // bounds what a probe can cost.
  double SpinLimitUs() const;
  // Records how long the wait Next() chose took, microseconds.
  void Record(double waited_us);

  // Running means (over about 8 waits; a probe counts for half) of the waits that spun and of
  // those that blocked; -1 while that way has not been timed.
  double spin_mean_us() const { return spin_mean_us_; }
  double block_mean_us() const { return block_mean_us_; }

 private:
  OpenClWait wait_;
  double spin_us_;
  double spin_mean_us_ = -1;
  double block_mean_us_ = -1;
  unsigned waits_ = 0;
  bool spin_ = false;   // the way Next() chose
  bool probe_ = false;  // and whether it was a probe
};

}  // namespace freespace
