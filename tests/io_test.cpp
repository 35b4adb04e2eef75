// Readers and writers: CARMEN FLASER and ROBOTLASER1 (with malformed and truncated lines), the
// project's own log format round trip, KITTI frames cut into a ScaLa-like scan, and the real
// logs in the shared data folder; a large KITTI frame read in bounded memory.
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

#include "alloc_counter.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

std::string TempFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string Flaser(int n, double range, double x, double t) {
  std::string line = "FLASER " + std::to_string(n);
  for (int i = 0; i < n; ++i) line += " " + std::to_string(i == 3 ? 81.83 : range);
  line += " " + std::to_string(x) + " 2 0.5 " + std::to_string(x) + " 2 0.5 " + std::to_string(t) +
          " host " + std::to_string(t);
  return line + "\n";
}

TEST(Io, CarmenFlaserGeometryPosesAndNoEcho) {
  const std::string path =
      TempFile("a.log", "# comment\nPARAM x 1\nODOM 0 0 0 0 0 0 1 h 1\n" +
                            Flaser(180, 3.5, 1.0, 10.0) + Flaser(180, 4.0, 1.5, 10.1));
  auto reader = OpenLog(path);
  EXPECT_EQ(reader->sensor().layers, 1);
  EXPECT_DOUBLE_EQ(reader->sensor().min_angle_deg, -90.0);
  EXPECT_DOUBLE_EQ(reader->sensor().max_angle_deg, 89.0);
  EXPECT_DOUBLE_EQ(reader->sensor().angular_resolution_deg, 1.0);
  EXPECT_DOUBLE_EQ(reader->sensor().max_range_m, 81.83);
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  EXPECT_EQ(reader->line(), 4u);
  ASSERT_EQ(scan.points.size(), 180u);
  EXPECT_NEAR(scan.points[0].angle_rad, -M_PI / 2, 1e-6);
  EXPECT_NEAR(scan.points[90].angle_rad, 0.0, 1e-6);
  EXPECT_FLOAT_EQ(scan.points[0].range_m, 3.5f);
  EXPECT_FALSE(scan.points[3].echo);  // the saturation value
  EXPECT_TRUE(scan.points[4].echo);
  EXPECT_DOUBLE_EQ(scan.pose.x, 1.0);
  EXPECT_DOUBLE_EQ(scan.pose.yaw, 0.5);
  EXPECT_DOUBLE_EQ(scan.timestamp_s, 10.0);
  ASSERT_TRUE(reader->Next(&scan));
  EXPECT_DOUBLE_EQ(scan.pose.x, 1.5);
  EXPECT_FALSE(reader->Next(&scan));
  EXPECT_TRUE(reader->TakeIssues().empty());
}

TEST(Io, MalformedAndTruncatedLinesAreReportedWithTheirLineAndSkipped) {
  std::string truncated = Flaser(180, 3.0, 0, 2.0);
  truncated = truncated.substr(0, truncated.size() / 2) + "\n";
  std::string bad_number = Flaser(180, 3.0, 0, 3.0);
  bad_number.replace(bad_number.find(" 3.000000"), 9, " 3.0abc");
  const std::string path =
      TempFile("b.log", Flaser(180, 3.0, 0, 1.0) + truncated + bad_number + "%%garbage%%\n" +
                            "FLASER -5 1 2 3\n" + Flaser(180, 3.0, 0, 4.0));
  auto reader = OpenLog(path);
  Scan scan;
  std::vector<double> times;
  while (reader->Next(&scan)) times.push_back(scan.timestamp_s);
  EXPECT_EQ(times, (std::vector<double>{1.0, 4.0}));
  const auto issues = reader->TakeIssues();
  ASSERT_EQ(issues.size(), 4u);
  EXPECT_EQ(issues[0].line, 2u);
  EXPECT_NE(issues[0].message.find("truncated"), std::string::npos);
  EXPECT_EQ(issues[1].line, 3u);
  EXPECT_NE(issues[1].message.find("'3.0abc'"), std::string::npos);
  EXPECT_EQ(issues[2].line, 4u);
  EXPECT_EQ(issues[3].line, 5u);
  EXPECT_NE(issues[0].ToString().find("b.log:2: "), std::string::npos);
}

