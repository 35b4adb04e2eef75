// Bad and extreme input to the readers (docs/behaviour.md): every problem is reported with its
// line and skipped, never thrown; counts and layer numbers that do not fit are caught before
// any arithmetic on them; messages quote a short, printable excerpt of the input.
#include <fstream>

#include "test_util.hpp"

namespace freespace {
namespace {

std::string TempFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

const char kNativeHeader[] = "FREESPACE_LOG 1\nSENSOR 1 -90 90 1 0 80 0 0 0\n";

// Reads every scan; returns the timestamps and leaves the issues in `issues`.
std::vector<double> ReadAll(const std::string& path, std::vector<LogIssue>* issues) {
  auto reader = OpenLog(path);
  std::vector<double> times;
  Scan scan;
  while (true) {
    bool more = false;
    EXPECT_NO_THROW(more = reader->Next(&scan));
    if (!more) break;
    times.push_back(scan.timestamp_s);
  }
  *issues = reader->TakeIssues();
  return times;
}

TEST(BadInput, NativePointCountsThatOverflowAreReportedNotThrown) {
  // 3 n + 6 overflows a long for the second count; the first is the largest long.
  const std::string path =
      TempFile("overflow.fslog", std::string(kNativeHeader) + "SCAN 1 0 0 0 1 0 1.0 5.0\n" +
                                     "SCAN 2 0 0 0 9223372036854775807 0 1.0 5.0\n" +
                                     "SCAN 3 0 0 0 3074457345618258602 0 1.0 5.0\n" +
                                     "SCAN 4 0 0 0 1 0 1.0 5.0\n");
  std::vector<LogIssue> issues;
  EXPECT_EQ(ReadAll(path, &issues), (std::vector<double>{1.0, 4.0}));
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_EQ(issues[0].line, 4u);
  EXPECT_NE(issues[0].message.find("expected 6 + 3 per point"), std::string::npos)
      << issues[0].message;
  EXPECT_EQ(issues[1].line, 5u);
}

TEST(BadInput, NativeSensorLayerCountMustBeAnInteger1To255) {
  for (const char* layers : {"1e300", "0", "256", "2.5", "nan", "-1"}) {
    const std::string path =
        TempFile("layers.fslog",
                 "FREESPACE_LOG 1\nSENSOR " + std::string(layers) + " -90 90 1 0 80 0 0 0\n");
    try {
      OpenLog(path);
      ADD_FAILURE() << layers << ": expected InputError";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(":2: SENSOR layer count '" + std::string(layers) +
                                           "' is not an integer 1..255"),
                std::string::npos)
          << e.what();
    }
  }
}

// The SENSOR line's optional tenth number is the sensor's sweep: read, written back where it is
// not 0, and refused outside -1 .. 1 s.
TEST(BadInput, NativeSensorSweepIsReadWrittenAndChecked) {
  const std::string with = TempFile("sweep.fslog",
                                    "FREESPACE_LOG 1\nSENSOR 1 -90 90 1 0 80 0 0 0 "
                                    "0.016\nSCAN 1 0 0 0 1 0 1.0 5.0\n");
  EXPECT_DOUBLE_EQ(OpenLog(with)->sensor().sweep_s, 0.016);
  EXPECT_DOUBLE_EQ(OpenLog(TempFile("nosweep.fslog", kNativeHeader))->sensor().sweep_s, 0.0);

  SensorConfig sensor = OpenLog(with)->sensor();
  const std::string written = ::testing::TempDir() + "/sweep_written.fslog";
  {
    NativeLogWriter writer(written, sensor);
    writer.Close();
  }
  EXPECT_DOUBLE_EQ(OpenLog(written)->sensor().sweep_s, 0.016);
  sensor.sweep_s = 0.0;
  {
    NativeLogWriter writer(written, sensor);
    writer.Close();
  }
  std::ifstream in(written);
  std::string line;
  while (std::getline(in, line) && line.rfind("SENSOR", 0) != 0) {
  }
  EXPECT_EQ(line, "SENSOR 1 -90 90 1 0 80 0 0 0");  // as before the field existed

  for (const char* bad : {"1.5", "-2", "nan", "x"}) {
    const std::string path =
        TempFile("badsweep.fslog",
                 "FREESPACE_LOG 1\nSENSOR 1 -90 90 1 0 80 0 0 0 " + std::string(bad) + "\n");
    try {
      OpenLog(path);
      ADD_FAILURE() << bad << ": expected InputError";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(":2: "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("sweep_s"), std::string::npos) << e.what();
    }
  }
}

// A SENSOR line's numbers the engine cannot use are the log's error, named at its line, not a
// config error about a field the user's config does not hold.
TEST(BadInput, SensorLineNumbersAreCheckedAtTheLine) {
  const struct {
    const char* numbers;  // layers min max resolution min_range max_range mount x y yaw
    const char* field;
  } cases[] = {
      {"1 -90 90 nan 0 80 0 0 0", "angular_resolution_deg"},
      {"1 -90 90 -1 0 80 0 0 0", "angular_resolution_deg"},
      {"1 -90 -95 1 0 80 0 0 0", "max_angle_deg"},
      {"1 -90 90 1 5 4 0 0 0", "max_range_m"},
      {"1 -90 90 1 0 80 inf 0 0", "mount_x_m"},
      {"1 -90 90 1 -1 80 0 0 0", "min_range_m"},
  };
  for (const auto& c : cases) {
    const std::string path =
        TempFile("badsensor.fslog", "FREESPACE_LOG 1\nSENSOR " + std::string(c.numbers) + "\n");
    try {
      OpenLog(path);
      ADD_FAILURE() << c.numbers << ": expected InputError";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("badsensor.fslog:2: SENSOR: sensor." + std::string(c.field) + " = "),
                std::string::npos)
          << what;
    }
  }
  // The same line with usable numbers reads.
  EXPECT_EQ(OpenLog(TempFile("goodsensor.fslog", "FREESPACE_LOG 1\nSENSOR 1 -90 90 1 0 80 0 0 0\n"))
                ->sensor()
                .max_range_m,
            80.0);
}

