// alignment.scan_match on a real drive: the full ACES building log's raw odometry against its
// published relations (pairs of scan times with the true relative pose between them). The
// corrected poses' relative heading over the long relations (the robot back where it was
// minutes before) errs far less than the odometry's, when heading_drift_dps is what the robot's
// odometry drifts; at the car's 0.1 deg/s the correction is too cautious for this robot.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "freespace/estimator.hpp"
#include "freespace/io.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

struct Relation {
  double t1 = 0.0, t2 = 0.0;  // scan times, s
  double yaw = 0.0;           // the true heading change from t1 to t2, radians
};

std::vector<Relation> ReadRelations(const std::string& path) {
  std::ifstream in(path);
  std::vector<Relation> out;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    Relation r;
    double x, y, z, roll, pitch;
    if (fields >> r.t1 >> r.t2 >> x >> y >> z >> roll >> pitch >> r.yaw) out.push_back(r);
  }
  return out;
}

struct Track {
  std::vector<double> t, odometry_yaw, corrected_yaw;

  // The index of the scan nearest the time `time` (the relations name scan times; the log's
  // are in order).
  std::size_t At(double time) const {
    const auto it = std::lower_bound(t.begin(), t.end(), time);
    std::size_t k = std::min<std::size_t>(it - t.begin(), t.size() - 1);
    if (k > 0 && std::abs(t[k - 1] - time) <= std::abs(t[k] - time)) --k;
    EXPECT_LT(std::abs(t[k] - time), 1e-3) << "no scan at t = " << time;
    return k;
  }
};

Track Drive(const std::string& path, double drift_dps) {
  auto reader = OpenLog(path);
  Config config = test::LoadProjectConfig("indoor.yaml");
  config.sensor = reader->sensor();
  config.alignment.scan_match = true;
  config.alignment.heading_drift_dps = drift_dps;
  Estimator estimator(config);
  Track track;
  Scan scan;
  while (reader->Next(&scan)) {
    const Result& r = estimator.Process(scan);
    EXPECT_NE(r.status, ScanStatus::kRejected) << r.message;
    track.t.push_back(scan.timestamp_s);
    track.odometry_yaw.push_back(scan.pose.yaw);
    track.corrected_yaw.push_back(scan.pose.yaw + r.pose_correction.yaw);
  }
  return track;
}

// Mean absolute error of the relative heading over the relations that span [lo, hi) seconds.
double MeanYawError(const Track& track, const std::vector<double>& yaw,
                    const std::vector<Relation>& relations, double lo, double hi) {
  double sum = 0.0;
  int n = 0;
  for (const Relation& rel : relations) {
    if (rel.t2 - rel.t1 < lo || rel.t2 - rel.t1 >= hi) continue;
    const double turned = yaw[track.At(rel.t2)] - yaw[track.At(rel.t1)];
    sum += std::abs(std::remainder(turned - rel.yaw, 2 * M_PI));
    ++n;
  }
  EXPECT_GT(n, 50);
  return n > 0 ? sum / n : 0.0;
}

TEST(HeadingRelations, AcesBuildingLongRelations) {
  FREESPACE_REQUIRE_FULL_DATA("carmen/aces.clf", log_path);
  FREESPACE_REQUIRE_FULL_DATA("carmen/aces.relations", relations_path);
  const std::vector<Relation> relations = ReadRelations(relations_path);
  ASSERT_GT(relations.size(), 1000u);
  // The robot's odometry: its heading errs 0.9 deg on the relations under 10 s (median 0.7 s),
  // about 1 deg/s.
  constexpr double kLong = 10.0, kAll = 1e9;
  const Track matched = Drive(log_path, 1.0);
  const double odometry = MeanYawError(matched, matched.odometry_yaw, relations, kLong, kAll);
  const double corrected = MeanYawError(matched, matched.corrected_yaw, relations, kLong, kAll);
  EXPECT_GT(odometry, 10 * M_PI / 180);
  EXPECT_LT(corrected, 0.4 * odometry);
  const Track cautious = Drive(log_path, 0.1);
  EXPECT_LT(corrected,
            0.6 * MeanYawError(cautious, cautious.corrected_yaw, relations, kLong, kAll));
  // The short relations are not made worse.
  EXPECT_LT(MeanYawError(matched, matched.corrected_yaw, relations, 0.0, kLong),
            1.02 * MeanYawError(matched, matched.odometry_yaw, relations, 0.0, kLong));
}

}  // namespace
}  // namespace freespace
