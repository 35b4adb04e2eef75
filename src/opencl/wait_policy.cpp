// WaitPolicy: the OpenCL backend's choice between spinning and blocking (wait_policy.hpp).
#include "opencl/wait_policy.hpp"

#include <algorithm>

namespace freespace {

bool WaitPolicy::Next() {
  probe_ = false;
  if (wait_ != OpenClWait::kAuto) {
    spin_ = wait_ == OpenClWait::kSpin;
  } else if (spin_us_ <= 0) {
    spin_ = false;
  } else if (spin_mean_us_ < 0 || block_mean_us_ < 0) {
    spin_ = spin_mean_us_ < 0;
  } else {
    probe_ = ++waits_ % kProbeEvery == 0;
    spin_ = (spin_mean_us_ < block_mean_us_) != probe_;
  }
  return spin_;
}

double WaitPolicy::SpinLimitUs() const {
  if (wait_ != OpenClWait::kAuto) return -1;
  return block_mean_us_ < 0 ? spin_us_ : std::min(spin_us_, block_mean_us_);
}

void WaitPolicy::Record(double waited_us) {
  if (wait_ != OpenClWait::kAuto) return;
  double& mean = spin_ ? spin_mean_us_ : block_mean_us_;
  mean = mean < 0 ? waited_us : mean + (waited_us - mean) / (probe_ ? 2 : 8);
}

}  // namespace freespace
