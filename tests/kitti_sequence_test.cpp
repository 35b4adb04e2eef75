// KITTI odometry sequences on folders the tests write: Velodyne frames of a synthetic scene (a
// wall across the road at world x = 20 m, a gap in the scan, ground points below the cut) with
// poses.txt, calib.txt and times.txt read back as scans at the poses of the matrices; the
// scan's echoes land on the wall in the world; folders with too few or too many poses, a
// malformed pose, an unreadable frame and no poses.txt reported; poses/NN.txt beside
// sequences/NN found; the layer-cut options change the cut; `freespace run` on a folder writes
// polygons and names a bad option.
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "freespace/errors.hpp"
#include "freespace/io.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

namespace fs = std::filesystem;

constexpr double kDeg = M_PI / 180.0;
constexpr double kWallX = 20.0;       // the wall, world metres
constexpr double kGapFromDeg = 10.0;  // no point at Velodyne azimuths [10, 20) deg
constexpr double kGapToDeg = 20.0;
constexpr double kMountYawDeg = 2.0;  // calib.txt's Velodyne heading in the vehicle
constexpr double kMountX = -0.27, kMountY = 0.02;

struct VehiclePose {
  double x, y, yaw;
};
const VehiclePose kPoses[] = {{0.0, 0.0, 0.0}, {1.0, 0.1, 0.05}, {2.5, -0.3, -0.1}};

std::string TempDir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("freespace_kitti_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

// The left camera's pose as KITTI writes it (3x4, row-major): the camera turned about its y
// axis (down) by -yaw, at (-y, height, x) in the first camera's frame (x right, y down, z
// forward).
std::string CameraPoseLine(const VehiclePose& p, double height) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  const double m[12] = {c, 0, -s, -p.y, 0, 1, 0, height, s, 0, c, p.x};
  std::ostringstream line;
  line << std::setprecision(17);
  for (int i = 0; i < 12; ++i) line << (i ? " " : "") << m[i];
  return line.str();
}

// The Velodyne's pose in the vehicle frame (the mount) at world pose `p`.
VehiclePose SensorInWorld(const VehiclePose& p) {
  const double c = std::cos(p.yaw), s = std::sin(p.yaw);
  return {p.x + c * kMountX - s * kMountY, p.y + s * kMountX + c * kMountY,
          p.yaw + kMountYawDeg * kDeg};
}

void WriteRecord(std::ofstream& out, double x, double y, double z) {
  const float v[4] = {float(x), float(y), float(z), 0.5f};
  out.write(reinterpret_cast<const char*>(v), sizeof v);
}

// One frame seen from `p`: per Velodyne azimuth at the bin centres of the ScaLa aperture (bar
// the gap) a point on the wall at each cut elevation, and a ground point at -8 deg half way.
void WriteFrame(const std::string& path, const VehiclePose& p) {
  std::ofstream out(path, std::ios::binary);
  const VehiclePose sensor = SensorInWorld(p);
  for (int k = 0; k <= 580; ++k) {
    const double a = -72.5 + 0.25 * k;
    if (a >= kGapFromDeg && a < kGapToDeg) continue;
    const double d = (kWallX - sensor.x) / std::cos(sensor.yaw + a * kDeg);
    for (double e : {-1.2, -0.4, 0.4, 1.2}) {
      WriteRecord(out, d * std::cos(a * kDeg), d * std::sin(a * kDeg), d * std::tan(e * kDeg));
    }
    const double g = d / 2;
    WriteRecord(out, g * std::cos(a * kDeg), g * std::sin(a * kDeg), g * std::tan(-8 * kDeg));
  }
}

struct SequenceSpec {
  bool velodyne_folder = true, calib = true, times = true;
  int frames = 3;
  int pose_lines = 3;
};

// calib.txt's Tr (Velodyne -> camera): the Velodyne's axes (x forward, y left, z up) turned by
// the mount yaw, then as camera axes, at the mount position.
std::string CalibTr() {
  const double c = std::cos(kMountYawDeg * kDeg), s = std::sin(kMountYawDeg * kDeg);
  const double m[12] = {-s, -c, 0, -kMountY, 0, 0, -1, -0.08, c, -s, 0, kMountX};
  std::ostringstream line;
  line << std::setprecision(17) << "Tr:";
  for (double v : m) line << " " << v;
  return line.str();
}