std::string RobotLaser(double t, int n) {
  std::string line = "ROBOTLASER1 0 -1.5 3 0.1 50 0.01 0 " + std::to_string(n);
  for (int i = 0; i < n; ++i) line += " 5.0";
  line += " 0 1 2 0.5 1 2 0.5 0 0 0 0 0 " + std::to_string(t) + " host " + std::to_string(t);
  return line + "\n";
}

// A scan holds at most 255 layers (SensorConfig::layers): lines past the 255th with one
// timestamp are reported with their count, neither wrapped back to layer 0 nor kept as a layer
// the engine would drop.
TEST(BadInput, RobotLaserLayersPast255AreReportedNotWrapped) {
  std::string text;
  for (int i = 0; i < 300; ++i) text += RobotLaser(1.0, 4);
  text += RobotLaser(2.0, 4);
  const std::string path = TempFile("many-layers.log", text);
  auto reader = OpenLog(path);
  ASSERT_EQ(reader->sensor().layers, 255);
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  ASSERT_EQ(scan.points.size(), 255u * 4);
  // Layer numbers run 0..254 once each, in order: none wrapped back to 0, all within the sensor's.
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    ASSERT_EQ(scan.points[i].layer, i / 4) << i;
  }
  const auto issues = reader->TakeIssues();
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].line, 256u);
  EXPECT_NE(issues[0].message.find("45 line(s) from here on share the timestamp of the 255 before"),
            std::string::npos)
      << issues[0].message;
  ASSERT_TRUE(reader->Next(&scan));
  EXPECT_DOUBLE_EQ(scan.timestamp_s, 2.0);
  EXPECT_EQ(scan.points.size(), 4u);
}

// The aperture a ROBOTLASER1 log's first line gives is checked there: a start angle that is not a
// number or a beam spacing over 10 deg refuses the log at that line.
TEST(BadInput, RobotLaserApertureIsCheckedAtItsLine) {
  for (const char* bad : {"ROBOTLASER1 0 nan 3 0.1", "ROBOTLASER1 0 -1.5 3 0.5"}) {
    std::string line = RobotLaser(1.0, 4);
    line.replace(0, std::string("ROBOTLASER1 0 -1.5 3 0.1").size(), bad);
    const std::string path = TempFile("aperture.log", "# a log\n" + line + RobotLaser(2.0, 4));
    try {
      OpenLog(path);
      ADD_FAILURE() << bad << ": expected InputError";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(
          what.find("aperture.log:2: ROBOTLASER1: the laser's aperture from this line: sensor."),
          std::string::npos)
          << what;
    }
  }
}

TEST(BadInput, RobotLaserRemissionCountsThatOverflowAreReported) {
  std::string line = RobotLaser(1.0, 4);
  line.replace(line.find(" 0 1 2 0.5"), 2, " 9223372036854775807");
  const std::string path = TempFile("remissions.log", RobotLaser(0.5, 4) + line + RobotLaser(2, 4));
  std::vector<LogIssue> issues;
  EXPECT_EQ(ReadAll(path, &issues), (std::vector<double>{0.5, 2.0}));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].line, 2u);
}

TEST(BadInput, MessagesQuoteAShortPrintableExcerpt) {
  // A 1 MB field and binary bytes: the message stays short and printable.
  const std::string huge(1 << 20, '7');
  const std::string binary = std::string("\x01\xff\x7f", 3) + "abc";
  const std::string path =
      TempFile("long.fslog", std::string(kNativeHeader) + "SCAN " + huge + " 0 0 0 0\n" + "SCAN " +
                                 binary + " 0 0 0 0\n" + binary + "\n");
  std::vector<LogIssue> issues;
  EXPECT_TRUE(ReadAll(path, &issues).empty());
  ASSERT_EQ(issues.size(), 3u);
  for (const LogIssue& issue : issues) {
    const std::string text = issue.ToString();
    EXPECT_LT(text.size(), 400u) << text.substr(0, 400);
    for (const char c : text) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << int(c);
  }
  EXPECT_NE(issues[0].message.find("7777... (1048576 bytes)"), std::string::npos)
      << issues[0].message;
  EXPECT_NE(issues[1].message.find("'\\x01\\xff\\x7fabc'"), std::string::npos) << issues[1].message;
  // The same for a file that is no log at all.
  const std::string not_log =
      TempFile("binary.bin.txt", std::string("\x89PNG\r\n\x1a\n", 8) + huge);
  try {
    OpenLog(not_log);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string text = e.what();
    EXPECT_LT(text.size(), 400u);
    EXPECT_NE(text.find("'\\x89PNG"), std::string::npos) << text.substr(0, 400);
  }
}

}  // namespace
}  // namespace freespace
