// What the command-line tools write: the polygons.jsonl line stays valid JSON for any number
// (docs/formats.md), and checked text files report a failed write naming the file.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>

#include "eval/stage_stats.hpp"
#include "freespace/errors.hpp"
#include "output/report.hpp"
#include "output/text_file.hpp"

namespace freespace {
namespace {

Result SmallResult() {
  Result r;
  r.timestamp_s = 12.5;
  r.status = ScanStatus::kOk;
  r.pose = {1.25, -2.5, 0.5};
  r.origin = Vec2(-30.0, -32.0);
  r.vehicle_cells = Vec2(150.5, 149.25);
  r.map_yaw = 0.0125;
  r.pose_correction = {0.5, -0.25, -0.0125};
  r.filtered_speed_mps = 3.125;
  r.polygon_status = PolygonStatus::kOk;
  r.polygon = {Vec2(0, 0), Vec2(1.5, 0), Vec2(0, 2.25)};
  return r;
}

TEST(PolygonJsonLine, KeepsItsFormat) {
  EXPECT_EQ(PolygonJsonLine(7, SmallResult()),
            "{\"scan\":7,\"t_s\":12.500000,\"status\":\"ok\",\"frame\":\"world\",\"pose\":{\"x\":"
            "1.250000,\"y\":-2.500000,\"yaw\":0.500000},\"origin\":[-30.000000,-32.000000],"
            "\"vehicle_cells\":[150.5000,149.2500],\"map_yaw_rad\":0.012500000,"
            "\"pose_correction\":{\"x\":0.500000,\"y\":-0.250000,\"yaw\":-0.012500},"
            "\"speed_mps\":3.125,\"polygon_status\":\"ok\","
            "\"polygon\":[[0.0000,0.0000],[1.5000,0.0000],[0.0000,2.2500],[0.0000,0.0000]]}");
}

TEST(PolygonJsonLine, IsValidJsonForExtremeAndNonFiniteNumbers) {
  Result r = SmallResult();
  r.timestamp_s = 1e307;
  r.pose.x = -1.7976931348623157e308;  // the most negative double: 309 digits
  r.origin = Vec2(-1.84e18, std::nan(""));
  r.filtered_speed_mps = INFINITY;
  r.polygon.push_back(Vec2(1e300, -INFINITY));
  const std::string line = PolygonJsonLine(18446744073709551615ull, r);
  nlohmann::json doc;
  ASSERT_NO_THROW(doc = nlohmann::json::parse(line)) << line.substr(0, 400);
  EXPECT_EQ(doc.at("scan").get<std::uint64_t>(), 18446744073709551615ull);
  EXPECT_EQ(doc.at("t_s").get<double>(), 1e307);
  EXPECT_EQ(doc.at("pose").at("x").get<double>(), -1.7976931348623157e308);
  EXPECT_EQ(doc.at("origin").at(0).get<double>(), -1.84e18);
  EXPECT_TRUE(doc.at("origin").at(1).is_null());
  EXPECT_TRUE(doc.at("speed_mps").is_null());
  EXPECT_EQ(doc.at("polygon").size(), 5u);  // closed: the first vertex again at the end
  EXPECT_EQ(doc.at("polygon").at(3).at(0).get<double>(), 1e300);
  EXPECT_TRUE(doc.at("polygon").at(3).at(1).is_null());
}

TEST(TextFile, AFullDiskIsAnErrorNamingTheFile) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  TextFile file("/dev/full");
  const std::string line(1000, 'x');
  try {
    // The stream buffers: the failure shows at a write that flushes, or at the close.
    for (int i = 0; i < 100; ++i) file.Write(line);
    file.Close();
    FAIL() << "writing 100 kB to /dev/full did not fail";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/full: write failed: No space left on device"),
              std::string::npos)
        << e.what();
  }
}

