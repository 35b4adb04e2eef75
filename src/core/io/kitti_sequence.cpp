// KITTI odometry benchmark sequence reader: a folder with the Velodyne frames
// (velodyne/NNNNNN.bin, or the .bin files in the folder itself), poses.txt (per frame the left
// camera's 3x4 pose in the first camera's frame, row-major), calib.txt (its Tr: line maps the
// Velodyne frame into the camera's) and times.txt (seconds per frame). Each frame becomes one
// scan through the KITTI layer cut, at the frame's planar pose. Camera frames (x right, y down,
// z forward) become vehicle frames (x forward, y left, yaw about up): the vehicle is the left
// camera, the world the first frame's camera. Frames are read one at a time.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include "freespace/errors.hpp"
#include "kitti.hpp"
#include "readers.hpp"
#include "text.hpp"

namespace freespace::io {
namespace {

namespace fs = std::filesystem;

// KITTI's Velodyne turns at 10 Hz: the frame period when there is no times.txt.
constexpr double kDefaultPeriodS = 0.1;

// A 3x4 row-major matrix [R | t] from a line of 12 numbers (after `skip` leading fields).
bool ParseMatrix(const std::string& line, std::size_t skip, double m[12], std::string* why) {
  std::vector<std::string_view> fields;
  SplitFields(line, &fields);
  if (fields.size() != 12 + skip) {
    *why = std::to_string(fields.size() - std::min(skip, fields.size())) +
           " numbers where a 3x4 matrix has 12";
    return false;
  }
  for (int i = 0; i < 12; ++i) {
    if (!ParseDouble(fields[skip + i], &m[i]) || !std::isfinite(m[i])) {
      *why = "field " + std::to_string(i + 1) + " '" + Excerpt(fields[skip + i]) +
             "' is not a finite number";
      return false;
    }
  }
  return true;
}

// The vehicle's planar pose from a camera pose: position (t_z, -t_x), heading the camera's
// optical axis (R_02, R_12, R_22) seen from above.
// (+ 0.0 turns the -0 of a zero entry into 0.)
Pose2D PoseFromCamera(const double m[12]) {
  return {m[11] + 0.0, -m[3] + 0.0, std::atan2(-m[2], m[10]) + 0.0};
}

// A frame number from a file stem of digits only ("000042" -> 42).
std::optional<long> FrameNumber(const std::string& stem) {
  if (stem.empty() || stem.size() > 12) return std::nullopt;
  for (char c : stem) {
    if (c < '0' || c > '9') return std::nullopt;
  }
  return std::stol(stem);
}

class KittiSequenceReader final : public LogReader {
 public:
  KittiSequenceReader(const std::string& dir, const LogOptions& options)
      : LogReader(dir, LogFormat::kKitti),
        cut_(KittiSensor(options, dir), options.kitti_layer_elevations_deg,
             options.kitti_layer_tolerance_deg) {
    cuts_by_elevation_ = true;
    sensor_ = KittiSensor(options, dir);
    ListFrames();
    ReadPoses();
    ReadTimes();
    ReadMount();
  }

  bool Next(Scan* scan) override {
    while (next_ < frames_.size()) {
      const auto& [number, path] = frames_[next_++];
      current_ = number;
      const std::string name = fs::path(path).filename().string();
      if (std::size_t(number) >= poses_.size() || !poses_[number]) {
        Report(line(), "frame " + name + " skipped: no pose (" + PoseWhy(number) + ")");
        continue;
      }
      double t = kDefaultPeriodS * double(number);
      if (has_times_) {
        if (std::size_t(number) >= times_.size() || !times_[number]) {
          Report(line(), "frame " + name + " skipped: no time (times.txt has " +
                             std::to_string(times_.size()) + " lines)");
          continue;
        }
        t = *times_[number];
      }
      cut_.Clear();
      std::vector<std::string> problems;
      std::error_code error;
      if (!fs::is_regular_file(path, error) || !CutVelodyneFrame(path, &cut_, &problems)) {
        Report(line(), "frame " + name + " skipped: cannot read " + path);
        continue;
      }
      for (const std::string& p : problems) Report(line(), name + ": " + p);
      scan->timestamp_s = t;
      scan->pose = *poses_[number];
      cut_.Fill(&scan->points);
      return true;
    }
    return false;
  }

  // The 1-based line of poses.txt (and times.txt) of the last frame: its number + 1.
  std::size_t line() const override { return std::size_t(current_) + 1; }
  double progress() const override {
    return frames_.empty() ? 1.0 : double(next_) / double(frames_.size());
  }

 private:
  void ListFrames();
  void ReadPoses();
  void ReadTimes();
  void ReadMount();
  std::string PoseWhy(long number) const {
    if (std::size_t(number) >= poses_.size()) {
      return pose_file_ + " has " + std::to_string(poses_.size()) + " lines";
    }
    return pose_file_ + " line " + std::to_string(number + 1) + " is not a pose";
  }

