// The heading filter (core/scan_match.hpp, alignment.heading_drift_dps) on its own: the share a
// match takes after a reset, after a gap, after failed matches, with a time that steps back, and
// with matches of no error; always a share in [0, 1].
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/scan_match.hpp"

namespace freespace {
namespace {

constexpr double kDrift = 1.0 * M_PI / 180.0;  // rad/s
constexpr double kStd = 0.05 * M_PI / 180.0;   // a match's standard error, rad

// The share the filter's rule gives a variance and a match's standard error.
double Expected(double variance, double std_rad) {
  const double noise = HeadingFilter::kMisfitCorrelation * std_rad;
  return variance / (variance + noise * noise);
}

TEST(HeadingFilter, AHeadingJustResetTakesNoMatch) {
  HeadingFilter f(kDrift);
  f.Reset(10.0);
  EXPECT_EQ(f.Share(kStd, 10.0), 0.0);  // exact by definition: nothing to correct yet
  EXPECT_EQ(f.variance(), 0.0);
  const double gap = 10.04 - 10.0;  // one scan at 25 Hz later
  const double v = kDrift * gap * (kDrift * gap);
  EXPECT_DOUBLE_EQ(f.Share(kStd, 10.04), Expected(v, kStd));
  EXPECT_GT(f.Share(kStd, 20.0), 0.0);
  // A reset after matches forgets their variance and time.
  f.Reset(30.0);
  EXPECT_EQ(f.variance(), 0.0);
  EXPECT_EQ(f.time(), 30.0);
  EXPECT_EQ(f.Share(kStd, 30.0), 0.0);
}

TEST(HeadingFilter, AMatchTakesTheShareOfTheVariancesAndShrinksIt) {
  HeadingFilter f(kDrift);
  f.Reset(0.0);
  const double v1 = kDrift * kDrift * 2.0 * 2.0;
  const double s1 = f.Share(kStd, 2.0);
  EXPECT_DOUBLE_EQ(s1, Expected(v1, kStd));
  EXPECT_DOUBLE_EQ(f.variance(), (1.0 - s1) * v1);
  // Another match at the same time adds no drift: it takes less.
  const double s2 = f.Share(kStd, 2.0);
  EXPECT_LT(s2, s1);
  EXPECT_DOUBLE_EQ(s2, Expected((1.0 - s1) * v1, kStd));
  // A worse match (twice the standard error) at the same state takes less than a better one.
  HeadingFilter a(kDrift), b(kDrift);
  a.Reset(0.0);
  b.Reset(0.0);
  EXPECT_LT(a.Share(2.0 * kStd, 1.0), b.Share(kStd, 1.0));
}

// Failed matches (no Share() call) do not restart the drift: the variance grows from the last
// applied match, so a match after a long gap takes more than one a scan later.
TEST(HeadingFilter, TheDriftCountsFromTheLastAppliedMatch) {
  HeadingFilter f(kDrift);
  f.Reset(0.0);
  f.Share(kStd, 1.0);
  const double after = f.variance();
  HeadingFilter next = f;
  const double soon = next.Share(kStd, 1.04);
  const double late = f.Share(kStd, 10.0);  // 9 s of failed matches between
  EXPECT_DOUBLE_EQ(late, Expected(after + kDrift * kDrift * 9.0 * 9.0, kStd));
  EXPECT_GT(late, soon);
  EXPECT_GT(late, 0.99);  // 9 deg of possible drift against a 0.15 deg match: nearly all of it
  EXPECT_EQ(f.time(), 10.0);
}

// A timestamp a little back (a rig's scanners out of order) adds no drift and leaves the
// filter's time where it was, so the drift up to the next match is not counted twice.
TEST(HeadingFilter, ATimeBackAddsNoDriftAndDoesNotCountTwice) {
  HeadingFilter f(kDrift);
  f.Reset(0.0);
  f.Share(kStd, 5.0);
  const double v = f.variance();
  EXPECT_DOUBLE_EQ(f.Share(kStd, 4.9), Expected(v, kStd));
  EXPECT_EQ(f.time(), 5.0);
  const double v2 = f.variance();
  EXPECT_DOUBLE_EQ(f.Share(kStd, 6.0), Expected(v2 + kDrift * kDrift * 1.0, kStd));
}

TEST(HeadingFilter, MatchesOfNoErrorAndNoDrift) {
  HeadingFilter f(kDrift);
  f.Reset(0.0);
  EXPECT_EQ(f.Share(0.0, 0.0), 0.0);  // no error on either side: nothing taken, nothing broken
  EXPECT_EQ(f.variance(), 0.0);
  EXPECT_EQ(f.Share(0.0, 1.0), 1.0);  // an exact match takes all of it
  EXPECT_EQ(f.variance(), 0.0);
  HeadingFilter still(0.0);  // heading_drift_dps 0: the odometry's heading is trusted
  still.Reset(0.0);
  for (double t = 0.0; t < 100.0; t += 7.0) EXPECT_EQ(still.Share(kStd, t), 0.0);
}

TEST(HeadingFilter, TheShareStaysInZeroToOne) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> step(-0.1, 2.0), error(0.0, 0.01);
  HeadingFilter f(5.0 * M_PI / 180.0);
  f.Reset(0.0);
  double t = 0.0;
  for (int i = 0; i < 10000; ++i) {
    t += step(rng);
    const double s = f.Share(error(rng), t);
    ASSERT_GE(s, 0.0);
    ASSERT_LE(s, 1.0);
    ASSERT_TRUE(std::isfinite(f.variance()));
    ASSERT_GE(f.variance(), 0.0);
  }
}

}  // namespace
}  // namespace freespace