// Runs `write` in a child process whose files may not grow past `limit` bytes (a full disk):
// true when it failed with an OutputError, as a full disk makes it.
bool FailsPastSize(long limit, const std::function<void()>& write) {
  const pid_t child = fork();
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG instead
    const rlimit size{rlim_t(limit), rlim_t(limit)};
    setrlimit(RLIMIT_FSIZE, &size);
    try {
      write();
    } catch (const OutputError&) {
      _exit(0);
    }
    _exit(1);
  }
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// A file of lines that fails keeps its whole lines only: a reader of polygons.jsonl never meets
// a cut line. A whole document that fails is removed.
TEST(TextFile, AFailedWriteLeavesWholeLinesOrNoDocument) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("freespace_output_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string lines = (dir / "lines.jsonl").string();
  const std::string line = "{\"scan\": 12345, \"polygon\": [1.5, 2]}\n";  // 37 bytes
  ASSERT_TRUE(FailsPastSize(1000, [&] {
    TextFile file(lines);
    try {
      for (int i = 0; i < 1000; ++i) file.Write(line);
    } catch (const OutputError&) {
      file.Close();  // says it again, rather than closing as if all was written
    }
  }));
  std::ifstream in(lines, std::ios::binary);
  const std::string kept((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(kept.size(), 1000 / line.size() * line.size());  // 27 whole lines of the 1000 bytes
  for (std::size_t at = 0; at < kept.size(); at += line.size()) {
    ASSERT_EQ(kept.substr(at, line.size()), line) << "at byte " << at;
  }

  const std::string document = (dir / "summary.json").string();
  ASSERT_TRUE(
      FailsPastSize(1000, [&] { WriteTextFile(document, std::string(5000, ' ') + "{}\n"); }));
  EXPECT_FALSE(std::filesystem::exists(document));
  std::filesystem::remove_all(dir);
}

TEST(TextFile, ADirectoryInTheWayIsAnErrorNamingTheFile) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "freespace_output_test_dir";
  std::filesystem::create_directories(dir);
  try {
    WriteTextFile(dir.string(), "{}\n");
    FAIL() << "writing over a directory did not fail";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.string() + ": cannot create"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(CheckWritten(dir.string()), OutputError);
  std::filesystem::remove_all(dir);
}

// An AVI file is written whole when its RIFF header's size is the file's: one cut short (a full
// disk, which OpenCV's writer does not report) or of another kind is an error naming it.
TEST(TextFile, AnAviCutShortIsAnErrorNamingTheFile) {
  const std::string path = ::testing::TempDir() + "/cut.avi";
  const auto write = [&](const char* riff, std::uint32_t said, const char* kind, int body) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(riff, 4);
    for (int k = 0; k < 4; ++k) out.put(char((said >> (8 * k)) & 0xff));
    out.write(kind, 4);
    out << std::string(std::size_t(body), 'x');
  };
  write("RIFF", 4 + 1000, "AVI ", 1000);
  EXPECT_NO_THROW(CheckAviWritten(path));
  write("RIFF", 4 + 5000, "AVI ", 1000);
  try {
    CheckAviWritten(path);
    ADD_FAILURE() << "a cut AVI passed";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": write failed: 1012 bytes, its header says 5012"),
              std::string::npos)
        << e.what();
  }
  write("RIFX", 4 + 1000, "AVI ", 1000);
  EXPECT_THROW(CheckAviWritten(path), OutputError);
  write("RIFF", 4 + 1000, "WAVE", 1000);
  EXPECT_THROW(CheckAviWritten(path), OutputError);
}

// `freespace run` keeps its stage times in fixed memory: the histogram's quantiles stay within
// half a bin (0.5 %) of the exact ones over a long, spread-out series.
TEST(StageHistogram, QuantilesMatchTheExactOnesWithinHalfABin) {
  std::mt19937 random(7);
  std::lognormal_distribution<double> times(std::log(800.0), 0.6);
  StageSeries exact;
  StageHistogram histogram;
  for (int i = 0; i < 100000; ++i) {
    StageTimes t;
    t.preprocess_us = times(random) / 10;
    t.align_us = 3.0;
    t.rasterize_us = times(random);
    t.fuse_us = times(random) * 2;
    t.classify_us = times(random);
    t.mask_us = 0.0;  // a stage that does not run
    t.insight_us = times(random) / 3;
    t.polygon_us = times(random) / 50;
    t.total_us = t.preprocess_us + t.rasterize_us + t.fuse_us + t.classify_us + t.insight_us;
    exact.Add(t);
    histogram.Add(t);
  }
  EXPECT_EQ(histogram.size(), 100000u);
  const nlohmann::json a = exact.Summary(), b = histogram.Summary();
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [stage, stats] : a.items()) {
    for (const char* q : {"median", "p99"}) {
      const double want = stats.at(q).get<double>(), got = b.at(stage).at(q).get<double>();
      EXPECT_NEAR(got, want, 0.005 * want + 0.01) << stage << " " << q;
    }
  }
  EXPECT_EQ(b.at("mask").at("median").get<double>(), 0.0);
  EXPECT_NEAR(histogram.MedianTotal(), exact.MedianTotal(), 0.005 * exact.MedianTotal());
}

}  // namespace
}  // namespace freespace