// Two ROBOTLASER1 scans (t 5 and 6, laser x 0 and 1) of `layers` lines each, 41 beams from -10
// to 10 deg: beam b of layer l at 10 + l + 0.01 b m, beam 7 without echo.
void WriteRobotLaserLog(const std::string& path, int layers) {
  SensorConfig sensor;
  sensor.layers = layers;
  sensor.min_angle_deg = -10;
  sensor.max_angle_deg = 10;
  sensor.angular_resolution_deg = 0.5;
  sensor.max_range_m = 60;
  RobotLaserWriter writer(path, sensor);
  for (int k = 0; k < 2; ++k) {
    Scan scan = test::MakeScan(5.0 + k, {1.0 * k, 2.0, 0.25}, {}, {});
    for (int layer = 0; layer < layers; ++layer) {
      for (int b = 0; b <= 40; ++b) {
        ScanPoint p;
        p.layer = std::uint8_t(layer);
        p.angle_rad = float((-10 + 0.5 * b) * M_PI / 180);
        p.echo = b != 7;
        p.range_m = float(10 + layer + 0.01 * b);
        scan.points.push_back(p);
      }
    }
    writer.Write(scan);
  }
  writer.Close();
}

TEST(Io, RobotLaserLinesWithOneTimestampAreTheLayersOfOneScan) {
  const std::string path = ::testing::TempDir() + "/c.log";
  WriteRobotLaserLog(path, 3);
  auto reader = OpenLog(path);
  EXPECT_EQ(reader->sensor().layers, 3);
  EXPECT_NEAR(reader->sensor().angular_resolution_deg, 0.5, 1e-6);
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  ASSERT_EQ(scan.points.size(), 3u * 41);
  EXPECT_EQ(scan.points[41].layer, 1);
  EXPECT_NEAR(scan.points[41 + 5].range_m, 11.05, 1e-3);
  EXPECT_FALSE(scan.points[7].echo);
  EXPECT_DOUBLE_EQ(scan.timestamp_s, 5.0);
  ASSERT_TRUE(reader->Next(&scan));
  EXPECT_DOUBLE_EQ(scan.pose.x, 1.0);
  EXPECT_FALSE(reader->Next(&scan));
  EXPECT_TRUE(reader->TakeIssues().empty());

  // The first scan's second line with another laser pose: no layer of that scan (reported and
  // skipped), and the log still has three layers.
  std::ifstream in(path);
  std::string text, line;
  int robot_lines = 0;
  while (std::getline(in, line)) {
    if (line.rfind("ROBOTLASER1 ", 0) == 0 && ++robot_lines == 2) {
      std::istringstream split(line);
      std::vector<std::string> f((std::istream_iterator<std::string>(split)),
                                 std::istream_iterator<std::string>());
      const std::size_t n = std::stoul(f[8]), m = std::stoul(f[9 + n]);
      f[n + m + 10] = "7.5";  // laser x
      line.clear();
      for (const std::string& field : f) line += (line.empty() ? "" : " ") + field;
    }
    text += line + "\n";
  }
  auto moved = OpenLog(TempFile("c_moved.log", text));
  EXPECT_EQ(moved->sensor().layers, 3);
  ASSERT_TRUE(moved->Next(&scan));
  EXPECT_EQ(scan.points.size(), 2u * 41);
  EXPECT_DOUBLE_EQ(scan.pose.x, 0.0);
  ASSERT_TRUE(moved->Next(&scan));
  EXPECT_EQ(scan.points.size(), 3u * 41);
  const auto issues = moved->TakeIssues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_NE(issues[0].message.find("another laser pose: no layer of that scan"), std::string::npos)
      << issues[0].message;
}

