// Truth file reading and writing (JSON): see truth.hpp and docs/formats.md.
#include "sim/truth.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/stream_error.hpp"
#include "freespace/errors.hpp"
#include "geometry/geometry.hpp"

namespace freespace::sim {
namespace {

using nlohmann::json;

json PoseJson(const Pose2D& p) { return json::array({p.x, p.y, p.yaw}); }

Pose2D PoseFrom(const json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

json ScannerJson(const ScannerConfig& c) {
  return {{"layers", c.layers},
          {"layer_spacing_deg", c.layer_spacing_deg},
          {"beam_height_deg", c.beam_height_deg},
          {"min_angle_deg", c.min_angle_deg},
          {"max_angle_deg", c.max_angle_deg},
          {"resolution_deg", c.resolution_deg},
          {"min_range_m", c.min_range_m},
          {"max_range_m", c.max_range_m},
          {"range_resolution_m", c.range_resolution_m},
          {"range_sigma_m", c.range_sigma_m},
          {"scan_period_s", c.scan_period_s},
          {"sweep_s", c.sweep_s},
          {"mount_x_m", c.mount_x_m},
          {"mount_y_m", c.mount_y_m},
          {"mount_yaw_deg", c.mount_yaw_deg},
          {"mount_height_m", c.mount_height_m},
          {"mount_pitch_deg", c.mount_pitch_deg},
          {"pitch_per_accel_deg", c.pitch_per_accel_deg},
          {"pitch_sigma_deg", c.pitch_sigma_deg},
          {"pitch_correlation", c.pitch_correlation},
          {"ground_echo_probability", c.ground_echo_probability},
          {"rain_probability", c.rain_probability},
          {"rain_min_range_m", c.rain_min_range_m},
          {"rain_max_range_m", c.rain_max_range_m},
          {"detection_range_m", c.detection_range_m},
          {"detection_exponent", c.detection_exponent}};
}

template <typename T>
void Get(const json& j, const char* key, T* value) {
  if (j.contains(key)) *value = j.at(key).get<T>();
}

ScannerConfig ScannerFrom(const json& j) {
  ScannerConfig c;
  Get(j, "layers", &c.layers);
  Get(j, "layer_spacing_deg", &c.layer_spacing_deg);
  Get(j, "beam_height_deg", &c.beam_height_deg);
  Get(j, "min_angle_deg", &c.min_angle_deg);
  Get(j, "max_angle_deg", &c.max_angle_deg);
  Get(j, "resolution_deg", &c.resolution_deg);
  Get(j, "min_range_m", &c.min_range_m);
  Get(j, "max_range_m", &c.max_range_m);
  Get(j, "range_resolution_m", &c.range_resolution_m);
  Get(j, "range_sigma_m", &c.range_sigma_m);
  Get(j, "scan_period_s", &c.scan_period_s);
  Get(j, "sweep_s", &c.sweep_s);
  Get(j, "mount_x_m", &c.mount_x_m);
  Get(j, "mount_y_m", &c.mount_y_m);
  Get(j, "mount_yaw_deg", &c.mount_yaw_deg);
  Get(j, "mount_height_m", &c.mount_height_m);
  Get(j, "mount_pitch_deg", &c.mount_pitch_deg);
  Get(j, "pitch_per_accel_deg", &c.pitch_per_accel_deg);
  Get(j, "pitch_sigma_deg", &c.pitch_sigma_deg);
  Get(j, "pitch_correlation", &c.pitch_correlation);
  Get(j, "ground_echo_probability", &c.ground_echo_probability);
  Get(j, "rain_probability", &c.rain_probability);
  Get(j, "rain_min_range_m", &c.rain_min_range_m);
  Get(j, "rain_max_range_m", &c.rain_max_range_m);
  Get(j, "detection_range_m", &c.detection_range_m);
  Get(j, "detection_exponent", &c.detection_exponent);
  return c;
}

json ScanJson(const TruthScan& s) {
  json movers = json::array();
  for (const Pose2D& p : s.movers) movers.push_back(PoseJson(p));
  return {{"scan", s.index},
          {"t", s.t},
          {"pose", PoseJson(s.pose)},
          {"odometry", PoseJson(s.odometry)},
          {"sensor", PoseJson(s.sensor)},
          {"speed", s.speed},
          {"movers", movers}};
}

// The whole document but the scans, "scans" an empty array.
json HeaderJson(const Truth& truth) {
  json obstacles = json::array();
  for (const Obstacle& o : truth.world.obstacles) {
    json outline = json::array();
    for (const Vec2& p : o.shape) outline.push_back(json::array({p.x(), p.y()}));
    json j = {{"kind", ToString(o.kind)},
              {"z", json::array({o.z_min_m, o.z_max_m})},
              {"reflectivity", o.reflectivity},
              {"no_echo", o.no_echo_probability},
              {"polygon", outline}};
    if (o.mover >= 0) j["mover"] = o.mover;
    obstacles.push_back(std::move(j));
  }
  const OdometryNoise& n = truth.odometry_noise;
  return {{"format", "freespace-truth"},
          {"version", 1},
          {"scenario", truth.scenario},
          {"description", truth.description},
          {"seed", truth.seed},
          {"scanner", ScannerJson(truth.scanner)},
          {"rig", truth.rig.name},
          {"odometry_noise",
           {{"speed_scale_error", n.speed_scale_error},
            {"speed_sigma_mps", n.speed_sigma_mps},
            {"yaw_rate_bias_dps", n.yaw_rate_bias_dps},
            {"yaw_rate_sigma_dps", n.yaw_rate_sigma_dps}}},
          {"movers", truth.world.movers},
          {"obstacles", obstacles},
          {"scans", json::array()}};
}

}  // namespace

TruthWriter::TruthWriter(const std::string& path, const Truth& header) : path_(path) {
  errno = 0;
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) throw StreamError(path, "cannot create");
  // JSON strings hold no raw newline, so the top-level key is the one match.
  const std::string text = HeaderJson(header).dump(1);
  const std::string key = "\n \"scans\": [";
  const std::size_t split = text.find(key + "]") + key.size();
  out_ << text.substr(0, split);
  tail_ = text.substr(split);
  Check();
}

void TruthWriter::Add(const TruthScan& scan) {
  if (closed_) throw OutputError(path_ + ": written after Close()");
  // The scan at depth 2 of the document: each of its lines indented by two more spaces.
  const std::string text = ScanJson(scan).dump(1);
  std::string indented = scans_++ == 0 ? "\n  " : ",\n  ";
  indented.reserve(text.size() + text.size() / 4);
  for (const char c : text) {
    indented += c;
    if (c == '\n') indented += "  ";
  }
  errno = 0;
  out_ << indented;
  Check();
}

void TruthWriter::Close() {
  if (closed_) return;
  closed_ = true;
  errno = 0;
  if (scans_ > 0) out_ << "\n ";
  out_ << tail_ << "\n";
  out_.close();
  Check();
}

void TruthWriter::Check() {
  if (out_.fail()) throw StreamError(path_, "write failed");
}

void WriteTruth(const std::string& path, const Truth& truth) {
  TruthWriter writer(path, truth);
  for (const TruthScan& s : truth.scans) writer.Add(s);
  writer.Close();
}

Truth ReadTruth(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  Truth truth;
  try {
    const json doc = json::parse(in);
    if (doc.value("format", "") != "freespace-truth") {
      throw InputError(path + ": not a freespace truth file (no \"format\": \"freespace-truth\")");
    }
    if (doc.at("version").get<int>() != 1) {
      throw InputError(path + ": truth version " + doc.at("version").dump() +
                       " is not supported (this reader reads 1)");
    }
    truth.scenario = doc.value("scenario", "");
    truth.description = doc.value("description", "");
    truth.seed = doc.value("seed", std::uint64_t(0));
    truth.scanner = ScannerFrom(doc.at("scanner"));
    try {
      truth.rig = MakeRig(doc.value("rig", "front"), truth.scanner);
    } catch (const std::invalid_argument& e) {
      throw InputError(path + ": " + e.what());
    }
    if (doc.contains("odometry_noise")) {
      const json& n = doc.at("odometry_noise");
      Get(n, "speed_scale_error", &truth.odometry_noise.speed_scale_error);
      Get(n, "speed_sigma_mps", &truth.odometry_noise.speed_sigma_mps);
      Get(n, "yaw_rate_bias_dps", &truth.odometry_noise.yaw_rate_bias_dps);
      Get(n, "yaw_rate_sigma_dps", &truth.odometry_noise.yaw_rate_sigma_dps);
    }
    truth.world.movers = doc.at("movers").get<int>();
    for (const json& j : doc.at("obstacles")) {
      Obstacle o;
      o.kind = ObstacleKindFromString(j.at("kind").get<std::string>());
      o.z_min_m = j.at("z").at(0).get<double>();
      o.z_max_m = j.at("z").at(1).get<double>();
      o.reflectivity = j.value("reflectivity", 0.3);
      o.no_echo_probability = j.value("no_echo", 0.0);
      for (const json& p : j.at("polygon"))
        o.shape.emplace_back(p.at(0).get<double>(), p.at(1).get<double>());
      o.mover = j.value("mover", -1);
      if (o.mover >= truth.world.movers || o.shape.size() < 3) {
        throw InputError(path + ": obstacle " + std::to_string(truth.world.obstacles.size()) +
                         ": bad mover index or fewer than 3 vertices");
      }
      truth.world.obstacles.push_back(std::move(o));
    }
    for (const json& j : doc.at("scans")) {
      TruthScan s;
      s.index = j.at("scan").get<std::uint64_t>();
      s.t = j.at("t").get<double>();
      s.pose = PoseFrom(j.at("pose"));
      s.odometry = PoseFrom(j.at("odometry"));
      s.sensor = PoseFrom(j.at("sensor"));
      s.speed = j.value("speed", 0.0);
      for (const json& p : j.at("movers")) s.movers.push_back(PoseFrom(p));
      if (int(s.movers.size()) != truth.world.movers) {
        throw InputError(path + ": scan " + std::to_string(s.index) + " has " +
                         std::to_string(s.movers.size()) + " mover poses, expected " +
                         std::to_string(truth.world.movers));
      }
      truth.scans.push_back(std::move(s));
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path + ": not a valid truth file: " + e.what());
  }
  return truth;
}

Pose2D TruthToMapFrame(const TruthScan& scan) { return Compose(scan.odometry, Inverse(scan.pose)); }

}  // namespace freespace::sim