std::string WriteSequence(const std::string& name, const SequenceSpec& spec) {
  const std::string dir = TempDir(name);
  const std::string frames = spec.velodyne_folder ? dir + "/velodyne" : dir;
  fs::create_directories(frames);
  std::ofstream poses(dir + "/poses.txt"), times;
  if (spec.times) times.open(dir + "/times.txt");
  for (int i = 0; i < spec.frames; ++i) {
    char file[32];
    std::snprintf(file, sizeof file, "/%06d.bin", i);
    WriteFrame(frames + file, kPoses[i % 3]);
    if (spec.times) times << std::setprecision(10) << 0.103 * i + 1.0e-3 << "\n";
  }
  for (int i = 0; i < spec.pose_lines; ++i)
    poses << CameraPoseLine(kPoses[i % 3], 0.02 * i) << "\n";
  if (spec.calib) {
    std::ofstream calib(dir + "/calib.txt");
    calib << "P0: 718.856 0 607.1928 0 0 718.856 185.2157 0 0 0 1 0\n" << CalibTr() << "\n";
  }
  return dir;
}

std::vector<Scan> ReadAll(LogReader& reader) {
  std::vector<Scan> scans;
  Scan scan;
  while (reader.Next(&scan)) scans.push_back(scan);
  return scans;
}

std::string Issues(LogReader& reader) {
  std::string all;
  for (const LogIssue& issue : reader.TakeIssues()) all += issue.ToString() + "\n";
  return all;
}

TEST(KittiSequence, FramesComeAtThePosesOfTheMatrices) {
  const std::string dir = WriteSequence("good", {});
  auto reader = OpenLog(dir);
  EXPECT_TRUE(reader->cuts_by_elevation());
  const SensorConfig& s = reader->sensor();
  EXPECT_EQ(s.layers, 4);
  EXPECT_NEAR(s.mount_x_m, kMountX, 1e-9);
  EXPECT_NEAR(s.mount_y_m, kMountY, 1e-9);
  EXPECT_NEAR(s.mount_yaw_deg, kMountYawDeg, 1e-9);
  const std::vector<Scan> scans = ReadAll(*reader);
  EXPECT_EQ(Issues(*reader), "");
  ASSERT_EQ(scans.size(), 3u);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const Scan& scan = scans[i];
    EXPECT_NEAR(scan.timestamp_s, 0.103 * double(i) + 1e-3, 1e-9);
    EXPECT_NEAR(scan.pose.x, kPoses[i].x, 1e-9);
    EXPECT_NEAR(scan.pose.y, kPoses[i].y, 1e-9);
    EXPECT_NEAR(scan.pose.yaw, kPoses[i].yaw, 1e-9);
    ASSERT_EQ(scan.points.size(), 4u * 581);
    // Every echo lies on the wall once put into the world through the pose and the mount; the
    // gap's beams (40 per layer) have none.
    const VehiclePose sensor = SensorInWorld(kPoses[i]);
    int no_echo = 0;
    for (const ScanPoint& p : scan.points) {
      if (!p.echo) {
        ++no_echo;
        const double a = p.angle_rad / kDeg;
        EXPECT_TRUE(a > kGapFromDeg - 0.2 && a < kGapToDeg) << a;
        continue;
      }
      const double x = sensor.x + p.range_m * std::cos(sensor.yaw + p.angle_rad);
      EXPECT_NEAR(x, kWallX, 1e-3) << "layer " << int(p.layer) << " at " << p.angle_rad / kDeg;
    }
    EXPECT_EQ(no_echo, 4 * 40);
  }
}