// A saturation range the caller gives that is no range is refused, not read as "the log's".
TEST(Io, CarmenMaxRangeMustBeARange) {
  const std::string path = TempFile("range.log", Flaser(180, 3.0, 1.0, 1.0));
  for (const double bad : {-5.0, double(NAN), double(INFINITY)}) {
    LogOptions options;
    options.carmen_max_range_m = bad;
    EXPECT_THROW(OpenLog(path, options), InputError) << bad;
  }
  // The sensor says the range the lines are read with, however short.
  for (const double range : {50.0, 0.5}) {
    LogOptions options;
    options.carmen_max_range_m = range;
    EXPECT_DOUBLE_EQ(OpenLog(path, options)->sensor().max_range_m, range);
  }
}

// What a skipped CARMEN line may not leave behind: a FLASER line with a field too many (which
// would shift its pose and time), its ranges in the saturation value or in the next scan, a rear
// laser whose lines are all unusable, a hexadecimal number.
TEST(Io, CarmenLinesSkippedLeaveNothingBehind) {
  {
    std::string extra = Flaser(180, 3.0, 0, 2.0);
    extra.insert(extra.find(" 3.000000"), " 3.000000");  // 181 ranges for n = 180
    std::string saturated = Flaser(180, 500.0, 0, 3.0);  // all 500 m, its timestamp broken
    saturated.replace(saturated.rfind(" host"), 0, "x");
    const std::string path = TempFile(
        "skip1.log", Flaser(180, 3.0, 1.0, 1.0) + extra + saturated + Flaser(180, 3.0, 1.0, 4.0));
    auto reader = OpenLog(path);
    EXPECT_DOUBLE_EQ(reader->sensor().max_range_m, 81.83);  // not the skipped line's 500
    Scan scan;
    std::vector<double> times;
    while (reader->Next(&scan)) {
      times.push_back(scan.timestamp_s);
      EXPECT_DOUBLE_EQ(scan.pose.x, 1.0);
      EXPECT_FALSE(scan.points[3].echo);  // 81.83 m: no echo
    }
    EXPECT_EQ(times, (std::vector<double>{1.0, 4.0}));
    const auto issues = reader->TakeIssues();
    ASSERT_EQ(issues.size(), 2u);
    EXPECT_EQ(issues[0].line, 2u);
    EXPECT_NE(issues[0].message.find("too many fields: 192 fields, expected 191"),
              std::string::npos)
        << issues[0].message;
    EXPECT_EQ(issues[1].line, 3u);
  }
  {
    // A ROBOTLASER1 scan after a FLASER line skipped for a bad range holds its own points only.
    const std::string robot = ::testing::TempDir() + "/skip2_robot.log";
    WriteRobotLaserLog(robot, 1);
    std::ifstream in(robot);
    std::string first, second, line;
    while (std::getline(in, line))
      (first.empty() && line[0] != '#' ? first : second) += line + "\n";
    std::string bad = Flaser(180, 3.0, 0, 5.5);
    bad.replace(bad.find(" 3.000000"), 9, " BAD");
    auto reader = OpenLog(TempFile("skip2.log", first + bad + second));
    Scan scan;
    std::vector<std::size_t> sizes;
    while (reader->Next(&scan)) sizes.push_back(scan.points.size());
    EXPECT_EQ(sizes, (std::vector<std::size_t>{41, 41}));
    ASSERT_EQ(reader->TakeIssues().size(), 1u);
  }
  {
    // RLASER lines, every one truncated: one laser, and the user is told the rear one is gone.
    std::string rear = Flaser(180, 3.0, 0, 1.05);
    rear.replace(0, 6, "RLASER");
    rear.resize(rear.size() / 2);
    rear += "\n";
    auto reader =
        OpenLog(TempFile("skip3.log", Flaser(180, 3.0, 0, 1.0) + rear + Flaser(180, 3.0, 0, 2.0)));
    EXPECT_EQ(reader->sensors().size(), 1u);
    const auto issues = reader->TakeIssues();
    ASSERT_EQ(issues.size(), 1u);
    EXPECT_EQ(issues[0].line, 2u);
    EXPECT_NE(issues[0].message.find("RLASER: no line of the second laser is usable"),
              std::string::npos);
  }
  {
    // A last line without its newline may be a file cut short: read, with a note saying so.
    std::string cut = Flaser(180, 3.0, 0, 2.0);
    cut.pop_back();
    auto reader = OpenLog(TempFile("cut.log", Flaser(180, 3.0, 0, 1.0) + cut));
    Scan scan;
    int scans = 0;
    while (reader->Next(&scan)) ++scans;
    EXPECT_EQ(scans, 2);
    const auto issues = reader->TakeIssues();
    ASSERT_EQ(issues.size(), 1u);
    EXPECT_TRUE(issues[0].note);
    EXPECT_EQ(issues[0].line, 2u);
    EXPECT_NE(issues[0].message.find("without a newline"), std::string::npos);
  }
  {
    std::string hex = Flaser(180, 3.0, 0, 2.0);
    hex.replace(hex.find(" 2.000000 host"), 9, " 0x64.4p0");
    auto reader = OpenLog(TempFile("skip4.log", Flaser(180, 3.0, 0, 1.0) + hex));
    Scan scan;
    int scans = 0;
    while (reader->Next(&scan)) ++scans;
    EXPECT_EQ(scans, 1);
    const auto issues = reader->TakeIssues();
    ASSERT_EQ(issues.size(), 1u);
    EXPECT_NE(issues[0].message.find("'0x64.4p0') is not a number"), std::string::npos)
        << issues[0].message;
  }
}

