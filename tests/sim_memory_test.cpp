// Long drives in bounded memory: the truth file written scan by scan holds the bytes of the
// whole document dumped at once; `freespace simulate`'s drive (WriteDrive) holds no more heap
// at its peak for a drive four times as long, where holding the whole document does; and the
// laps of a soak run join into one continuous drive.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "alloc_counter.hpp"
#include "geometry/geometry.hpp"
#include "sim/laps.hpp"
#include "sim/simulator.hpp"
#include "sim/truth.hpp"
#include "test_util.hpp"

namespace freespace::sim {
namespace {

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

SimulationOptions Drive(double seconds, bool keep) {
  SimulationOptions options;
  options.scenario = "urban";
  options.seed = 3;
  options.duration_s = seconds;
  options.odometry = OdometryNoise::Preset("typical");
  options.keep_truth_scans = keep;
  return options;
}

// Simulates into `dir` as `freespace simulate` does; returns the peak heap bytes above those
// live before.
long PeakHeapOfWrittenDrive(const std::string& dir, double seconds) {
  std::filesystem::create_directories(dir);
  const long before = LiveHeapBytes();
  ResetPeakHeapBytes();
  {
    Simulation simulation(Drive(seconds, false));
    SimulationWriter writer(dir, simulation.truth());
    WriteDrive(&simulation, &writer);
    writer.Close();
  }
  return PeakHeapBytes() - before;
}

// The same drive held as the truth file was written before it was streamed: every scan's truth
// kept, then the whole JSON document built in memory (here: parsed back from the file) and its
// text.
long PeakHeapOfWholeDocument(const std::string& dir, double seconds) {
  std::filesystem::create_directories(dir);
  const long before = LiveHeapBytes();
  ResetPeakHeapBytes();
  {
    Simulation simulation(Drive(seconds, true));
    Scan scan;
    while (simulation.Next(&scan)) {
    }
    WriteTruth(dir + "/truth.json", simulation.truth());
    const std::string text = Slurp(dir + "/truth.json");
    const nlohmann::json document = nlohmann::json::parse(text);
    EXPECT_EQ(document.at("scans").size(), simulation.truth().scans.size());
  }
  return PeakHeapBytes() - before;
}

TEST(SimMemory, StreamedTruthIsTheWholeDocumentDumpedAtOnce) {
  const std::string dir = ::testing::TempDir() + "/sim_memory_stream";
  std::filesystem::create_directories(dir);
  Simulation kept(Drive(2.0, true));
  Simulation streamed(Drive(2.0, false));
  SimulationWriter writer(dir, streamed.truth());
  EXPECT_EQ(WriteDrive(&streamed, &writer), 51u);
  writer.Close();
  EXPECT_TRUE(streamed.truth().scans.empty());
  Scan scan;
  while (kept.Next(&scan)) {
  }
  ASSERT_EQ(kept.truth().scans.size(), 51u);
  EXPECT_EQ(kept.last().t, streamed.last().t);
  WriteTruth(dir + "/whole.json", kept.truth());
  const std::string text = Slurp(writer.truth_path());
  EXPECT_EQ(text, Slurp(dir + "/whole.json"));
  // And what WriteTruth writes is nlohmann's dump(1) of the document (the format until the
  // truth file was streamed).
  EXPECT_EQ(text, nlohmann::json::parse(text).dump(1) + "\n");
  const Truth read = ReadTruth(writer.truth_path());
  ASSERT_EQ(read.scans.size(), 51u);
  EXPECT_EQ(read.scans.back().movers.size(), kept.last().movers.size());
  // An empty drive is an empty "scans" array.
  Truth header = kept.truth();
  header.scans.clear();
  WriteTruth(dir + "/empty.json", header);
  const nlohmann::json empty = nlohmann::json::parse(Slurp(dir + "/empty.json"));
  EXPECT_TRUE(empty.at("scans").is_array() && empty.at("scans").empty());
  EXPECT_EQ(Slurp(dir + "/empty.json"), empty.dump(1) + "\n");
}

TEST(SimMemory, WrittenDriveHoldsNoMoreHeapWhenFourTimesLonger) {
  const std::string dir = ::testing::TempDir() + "/sim_memory_peak";
  const long short_peak = PeakHeapOfWrittenDrive(dir + "/short", 8.0);  // 201 scans
  const long long_peak = PeakHeapOfWrittenDrive(dir + "/long", 32.0);   // 801 scans
  const long whole_short = PeakHeapOfWholeDocument(dir + "/whole_short", 8.0);
  const long whole_long = PeakHeapOfWholeDocument(dir + "/whole_long", 32.0);
  std::printf("peak heap, kB: streamed %ld / %ld, whole document %ld / %ld (8 s / 32 s)\n",
              short_peak / 1024, long_peak / 1024, whole_short / 1024, whole_long / 1024);
  EXPECT_GT(short_peak, 0);
  // Streamed: the peak does not depend on the drive's length (within 2 % and 16 kB).
  EXPECT_LE(long_peak, short_peak + short_peak / 50 + 16 * 1024);
  // Held whole, the peak grows with the drive, by far more than the bound above allows.
  EXPECT_GT(whole_long - whole_short, 512 * 1024);
  // The files are the same either way.
  EXPECT_EQ(Slurp(dir + "/long/truth.json"), Slurp(dir + "/whole_long/truth.json"));
}

TEST(SimMemory, LapsJoinIntoOneDrive) {
  SimulationOptions options = Drive(1.0, true);  // laps of 26 scans
  DriveLaps laps(options, 60);
  EXPECT_FALSE(laps.options().keep_truth_scans);
  std::vector<Scan> drive;
  Scan scan;
  while (laps.Next(&scan)) drive.push_back(scan);
  ASSERT_EQ(drive.size(), 60u);
  EXPECT_EQ(laps.laps(), 3u);
  EXPECT_TRUE(laps.lap().truth().scans.empty());
  const double period = options.scanner.scan_period_s;
  for (std::size_t i = 1; i < drive.size(); ++i) {
    EXPECT_NEAR(drive[i].timestamp_s - drive[i - 1].timestamp_s, period, 1e-9) << i;
  }
  // Lap 1 is seed 4's drive moved onto the end of lap 0 (seed 3's): the same steps.
  options.seed = 4;
  Simulation second(options);
  std::vector<Scan> alone;
  while (second.Next(&scan)) alone.push_back(scan);
  ASSERT_EQ(alone.size(), 26u);
  EXPECT_NEAR(drive[26].pose.x, drive[25].pose.x, 1e-9);
  EXPECT_NEAR(drive[26].pose.y, drive[25].pose.y, 1e-9);
  for (std::size_t i = 1; i < 26; ++i) {
    const Pose2D a = Compose(Inverse(alone[i - 1].pose), alone[i].pose);
    const Pose2D b = Compose(Inverse(drive[25 + i].pose), drive[26 + i].pose);
    EXPECT_NEAR(a.x, b.x, 1e-6) << i;
    EXPECT_NEAR(a.y, b.y, 1e-6) << i;
    EXPECT_NEAR(a.yaw, b.yaw, 1e-9) << i;
    ASSERT_EQ(alone[i].points.size(), drive[26 + i].points.size());
    EXPECT_EQ(alone[i].points[100].range_m, drive[26 + i].points[100].range_m);
  }
}

}  // namespace
}  // namespace freespace::sim
