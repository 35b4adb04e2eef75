// WaitPolicy: how the OpenCL backend waits for a scan's result. The waits are made up here, so
// the choices are checked without a device or a clock.
#include "opencl/wait_policy.hpp"

#include <gtest/gtest.h>

namespace freespace {
namespace {

// Runs `waits` waits of a device whose waits take spin_us spinning and block_us blocking;
// returns how many spun.
int Drive(WaitPolicy* policy, int waits, double spin_us, double block_us) {
  int spins = 0;
  for (int i = 0; i < waits; ++i) {
    const bool spin = policy->Next();
    spins += spin;
    policy->Record(spin ? spin_us : block_us);
  }
  return spins;
}

TEST(WaitPolicy, BlockAndSpinAlwaysWaitTheirWayWithoutALimit) {
  for (const OpenClWait wait : {OpenClWait::kBlock, OpenClWait::kSpin}) {
    WaitPolicy policy(wait, 250);
    const int spins = Drive(&policy, 100, 10, 1000);
    EXPECT_EQ(spins, wait == OpenClWait::kSpin ? 100 : 0);
    EXPECT_LT(policy.SpinLimitUs(), 0);
    EXPECT_LT(policy.spin_mean_us(), 0);  // nothing recorded
    EXPECT_LT(policy.block_mean_us(), 0);
  }
}

TEST(WaitPolicy, AutoTriesEachWayOnceThenTakesTheFasterOne) {
  WaitPolicy policy(OpenClWait::kAuto, 250);
  EXPECT_TRUE(policy.Next());
  EXPECT_DOUBLE_EQ(policy.SpinLimitUs(), 250);  // nothing blocked yet
  policy.Record(100);
  EXPECT_FALSE(policy.Next());
  policy.Record(130);
  EXPECT_DOUBLE_EQ(policy.spin_mean_us(), 100);
  EXPECT_DOUBLE_EQ(policy.block_mean_us(), 130);
  // Spinning is faster: every wait spins but each 32nd, which blocks.
  for (unsigned i = 1; i <= 4 * WaitPolicy::kProbeEvery; ++i) {
    const bool spin = policy.Next();
    EXPECT_EQ(spin, i % WaitPolicy::kProbeEvery != 0) << "wait " << i;
    EXPECT_DOUBLE_EQ(policy.SpinLimitUs(), 130);  // a spin gives up at the blocked mean
    policy.Record(spin ? 100 : 130);
  }
}

// Where spinning slows the device (a CPU device's threads lose a core to the spinning host),
// a spun wait can be longer than a blocked one even though the blocked ones are under
// opencl_spin_us: auto blocks and spins only for its probes.
TEST(WaitPolicy, AutoBlocksWhereSpinningSlowsTheDevice) {
  WaitPolicy policy(OpenClWait::kAuto, 250);
  const int waits = 32 * int(WaitPolicy::kProbeEvery);
  const int spins = Drive(&policy, waits, 383, 225);
  EXPECT_LE(spins, 1 + waits / int(WaitPolicy::kProbeEvery));
  EXPECT_DOUBLE_EQ(policy.SpinLimitUs(), 225);
}

TEST(WaitPolicy, AutoFollowsAChangeThroughItsProbes) {
  WaitPolicy policy(OpenClWait::kAuto, 250);
  Drive(&policy, 200, 100, 130);
  ASSERT_TRUE(policy.Next());
  policy.Record(100);
  // Blocking becomes the faster way (say the map grew): within a few probes auto blocks.
  Drive(&policy, 4 * WaitPolicy::kProbeEvery, 100, 40);
  EXPECT_LT(policy.block_mean_us(), policy.spin_mean_us());
  EXPECT_LE(Drive(&policy, 10 * WaitPolicy::kProbeEvery, 100, 40), 10);
  // And back.
  Drive(&policy, 4 * WaitPolicy::kProbeEvery, 20, 40);
  EXPECT_GE(Drive(&policy, 10 * WaitPolicy::kProbeEvery, 20, 40),
            int(10 * WaitPolicy::kProbeEvery) - 10);
}

TEST(WaitPolicy, AutoWithNoSpinTimeNeverSpins) {
  WaitPolicy policy(OpenClWait::kAuto, 0);
  EXPECT_EQ(Drive(&policy, 100, 1, 1000), 0);
}

}  // namespace
}  // namespace freespace