TEST(Io, NativeLogRoundTripAndErrors) {
  SensorConfig sensor;
  sensor.mount_x_m = 3.7;
  const std::string path = ::testing::TempDir() + "/d.fslog";
  NativeLogWriter writer(path, sensor);
  Scan scan =
      test::MakeScan(1.25, {100000.123456, -5.5, 3.1}, {-72.5, 0.0, 72.25}, {12.345, -1.0, 149.0});
  scan.points[2].layer = 3;
  writer.Write(scan);
  writer.Close();
  std::ofstream(path, std::ios::app) << "SCAN 2 0 0 0 2 0 1.0 5.0\nSCAN 3 0 0 0 1 0 1.0 x\n";
  auto reader = OpenLog(path);
  EXPECT_DOUBLE_EQ(reader->sensor().mount_x_m, 3.7);
  Scan back;
  ASSERT_TRUE(reader->Next(&back));
  EXPECT_DOUBLE_EQ(back.timestamp_s, 1.25);
  EXPECT_NEAR(back.pose.x, 100000.123456, 1e-9);
  ASSERT_EQ(back.points.size(), 3u);
  EXPECT_NEAR(back.points[0].range_m, 12.345, 1e-4);
  EXPECT_FALSE(back.points[1].echo);
  EXPECT_EQ(back.points[2].layer, 3);
  EXPECT_NEAR(back.points[2].angle_rad, 72.25 * M_PI / 180, 1e-6);
  EXPECT_FALSE(reader->Next(&back));
  const auto issues = reader->TakeIssues();
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_NE(issues[0].message.find("expected 12"), std::string::npos);
  EXPECT_NE(issues[1].message.find("'x'"), std::string::npos);
}

// Numbers of any size are written whole: a huge but finite yaw (300 digits in %.9f, which the
// estimator takes and wraps) and a point at the float's limits read back as written.
TEST(Io, NativeLogWritesHugeNumbersWhole) {
  const std::string path = ::testing::TempDir() + "/huge.fslog";
  NativeLogWriter writer(path, SensorConfig{});
  Scan scan = test::MakeScan(2.0, {1.0, 2.0, 1e300}, {0.0, 10.0}, {5.0, 1e38});
  writer.Write(scan);
  writer.Close();
  auto reader = OpenLog(path);
  Scan back;
  const bool read = reader->Next(&back);
  for (const LogIssue& issue : reader->TakeIssues()) ADD_FAILURE() << issue.ToString();
  ASSERT_TRUE(read);
  EXPECT_DOUBLE_EQ(back.pose.yaw, 1e300);
  ASSERT_EQ(back.points.size(), 2u);
  EXPECT_FLOAT_EQ(back.points[1].range_m, 1e38f);

  // The CARMEN writer's poses likewise.
  const std::string clf = ::testing::TempDir() + "/huge.clf";
  RobotLaserWriter carmen(clf, SensorConfig{});
  carmen.Write(scan);
  carmen.Close();
  auto carmen_reader = OpenLog(clf);
  const bool carmen_read = carmen_reader->Next(&back);
  for (const LogIssue& issue : carmen_reader->TakeIssues()) ADD_FAILURE() << issue.ToString();
  ASSERT_TRUE(carmen_read);
  EXPECT_DOUBLE_EQ(back.pose.yaw, 1e300);
}

