// Every parameter of every stage, with units, valid ranges and the paper's defaults.
// A Config is plain data; Validate() checks it once and throws ConfigError naming the field
// and the bad value. The Estimator validates the config it is given.
#pragma once

#include <string>
#include <vector>

namespace freespace {

// The local occupancy grid (paper: 300 x 300 cells at 0.2 m).
struct MapConfig {
  int width_cells = 300;      // columns, along world x; 2 .. 8192
  int height_cells = 300;     // rows, along world y; 2 .. 8192
  double resolution_m = 0.2;  // edge of a square cell in metres; (0, 10]
};

// The laser scanner (defaults: Valeo ScaLa, paper section V.A).
struct SensorConfig {
  std::string name = "front";            // names the sensor in a rig (Config::sensors)
  int layers = 4;                        // points with layer >= layers are dropped; 1 .. 255
  double min_angle_deg = -72.5;          // horizontal aperture, sensor frame, CCW
  double max_angle_deg = 72.5;           // (min_angle, min_angle + 360]
  double angular_resolution_deg = 0.25;  // beam spacing; beams are grouped by this; (0, 10]
  double min_range_m = 0.1;              // echoes closer than this are invalid; >= 0
  double max_range_m = 150.0;            // echoes at or beyond max - margin are "no echo"
  double no_echo_margin_m = 0.01;        // see max_range_m; >= 0
  double mount_x_m = 0.0;                // sensor position in the vehicle (odometry) frame
  double mount_y_m = 0.0;
  double mount_yaw_deg = 0.0;  // sensor heading relative to the vehicle's
  // The time the beam takes to cross the aperture from min_angle_deg to max_angle_deg within one
  // scan (negative: from max to min), the scan's timestamp being the middle of the sweep. 0 (the
  // paper): every point is placed as if taken at the timestamp. Otherwise each point is placed
  // from where the sensor was when it was taken (docs/design.md); [-1, 1] s.
  double sweep_s = 0.0;
};

// DBSCAN clutter filter (paper section II): clusters of fewer than min_cluster_size points
// are clutter. Two echoes are neighbours when they are at most eps_m + eps_per_m * r apart,
// r being the larger of their ranges (far points of one wall are farther apart).
struct ClutterConfig {
  bool enabled = true;
  double eps_m = 0.2;        // (0, 100]
  double eps_per_m = 0.01;   // growth of eps with range, metres per metre; [0, 1)
  int min_points = 3;        // DBSCAN core-point threshold, the point itself included; >= 1
  int min_cluster_size = 5;  // paper: "less than 5 points empirically"; >= 1
};

enum class SensorModelKind {
  kEnhanced,      // full-scan polygon, each cell updated at most once per scan (paper II)
  kConventional,  // one Bresenham ray per point (the paper's baseline)
};

// Inverse sensor model probabilities (paper V.B: 0.40 / 0.5 / 0.65) and the clamp bounds of
// the log-odds map.
struct SensorModelConfig {
  SensorModelKind kind = SensorModelKind::kEnhanced;
  double p_free = 0.40;      // (p_min, 0.5)
  double p_occupied = 0.65;  // (0.5, p_max)
  double p_min = 0.03;       // lower clamp of a cell's probability; (0, 0.5)
  double p_max = 0.97;       // upper clamp; (0.5, 1)
  // The paper's rule: a cell whose centre is inside the scan's polygon is updated free. Off:
  // not when the polygon's outline between two beams touches the cell, which may hold the
  // obstacle's face (not in the paper; docs/design.md).
  bool free_on_outline = true;
};

enum class AlignmentKind {
  kCircle,  // vehicle on a circle: integer shifts only (paper III)
  kRotate,  // vehicle-centred map rotated and sub-pixel shifted (the paper's baseline)
};

// Vehicle on a circle (paper III, eqs. 1-7). The sensor origin is what the estimator places on
// the circle and calls "the vehicle".
struct AlignmentConfig {
  AlignmentKind kind = AlignmentKind::kCircle;
  int speed_window = 10;        // n of eq. (1): moving average of the last n speeds; 1 .. 1000
  double gain_s = 0.5;          // circle radius in metres per m/s of filtered speed; >= 0
  double margin_m = 2.0;        // the vehicle stays at least this far inside the map; >= 0
  double max_speed_mps = 70.0;  // a pose moving faster than this (plus slack) is a jump; > 0
  double jump_slack_m = 2.0;    // allowed extra displacement per scan; >= 0
  int reset_after_jumps = 5;    // consecutive jumps after which the map restarts there; >= 1
  double time_jitter_s = 1.0;   // a timestamp up to this much before the previous one is clock
                                // jitter: the scan is used without a speed sample; >= 0
  // Heading correction (not in the paper): each scan's heading is corrected by matching its
  // echoes to the occupied cells the map holds, and the correction carried to the next scan's
  // odometry pose, so that a drifting yaw (a gyro's yaw-rate bias) does not smear the map. The
  // result stays in the input poses' frame; the map is kept in the corrected one
  // (Result::pose_correction). Needs kind circle and one sensor.
  bool scan_match = false;
  // How fast the odometry's heading may drift, deg/s (a gyro's yaw-rate bias, wheel slip): the
  // correction takes more of each match the faster the heading can have drifted since the last
  // one, against how precisely the match fixes it. > 0.
  double heading_drift_dps = 0.1;
};

// Normalisation, neighbourhood hysteresis and morphological opening (paper IV.A).
struct ClassifyConfig {
  double t_low = 0.42;           // free if p <= t_low; (0, t_high]
  double t_high = 0.48;          // also free if p <= t_high next to a t_low cell; [t_low, 0.5)
  double vehicle_width_m = 1.8;  // opening element: a disk of about this width; >= 0
  // The cells holding an echo of the current scan (after the clutter filter) are not free in
  // this scan's free mask, whatever the map holds, so that the border rays and the polygon stop
  // in front of an obstacle that moved into space the map calls free. The map keeps the
  // paper's fusion.
  bool veto_current_echoes = true;
};

enum class PolygonShape {
  kPaper,   // vertices at the C_Edge cell centres (paper IV.B): edges run through the centres
            // of the first not-free cells, so the polygon covers about half of each
  kInside,  // conservative: the border rays cast exactly from the sensor on the free mask,
            // vertices where a ray first touches a not-free cell, the simplified polygon
            // pulled toward the sensor until it covers free cells only (docs/design.md)
};

// Free-space polygon: modified Douglas-Peucker (paper IV.B).
struct PolygonConfig {
  PolygonShape shape = PolygonShape::kPaper;
  int max_vertices = 32;   // N; 3 .. 4096
  double epsilon_m = 0.2;  // tolerance; >= 0
  // Safety margin of the inside polygon (not in the paper; 0 = none): a free cell is kept out
  // of the polygon when a cell the map holds occupied or unknown (log-odds >= 0) lies within
  // margin_cells of it (Chebyshev) and beyond it as seen from the sensor, within
  // margin_cone_deg of the line of sight through it (180: all around). The sensor's own cell
  // stays free. 0 .. 32 cells, needs shape inside; cone (0, 180] degrees.
  int margin_cells = 0;
  double margin_cone_deg = 180.0;
  // The face layer of the inside polygon (not in the paper; 0 = none): a cell within
  // face_tolerance_m of one of this scan's faces (its outline where it runs along a surface) is
  // kept out of the polygon, and a cell this scan's outline touches is no margin source: where
  // the scan sees the face, the face, not its cell, decides. 0 .. 1 m, needs shape inside.
  double face_tolerance_m = 0.0;
  // The mover layer of the inside polygon (not in the paper; 0 = none): a vehicle the scans saw
  // move into space an earlier scan saw free is followed at its speed, and the place it may be
  // now, out of the scanners' sight, is kept out of the polygon for up to mover_memory_s after
  // it was last seen. 0 .. 10 s, needs shape inside.
  double mover_memory_s = 0.0;
};

// The vehicle around a rig of several sensors (Config::sensors). With one `sensor` the
// estimator's reference point is that sensor's origin, as in the paper; with a rig it is this
// point of the vehicle frame: the vehicle on a circle, the border rays and the polygon's star
// centre. The footprint, a rectangle of the vehicle's size centred on the reference point and
// turned with the vehicle, is fused as free in every cycle: the vehicle stands there, and no
// scanner of a surround rig sees under it.
struct RigConfig {
  double reference_x_m = 0.0;  // the reference point in the vehicle (odometry) frame
  double reference_y_m = 0.0;
  double footprint_length_m = 0.0;  // 0: no footprint
  double footprint_width_m = 0.0;
};

// The most sensors of a rig.
inline constexpr int kMaxSensors = 16;

enum class BackendKind { kTbb, kOpenCl, kAuto };

// How the host waits for a scan's result from an OpenCL device (docs/opencl.md): blocking
// (the thread sleeps until a thread of the driver wakes it), spinning (it polls the result,
// keeping a core busy meanwhile), or auto: the way whose recent waits were shorter (each way
// timed on its own, the other one tried one wait in 32), a spin giving up after opencl_spin_us.
enum class OpenClWait { kAuto, kBlock, kSpin };

struct BackendConfig {
  BackendKind kind = BackendKind::kTbb;
  int threads = 0;              // TBB worker threads; 0 = all cores, in the caller's arena
  std::string opencl_platform;  // substring of the platform name; empty = first with a device
  std::string opencl_device;    // substring of the device name; empty = first
  OpenClWait opencl_wait = OpenClWait::kAuto;
  int opencl_spin_us = 250;  // auto's longest spin, microseconds; 0 (never spin) .. 100000
  // CPU devices to split the row pass, classification and in-sight scan over: the chosen one
  // and the next ones of its platform with the same name (PoCL lists two basic devices with
  // POCL_DEVICES="basic basic"), each driven by a thread of the backend's own. 1 .. 16;
  // FREESPACE_OPENCL_DEVICES overrides it.
  int opencl_devices = 1;
};

struct Config {
  MapConfig map;
  SensorConfig sensor;
  // Several sensors on one vehicle (docs/design.md, "A rig of sensors"): when not empty, the
  // rig, and `sensor` is not used; each Scan names its sensor by index into this list.
  std::vector<SensorConfig> sensors;
  RigConfig rig;
  ClutterConfig clutter;
  SensorModelConfig sensor_model;
  AlignmentConfig alignment;
  ClassifyConfig classify;
  PolygonConfig polygon;
  BackendConfig backend;

