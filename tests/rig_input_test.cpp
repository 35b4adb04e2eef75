// A rig's odd cycles (docs/behaviour.md): a sensor that adds nothing or sends no scan, a scan
// at or before the latest accepted time, a bad scan named by its sensor; and the clock that
// stays behind after one scan stamped far ahead, for one sensor and for a rig.
#include <algorithm>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace freespace {
namespace {

using test::TwoAlike;
using test::Wall;

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(RigInput, ASensorThatAddsNothingIsListedAndNamed) {
  Estimator rig(TwoAlike());
  Scan empty = Wall(0.0, {0, 0, 0}, 1, 12.0);
  empty.points.clear();
  const Result& r = rig.ProcessCycle(std::vector<Scan>{Wall(0.0, {0, 0, 0}, 0, 12.0), empty});
  ASSERT_EQ(r.status, ScanStatus::kOk) << r.message;  // sensor a updated the map
  EXPECT_EQ(r.cycle_silent_sensors, std::vector<int>{1});
  EXPECT_TRUE(Has(r.message, "sensor 1 (b): empty scan")) << r.message;

  Scan no_echo = Wall(0.04, {0, 0, 0}, 0, 12.0);
  for (ScanPoint& p : no_echo.points) p.range_m = 1e9f;  // beyond max_range_m: no echo
  const Result& r2 = rig.ProcessCycle(std::vector<Scan>{no_echo, Wall(0.04, {0, 0, 0}, 1, 12.0)});
  ASSERT_EQ(r2.status, ScanStatus::kOk) << r2.message;
  EXPECT_EQ(r2.cycle_silent_sensors, std::vector<int>{0});
  EXPECT_TRUE(Has(r2.message, "sensor 0 (a): no usable echo")) << r2.message;

  const Result& r3 = rig.ProcessCycle(std::vector<Scan>{Wall(0.08, {0, 0, 0}, 1, 12.0)});
  ASSERT_EQ(r3.status, ScanStatus::kOk) << r3.message;
  EXPECT_EQ(r3.cycle_silent_sensors, std::vector<int>{0});
  EXPECT_TRUE(Has(r3.message, "sensor 0 (a): no scan in this cycle")) << r3.message;

  const Result& whole = rig.ProcessCycle(
      std::vector<Scan>{Wall(0.12, {0, 0, 0}, 0, 12.0), Wall(0.12, {0, 0, 0}, 1, 12.0)});
  EXPECT_TRUE(whole.cycle_silent_sensors.empty());
  EXPECT_FALSE(Has(whole.message, "sensor 0 (") || Has(whole.message, "sensor 1 ("))
      << whole.message;

  // A rejected cycle lists nothing, though its scans were preprocessed before the alignment
  // rejected it (a pose jump): the list is an accepted cycle's.
  empty.timestamp_s = 0.16;
  empty.pose = {500, 0, 0};
  const Result& rejected =
      rig.ProcessCycle(std::vector<Scan>{empty, Wall(0.16, {500, 0, 0}, 0, 12.0)});
  EXPECT_EQ(rejected.reject_reason, RejectReason::kPoseJump);
  EXPECT_TRUE(rejected.cycle_silent_sensors.empty());
}

TEST(RigInput, AScanRejectedForItsInputNamesItsSensor) {
  Estimator rig(TwoAlike());
  const Result& r = rig.ProcessCycle(
      std::vector<Scan>{Wall(0.0, {0, 0, 0}, 0, 12.0), Wall(NAN, {0, 0, 0}, 1, 12.0)});
  EXPECT_EQ(r.reject_reason, RejectReason::kTimestampNotFinite);
  EXPECT_TRUE(Has(r.message, "the scan of sensor 1 (b): timestamp nan")) << r.message;
}

// A scan of the cycle other than its newest at or before the latest accepted time, within
// alignment.time_jitter_s, is used and reported as clock jitter, as Process() reports it.
TEST(RigInput, AnEarlierScanWithinTheJitterIsReported) {
  Estimator rig(TwoAlike());
  ASSERT_EQ(rig.ProcessCycle(std::vector<Scan>{Wall(10.0, {0, 0, 0}, 0, 12.0),
                                               Wall(10.01, {0, 0, 0}, 1, 12.0)})
                .status,
            ScanStatus::kOk);
  const Result& r = rig.ProcessCycle(
      std::vector<Scan>{Wall(9.5, {0.5, 0, 0}, 0, 11.0), Wall(10.1, {0.5, 0, 0}, 1, 11.0)});
  ASSERT_EQ(r.status, ScanStatus::kOk) << r.message;
  EXPECT_TRUE(r.timestamp_jitter);
  EXPECT_TRUE(Has(r.message, "sensor 0 (a) at 9.500000 s is not after")) << r.message;
  const Result& next = rig.ProcessCycle(
      std::vector<Scan>{Wall(10.14, {0.6, 0, 0}, 0, 11.0), Wall(10.15, {0.6, 0, 0}, 1, 11.0)});
  EXPECT_FALSE(next.timestamp_jitter) << next.message;
}

// One scan stamped 1e6 s ahead is taken (a long pause is no error); the scans after it are
// behind the clock. After alignment.reset_after_jumps of them in a row, each later than the one
// before, the map restarts at the last one rather than rejecting the rest of the log.
TEST(ClockBehind, TheMapRestartsAfterScansInARowBehindTheClock) {
  Config config;
  config.alignment.reset_after_jumps = 3;
  Estimator estimator(config);
  const Pose2D pose{0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(estimator.Process(Wall(0.04 * k, pose, 0, 12.0)).status, ScanStatus::kOk);
  }
  ASSERT_EQ(estimator.Process(Wall(1e6, pose, 0, 12.0)).status, ScanStatus::kOk);
  for (int k = 0; k < 2; ++k) {
    const Result& r = estimator.Process(Wall(0.2 + 0.04 * k, pose, 0, 12.0));
    EXPECT_EQ(r.reject_reason, RejectReason::kTimestampNotIncreasing);
    EXPECT_TRUE(Has(r.message, std::to_string(k + 1) + " in a row behind")) << r.message;
  }
  const Result& r = estimator.Process(Wall(0.28, pose, 0, 12.0));
  ASSERT_EQ(r.status, ScanStatus::kOk) << r.message;
  EXPECT_TRUE(r.map_reset);
  EXPECT_TRUE(Has(r.message, "the clock stayed behind")) << r.message;
  EXPECT_EQ(estimator.Process(Wall(0.32, pose, 0, 12.0)).status, ScanStatus::kOk);
}

// A scan stamped 1.3 s ahead: the clock catches up (to within alignment.time_jitter_s) sooner
// than the scans have been behind by the time reset_after_jumps of them are: the map is kept.
TEST(ClockBehind, AShortGlitchIsWaitedOutAndTheMapKept) {
  Estimator estimator{Config{}};
  const Pose2D pose{0, 0, 0};
  for (int k = 0; k < 4; ++k) estimator.Process(Wall(0.04 * k, pose, 0, 12.0));
  ASSERT_EQ(estimator.Process(Wall(1.42, pose, 0, 12.0)).status, ScanStatus::kOk);
  int rejected = 0;
  for (int k = 4; k < 20; ++k) {
    const Result& r = estimator.Process(Wall(0.04 * k, pose, 0, 12.0));
    EXPECT_FALSE(r.map_reset) << k;
    rejected += r.status == ScanStatus::kRejected;
  }
  EXPECT_EQ(rejected, 7);  // 0.16 .. 0.40 s, more than 1 s behind 1.42 s
}

// Scans behind the clock that are not in order among themselves (a stale frame now and then)
// never add up to a restart.
TEST(ClockBehind, StaleScansOutOfOrderNeverRestartTheMap) {
  Config config;
  config.alignment.reset_after_jumps = 3;
  Estimator estimator(config);
  const Pose2D pose{0, 0, 0};
  ASSERT_EQ(estimator.Process(Wall(10.0, pose, 0, 12.0)).status, ScanStatus::kOk);
  for (const double t : {5.0, 4.0, 5.0, 3.0, 4.0, 2.0}) {
    const Result& r = estimator.Process(Wall(t, pose, 0, 12.0));
    EXPECT_EQ(r.reject_reason, RejectReason::kTimestampNotIncreasing) << t;
  }
  // An accepted scan between two behind ones starts the count again.
  for (const double t : {5.0, 10.04, 5.1, 5.2}) {
    const Result& r = estimator.Process(Wall(t, pose, 0, 12.0));
    EXPECT_EQ(r.status, t > 10.0 ? ScanStatus::kOk : ScanStatus::kRejected) << t;
    EXPECT_FALSE(r.map_reset) << t;
  }
}

TEST(ClockBehind, ARigRestartsToo) {
  Config config = TwoAlike();
  config.alignment.reset_after_jumps = 2;
  Estimator rig(config);
  const auto cycle = [](double t) {
    return std::vector<Scan>{Wall(t, {0, 0, 0}, 0, 12.0), Wall(t + 0.01, {0, 0, 0}, 1, 12.0)};
  };
  ASSERT_EQ(rig.ProcessCycle(cycle(0.0)).status, ScanStatus::kOk);
  ASSERT_EQ(rig.ProcessCycle(cycle(1e6)).status, ScanStatus::kOk);
  EXPECT_EQ(rig.ProcessCycle(cycle(0.1)).reject_reason, RejectReason::kTimestampNotIncreasing);
  const Result& r = rig.ProcessCycle(cycle(0.2));
  ASSERT_EQ(r.status, ScanStatus::kOk) << r.message;
  EXPECT_TRUE(r.map_reset);
}

// A scan without a usable echo places nothing: it is not counted as placed from the sweep.
TEST(SweepCorrected, NotForAScanWithoutEchoes) {
  Config config;
  config.sensor.sweep_s = 0.02;
  Estimator estimator(config);
  for (int k = 0; k < 3; ++k) {
    const Result& r = estimator.Process(Wall(0.04 * k, {0.5 * k, 0, 0}, 0, 12.0));
    EXPECT_EQ(r.sweep_corrected, k > 0) << k;
  }
  Scan empty = Wall(0.12, {1.5, 0, 0}, 0, 12.0);
  empty.points.clear();
  EXPECT_FALSE(estimator.Process(empty).sweep_corrected);
  EXPECT_TRUE(estimator.Process(Wall(0.16, {2.0, 0, 0}, 0, 12.0)).sweep_corrected);
}

}  // namespace
}  // namespace freespace