TEST(Io, UnrecognisedFilesFailWithTheirName) {
  const std::string path = TempFile("e.txt", "hello world\n");
  try {
    OpenLog(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("e.txt: not a recognised log"), std::string::npos);
  }
  EXPECT_THROW(OpenLog(::testing::TempDir() + "/does-not-exist.log"), InputError);
}

TEST(Io, APipeOrADeviceIsRefusedBeforeItIsOpened) {
  // Opening a FIFO for reading would wait for a writer: refused from its status alone, with the
  // reason, in every format; /dev/null (a device) likewise. A file behind a link is a file.
  const std::string tag = std::to_string(getpid());
  const std::string fifo = ::testing::TempDir() + "/log-" + tag + ".fifo";
  std::remove(fifo.c_str());
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const LogFormat format : {LogFormat::kAuto, LogFormat::kNative, LogFormat::kCarmen}) {
    LogOptions options;
    options.format = format;
    for (const std::string& path : {fifo, std::string("/dev/null")}) {
      try {
        OpenLog(path, options);
        FAIL() << path << " opened as " << ToString(format);
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(path + ": a pipe or a device, not a file"),
                  std::string::npos)
            << e.what();
      }
    }
  }
  std::remove(fifo.c_str());
  const std::string file = TempFile("linked-" + tag + ".log", Flaser(181, 5.0, 1.0, 1.0));
  const std::string link = ::testing::TempDir() + "/link-" + tag + ".log";
  std::remove(link.c_str());
  ASSERT_EQ(symlink(file.c_str(), link.c_str()), 0);
  EXPECT_EQ(OpenLog(link)->format(), LogFormat::kCarmen);
  std::remove(link.c_str());
}

TEST(Io, RealCarmenLogs) {
  FREESPACE_REQUIRE_DATA("carmen/intel-corrected.log", path);
  auto reader = OpenLog(path);
  EXPECT_DOUBLE_EQ(reader->sensor().max_range_m, 81.83);
  Scan scan;
  int scans = 0, no_echo = 0;
  while (reader->Next(&scan)) {
    ++scans;
    ASSERT_EQ(scan.points.size(), 180u);
    for (const ScanPoint& p : scan.points) no_echo += p.echo ? 0 : 1;
  }
  EXPECT_EQ(scans, 910);
  EXPECT_GT(no_echo, 0);
  EXPECT_LT(no_echo, scans * 180 / 10);
  EXPECT_TRUE(reader->TakeIssues().empty());
}

TEST(Io, KittiFrameIsCutIntoAScalaLikeScan) {
  FREESPACE_REQUIRE_DATA("kitti/kitti_00_000000.bin", path);
  auto reader = OpenLog(path);
  EXPECT_EQ(reader->sensor().layers, 4);
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  ASSERT_EQ(scan.points.size(), 4u * 581);
  int echoes = 0;
  for (const ScanPoint& p : scan.points) {
    EXPECT_LE(std::abs(p.angle_rad), float(72.625 * M_PI / 180));
    echoes += p.echo ? 1 : 0;
  }
  EXPECT_GT(echoes, 581);
  EXPECT_FALSE(reader->Next(&scan));
  // One frame through the estimator: a polygon around the car.
  Config c;
  c.sensor = reader->sensor();
  Estimator estimator(c);
  const Result& r = estimator.Process(scan);
  EXPECT_EQ(r.status, ScanStatus::kOk);
  EXPECT_GT(r.stats.kept, 500);
  EXPECT_TRUE(r.polygon_contains_vehicle);
}