  LayerCut cut_;
  std::string pose_file_ = "poses.txt";               // its name, for messages
  std::vector<std::pair<long, std::string>> frames_;  // (number, path), by number
  std::vector<std::optional<Pose2D>> poses_;          // by frame number
  std::vector<std::optional<double>> times_;          // by frame number
  bool has_times_ = false;
  std::size_t next_ = 0;
  long current_ = 0;
};

// The frames: velodyne/*.bin when there is a velodyne folder, else the folder's *.bin, in the
// order of their numbers. Names that are not numbers and gaps in the numbering are reported.
void KittiSequenceReader::ListFrames() {
  const fs::path root(path_);
  std::error_code error;
  const fs::path folder = fs::is_directory(root / "velodyne", error) ? root / "velodyne" : root;
  std::map<long, std::string> frames_by_number;
  for (const fs::directory_entry& e : fs::directory_iterator(folder, error)) {
    if (e.path().extension() != ".bin") continue;
    const std::optional<long> number = FrameNumber(e.path().stem().string());
    if (!number) {
      Report(0, e.path().filename().string() + " skipped: not a frame number (NNNNNN.bin)");
    } else if (!frames_by_number.emplace(*number, e.path().string()).second) {
      Report(0, e.path().filename().string() + " skipped: frame " + std::to_string(*number) +
                    " is also " + fs::path(frames_by_number[*number]).filename().string());
    }
  }
  if (error) throw InputError(folder.string() + ": cannot list: " + error.message());
  if (frames_by_number.empty()) {
    throw InputError(path_ + ": no KITTI frames (velodyne/NNNNNN.bin or NNNNNN.bin)");
  }
  long expected = 0;
  for (const auto& [number, path] : frames_by_number) {
    if (number > expected) {
      Report(0, "frames " + std::to_string(expected) + " .. " + std::to_string(number - 1) +
                    " are missing (no .bin file)");
    }
    expected = number + 1;
    frames_.emplace_back(number, path);
  }
}

// poses.txt in the folder, or the benchmark's own layout: sequences/NN/ beside poses/NN.txt.
void KittiSequenceReader::ReadPoses() {
  std::error_code error;
  const fs::path root = fs::absolute(fs::path(path_), error).lexically_normal();
  fs::path file = fs::path(path_) / "poses.txt";
  const fs::path folder = root.has_filename() ? root : root.parent_path();
  const fs::path benchmark =
      folder.parent_path().parent_path() / "poses" / (folder.filename().string() + ".txt");
  if (!fs::is_regular_file(file, error) && fs::is_regular_file(benchmark, error)) file = benchmark;
  pose_file_ = file.filename().string();
  std::ifstream in(file);
  if (!in) {
    throw InputError(path_ + ": no poses.txt (one 3x4 camera pose per frame; the benchmark's " +
                     "poses/NN.txt is taken from beside sequences/NN too)");
  }
  std::string text;
  double m[12];
  std::string why;
  while (std::getline(in, text)) {
    poses_.emplace_back();
    if (ParseMatrix(text, 0, m, &why)) {
      poses_.back() = PoseFromCamera(m);
    } else {
      Report(0, pose_file_ + ":" + std::to_string(poses_.size()) + ": " + why);
    }
  }
  const long frames_end = frames_.back().first + 1;
  if (long(poses_.size()) > frames_end) {
    Report(0, pose_file_ + " has " + std::to_string(poses_.size()) + " poses for frames 0 .. " +
                  std::to_string(frames_end - 1) + ": the last " +
                  std::to_string(long(poses_.size()) - frames_end) + " have no frame");
  }
}

// times.txt: one time (s) per line; without it frame n is at n * 0.1 s, and a note says so.
void KittiSequenceReader::ReadTimes() {
  std::ifstream in(fs::path(path_) / "times.txt");
  if (!in) {
    Note(0, "no times.txt: frame n is taken at n * 0.1 s (the Velodyne's 10 Hz)");
    return;
  }
  has_times_ = true;
  std::string text;
  std::vector<std::string_view> fields;
  while (std::getline(in, text)) {
    times_.emplace_back();
    SplitFields(text, &fields);
    double t = 0;
    if (fields.size() == 1 && ParseDouble(fields[0], &t) && std::isfinite(t)) {
      times_.back() = t;
    } else {
      Report(0, "times.txt:" + std::to_string(times_.size()) + ": '" + Excerpt(text) +
                    "' is not one time in seconds");
    }
  }
}

// The mount from calib.txt's Tr (Velodyne -> camera): the Velodyne's origin and x axis seen in
// the vehicle frame. Without it the Velodyne is taken at the camera, facing forward.
void KittiSequenceReader::ReadMount() {
  std::ifstream in(fs::path(path_) / "calib.txt");
  const bool found = bool(in);
  std::string text, why = found ? "calib.txt has no Tr: line" : "no calib.txt";
  double m[12];
  while (std::getline(in, text)) {
    if (text.rfind("Tr:", 0) != 0) continue;
    if (ParseMatrix(text, 1, m, &why)) {
      sensor_.mount_x_m = m[11];
      sensor_.mount_y_m = -m[3] + 0.0;
      sensor_.mount_yaw_deg = std::atan2(-m[0], m[8]) * 180.0 / M_PI + 0.0;
      return;
    }
    why = "calib.txt Tr: " + why;
    break;
  }
  const std::string assumed =
      ": the Velodyne is taken at the left camera, facing forward (mount zero)";
  if (found) {
    Report(0, why + assumed);  // a calib.txt that cannot be used
  } else {
    Note(0, why + assumed);
  }
}

}  // namespace

std::unique_ptr<LogReader> OpenKittiSequence(const std::string& dir, const LogOptions& options) {
  return std::make_unique<KittiSequenceReader>(dir, options);
}

}  // namespace freespace::io