// Without times.txt or calib.txt the reader assumes them, and notes it: notes, not skipped
// input. A calib.txt without a usable Tr line is reported as input that could not be used.
TEST(KittiSequence, FramesInTheFolderWithoutTimesOrCalibAreReported) {
  const std::string dir = WriteSequence("flat", {false, false, false});
  auto reader = OpenLog(dir);
  EXPECT_EQ(reader->sensor().mount_x_m, 0.0);
  const std::vector<LogIssue> notes = reader->TakeIssues();
  std::string issues;
  for (const LogIssue& issue : notes) {
    issues += issue.ToString() + "\n";
    EXPECT_TRUE(issue.note) << issue.ToString();
  }
  EXPECT_NE(issues.find("no times.txt: frame n is taken at n * 0.1 s"), std::string::npos);
  EXPECT_NE(issues.find("no calib.txt: the Velodyne is taken at the left camera"),
            std::string::npos);
  std::ofstream(dir + "/calib.txt") << "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n";
  auto no_tr = OpenLog(dir);
  bool reported = false;
  for (const LogIssue& issue : no_tr->TakeIssues()) {
    if (issue.message.find("calib.txt has no Tr: line") == std::string::npos) continue;
    reported = true;
    EXPECT_FALSE(issue.note);
  }
  EXPECT_TRUE(reported);
  const std::vector<Scan> scans = ReadAll(*reader);
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_DOUBLE_EQ(scans[2].timestamp_s, 0.2);
  EXPECT_NEAR(scans[2].pose.x, kPoses[2].x, 1e-9);
}

TEST(KittiSequence, FramesWithoutAPoseAreReportedAndSkipped) {
  SequenceSpec spec;
  spec.pose_lines = 2;
  const std::string dir = WriteSequence("short", spec);
  auto reader = OpenLog(dir);
  EXPECT_EQ(ReadAll(*reader).size(), 2u);
  EXPECT_NE(Issues(*reader).find(":3: frame 000002.bin skipped: no pose (poses.txt has 2 lines)"),
            std::string::npos);

  spec.pose_lines = 5;
  auto longer = OpenLog(WriteSequence("long", spec));
  EXPECT_NE(Issues(*longer).find("poses.txt has 5 poses for frames 0 .. 2: the last 2 have no "
                                 "frame"),
            std::string::npos);
  EXPECT_EQ(ReadAll(*longer).size(), 3u);
}

TEST(KittiSequence, BadPoseLinesAndUnreadableFramesAreReportedAndSkipped) {
  const std::string dir = WriteSequence("bad", {});
  {
    std::ofstream poses(dir + "/poses.txt");
    poses << CameraPoseLine(kPoses[0], 0) << "\n1 0 0 0 0 1 0 0 0 0 1\n"
          << CameraPoseLine(kPoses[2], 0) << "\n";
  }
  fs::remove(dir + "/velodyne/000002.bin");
  fs::create_directory(dir + "/velodyne/000002.bin");  // a frame that cannot be read
  std::ofstream(dir + "/velodyne/notes.bin") << "x";
  auto reader = OpenLog(dir);
  const std::vector<Scan> scans = ReadAll(*reader);
  EXPECT_EQ(scans.size(), 1u);
  const std::string issues = Issues(*reader);
  EXPECT_NE(issues.find("poses.txt:2: 11 numbers where a 3x4 matrix has 12"), std::string::npos)
      << issues;
  EXPECT_NE(issues.find("frame 000001.bin skipped: no pose (poses.txt line 2 is not a pose)"),
            std::string::npos)
      << issues;
  EXPECT_NE(issues.find("frame 000002.bin skipped: cannot read"), std::string::npos) << issues;
  EXPECT_NE(issues.find("notes.bin skipped: not a frame number"), std::string::npos) << issues;
}

TEST(KittiSequence, AFolderWithoutPosesOrFramesIsRefused) {
  const std::string dir = WriteSequence("noposes", {});
  fs::remove(dir + "/poses.txt");
  EXPECT_THROW(
      {
        try {
          OpenLog(dir);
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("no poses.txt"), std::string::npos) << e.what();
          throw;
        }
      },
      InputError);
  EXPECT_THROW(OpenLog(TempDir("empty")), InputError);
}

TEST(KittiSequence, PosesFromTheBenchmarksOwnLayout) {
  // sequences/07/ with its poses in poses/07.txt, as the benchmark's downloads unpack.
  const std::string root = TempDir("layout");
  fs::create_directories(root + "/sequences");
  fs::create_directories(root + "/poses");
  fs::rename(WriteSequence("layout07", {}), root + "/sequences/07");
  fs::rename(root + "/sequences/07/poses.txt", root + "/poses/07.txt");
  auto reader = OpenLog(root + "/sequences/07/");
  const std::vector<Scan> scans = ReadAll(*reader);
  EXPECT_EQ(Issues(*reader), "");
  ASSERT_EQ(scans.size(), 3u);
  EXPECT_NEAR(scans[1].pose.x, kPoses[1].x, 1e-9);
  EXPECT_NEAR(scans[1].pose.yaw, kPoses[1].yaw, 1e-9);
}