// Frames that give no Velodyne point say so: an empty file, records that lie beyond any
// Velodyne's reach (a file of another kind named .bin), points in no layer of the cut.
TEST(Io, KittiFramesWithoutPointsAreReported) {
  const auto issues = [](const std::string& name, const std::vector<float>& values) {
    const std::string path = ::testing::TempDir() + "/" + name;
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(values.data()),
               std::streamsize(values.size() * sizeof(float)));
    auto reader = OpenLog(path);
    Scan scan;
    EXPECT_TRUE(reader->Next(&scan));
    std::string all;
    for (const LogIssue& issue : reader->TakeIssues()) all += issue.ToString() + "\n";
    return all;
  };
  EXPECT_NE(issues("empty.bin", {}).find("empty.bin: no point (0 bytes)"), std::string::npos);
  const std::string far = issues("far.bin", {10, 0, 0, 0, 5000, 0, 0, 0, 0, 3e11f, 1, 0});
  EXPECT_NE(far.find("2 of 3 records more than 1 km from the sensor ignored"), std::string::npos)
      << far;
  EXPECT_EQ(far.find("no point of"), std::string::npos) << far;  // the one at 10 m is in a layer
  const std::string high = issues("high.bin", {10, 0, 5, 0});    // 26 deg up: in no layer
  EXPECT_NE(high.find("no point of its 1 lies in a layer of the cut"), std::string::npos) << high;
  EXPECT_EQ(issues("good.bin", {10, 0, 0, 0, 12, 1, 0.05f, 0}), "");
}

// A 64 MB frame (the recorded one over and over, then one nearer point straight ahead in the
// layer at +0.4 deg) is read in chunks: the heap's peak while reading stays far below the
// file's size, and the scan is the recorded frame's with that one beam nearer.
TEST(Io, LargeKittiFrameIsReadInBoundedMemory) {
  FREESPACE_REQUIRE_DATA("kitti/kitti_00_000000.bin", path);
  std::ostringstream bytes;
  bytes << std::ifstream(path, std::ios::binary).rdbuf();
  const std::string frame = bytes.str();
  ASSERT_EQ(frame.size() % 16, 0u);
  Scan recorded;
  ASSERT_TRUE(OpenLog(path)->Next(&recorded));

  const std::string large = ::testing::TempDir() + "/large_frame.bin";
  constexpr std::size_t kSize = std::size_t(64) << 20;
  {
    std::ofstream out(large, std::ios::binary | std::ios::trunc);
    for (std::size_t written = 0; written < kSize; written += frame.size()) {
      out.write(frame.data(), std::streamsize(frame.size()));
    }
    const float nearer[4] = {3.0f, 0.0f, float(3.0 * std::tan(0.4 * M_PI / 180.0)), 0.5f};
    out.write(reinterpret_cast<const char*>(nearer), sizeof nearer);
    ASSERT_TRUE(out.good());
  }
  const long before = LiveHeapBytes();
  ResetPeakHeapBytes();
  Scan scan;
  std::vector<LogIssue> issues;
  {
    auto reader = OpenLog(large);
    ASSERT_TRUE(reader->Next(&scan));
    issues = reader->TakeIssues();
  }
  const long peak = PeakHeapBytes() - before;
  std::remove(large.c_str());
  std::printf("peak heap reading a %zu MB frame: %ld kB\n", kSize >> 20, peak / 1024);
  EXPECT_LT(peak, long(kSize / 32)) << "peak heap while reading: " << peak << " bytes";
  EXPECT_TRUE(issues.empty());

  ASSERT_EQ(scan.points.size(), recorded.points.size());
  int changed = 0;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const ScanPoint &a = scan.points[i], &b = recorded.points[i];
    if (a.range_m == b.range_m && a.angle_rad == b.angle_rad && a.echo == b.echo) continue;
    ++changed;
    EXPECT_EQ(a.layer, 2);
    EXPECT_TRUE(a.echo);
    EXPECT_FLOAT_EQ(a.range_m, 3.0f);
    EXPECT_FLOAT_EQ(a.angle_rad, 0.0f);
  }
  EXPECT_EQ(changed, 1);
}

}  // namespace
}  // namespace freespace