  // Throws ConfigError naming the first invalid field and its value (a rig's sensor as
  // sensors[name].field).
  void Validate() const;

  // The sensors scans come from: `sensors`, or `sensor` alone.
  bool is_rig() const { return !sensors.empty(); }
  int sensor_count() const { return is_rig() ? int(sensors.size()) : 1; }
  const SensorConfig& sensor_at(int i) const { return is_rig() ? sensors[i] : sensor; }

  // Reads a YAML document whose top-level keys are the section names above (map, sensor, ...)
  // and whose fields are the member names; missing fields keep their defaults, unknown keys
  // are errors. `source` names the text in messages. Throws ConfigError.
  static Config FromYaml(const std::string& yaml_text, const std::string& source = "config");
  static Config FromYamlFile(const std::string& path);

  // The full config as YAML, every field written (round-trips through FromYaml).
  std::string ToYaml() const;
};

// Checks one sensor on its own: each field within its range and the rules among its fields
// (not those with the rest of a config, such as the scan's reach in cells). Throws ConfigError
// ("config: sensor.<field> = <value>: <rule>").
void ValidateSensor(const SensorConfig& sensor);

// `config` with fields set by "section.field=value" texts, applied in order (the value as YAML
// reads a plain value: polygon.margin_cells=0, alignment.scan_match=true), each checked as a
// config file's field is; the result validated. A rig's sensors are not set this way. Throws
// ConfigError naming the setting.
Config WithSettings(const Config& config, const std::vector<std::string>& settings);

// The top-level sections present in a YAML config text (e.g. to tell whether it sets the
// sensor or leaves it to the log).
std::vector<std::string> YamlSections(const std::string& yaml_text);

const char* ToString(SensorModelKind kind);
const char* ToString(AlignmentKind kind);
const char* ToString(BackendKind kind);
const char* ToString(OpenClWait wait);
const char* ToString(PolygonShape shape);

}  // namespace freespace