TEST(KittiSequence, TheLayerCutOptionsChangeTheCut) {
  const std::string dir = WriteSequence("cut", {});
  LogOptions options;
  options.kitti_layer_elevations_deg = {-8.0};
  auto reader = OpenLog(dir, options);
  EXPECT_EQ(reader->sensor().layers, 1);
  Scan scan;
  ASSERT_TRUE(reader->Next(&scan));
  ASSERT_EQ(scan.points.size(), 581u);
  // Only the ground points, half way to the wall.
  const VehiclePose sensor = SensorInWorld(kPoses[0]);
  for (const ScanPoint& p : scan.points) {
    if (!p.echo) continue;
    EXPECT_NEAR(sensor.x + 2 * p.range_m * std::cos(sensor.yaw + p.angle_rad), kWallX, 2e-3);
  }
  // Two of the four wall layers with a narrow tolerance.
  options.kitti_layer_elevations_deg = {-0.4, 0.4};
  options.kitti_layer_tolerance_deg = 0.05;
  EXPECT_EQ(OpenLog(dir, options)->sensor().layers, 2);
  for (const auto& [elevations, tolerance] : std::vector<std::pair<std::vector<double>, double>>{
           {{}, 0.4}, {{0.4, -0.4}, 0.4}, {{0.0}, 0.0}, {{95.0}, 0.4}}) {
    options.kitti_layer_elevations_deg = elevations;
    options.kitti_layer_tolerance_deg = tolerance;
    EXPECT_THROW(OpenLog(dir, options), InputError);
  }
}

#ifdef FREESPACE_CLI_PATH
int RunCli(const std::string& args, const std::string& err) {
  const std::string command =
      std::string(FREESPACE_CLI_PATH) + " run --quiet --backend tbb " + args + " 2>" + err;
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(KittiSequence, RunOnAFolderWritesPolygons) {
  const std::string dir = WriteSequence("cli", {});
  const std::string out = TempDir("cli_out");
  ASSERT_EQ(RunCli("--log " + dir + " --out " + out, out + "/err"), 0) << ReadText(out + "/err");
  std::ifstream lines(out + "/polygons.jsonl");
  int n = 0, with_polygon = 0;
  for (std::string line; std::getline(lines, line); ++n) {
    with_polygon += line.find("\"polygon\":[[") != std::string::npos ? 1 : 0;
  }
  EXPECT_EQ(n, 3);
  EXPECT_EQ(with_polygon, 3);
  // The cut from the command line: one layer.
  EXPECT_EQ(RunCli("--log " + dir + " --out " + out + " --kitti-layers=-8", out + "/err"), 0);
  EXPECT_NE(ReadText(out + "/err").find(": 1 layer(s)"), std::string::npos);
  EXPECT_EQ(RunCli("--log " + dir + " --out " + out + " --kitti-layers=0.4,-0.4", out + "/err"), 2);
  EXPECT_NE(ReadText(out + "/err").find("--kitti-layers 0.4,-0.4: elevation -0.4 deg after 0.4"),
            std::string::npos)
      << ReadText(out + "/err");
  EXPECT_EQ(RunCli("--log " + dir + " --out " + out + " --kitti-layer-tolerance 0", out + "/err"),
            2);
  EXPECT_NE(ReadText(out + "/err").find("--kitti-layer-tolerance: tolerance 0 deg"),
            std::string::npos)
      << ReadText(out + "/err");
  // Too few poses: reported and skipped, or under --strict exit 1.
  std::ofstream(dir + "/poses.txt") << CameraPoseLine(kPoses[0], 0) << "\n";
  EXPECT_EQ(RunCli("--log " + dir + " --out " + out, out + "/err"), 0);
  EXPECT_NE(ReadText(out + "/err").find("frame 000001.bin skipped: no pose"), std::string::npos);
  EXPECT_EQ(RunCli("--strict --log " + dir + " --out " + out, out + "/err"), 1);
}
#endif

}  // namespace
}  // namespace freespace
