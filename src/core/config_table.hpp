// The config's field table, shared by config.cpp (validation, writing, documentation) and
// config_yaml.cpp (reading): every field with its section, name, unit, valid range and doc
// line. Private to the core library.
#pragma once

#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "freespace/config.hpp"

namespace freespace::config_table {

template <class Enum>
struct EnumName {
  Enum value;
  const char* name;
};

constexpr EnumName<SensorModelKind> kSensorModelNames[] = {
    {SensorModelKind::kEnhanced, "enhanced"}, {SensorModelKind::kConventional, "conventional"}};
constexpr EnumName<AlignmentKind> kAlignmentNames[] = {{AlignmentKind::kCircle, "circle"},
                                                       {AlignmentKind::kRotate, "rotate"}};
constexpr EnumName<PolygonShape> kPolygonShapeNames[] = {{PolygonShape::kPaper, "paper"},
                                                         {PolygonShape::kInside, "inside"}};
constexpr EnumName<BackendKind> kBackendNames[] = {
    {BackendKind::kTbb, "tbb"}, {BackendKind::kOpenCl, "opencl"}, {BackendKind::kAuto, "auto"}};
constexpr EnumName<OpenClWait> kOpenClWaitNames[] = {
    {OpenClWait::kAuto, "auto"}, {OpenClWait::kBlock, "block"}, {OpenClWait::kSpin, "spin"}};

template <class Enum, std::size_t N>
const char* NameOf(const EnumName<Enum> (&names)[N], Enum value) {
  for (const auto& n : names) {
    if (n.value == value) return n.name;
  }
  return "?";
}

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The valid values of a numeric field: an interval whose bounds may be open, closed or absent
// (infinite). Every number must also be finite.
struct Range {
  double lo = -kInfinity;
  double hi = kInfinity;
  bool lo_open = false;
  bool hi_open = false;

  bool Contains(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  // "[1, 8192]", "(0, 10]", ">= 0", "> 0"; empty when unbounded.
  std::string Text() const;
};

constexpr Range Closed(double lo, double hi) { return {lo, hi, false, false}; }
constexpr Range Open(double lo, double hi) { return {lo, hi, true, true}; }
constexpr Range OpenClosed(double lo, double hi) { return {lo, hi, true, false}; }
constexpr Range ClosedOpen(double lo, double hi) { return {lo, hi, false, true}; }
constexpr Range AtLeast(double lo) { return {lo, kInfinity, false, false}; }
constexpr Range Above(double lo) { return {lo, kInfinity, true, false}; }
constexpr Range Finite() { return {}; }

// What the table says about a field besides its name and type.
struct Spec {
  const char* unit;  // "" when none
  Range range;       // numeric fields only
  const char* doc;   // one line
};

inline std::string Format(int v) { return std::to_string(v); }
// Six significant digits where they read back as v, else the shortest text that does (a refused
// 180.0000001 is not shown as 180); std::to_chars, free of the embedding process's locale.
inline std::string Format(double v) {
  char text[32];
  std::to_chars_result r =
      std::to_chars(text, text + sizeof text, v, std::chars_format::general, 6);
  double back = 0.0;
  std::from_chars(text, r.ptr, back);
  if (back != v && v == v) r = std::to_chars(text, text + sizeof text, v);
  return std::string(text, r.ptr);
}
inline std::string Format(bool v) { return v ? "true" : "false"; }
inline std::string Format(const std::string& v) { return "\"" + v + "\""; }

inline std::string Range::Text() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) {
    return (lo_open ? "(" : "[") + Format(lo) + ", " + Format(hi) + (hi_open ? ")" : "]");
  }
  if (has_lo) return (lo_open ? "> " : ">= ") + Format(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + Format(hi);
  return "";
}

template <class Enum, std::size_t N>
std::string AllowedNames(const EnumName<Enum> (&names)[N], const char* separator) {
  std::string allowed;
  for (const auto& n : names) allowed += (allowed.empty() ? "" : separator) + std::string(n.name);
  return allowed;
}

// The field table, a section at a time. Visits every field with its name, the member and its
// Spec; the one place that lists them, so that reading, writing, the unknown-key check,
// validation and the documentation cannot drift apart. `C` is Config or const Config.
template <class C, class Visitor>
void VisitMap(C& m, Visitor& v) {
  v("width_cells", m.width_cells, {"cells", Closed(2, 8192), "map columns, along world x"});
  v("height_cells", m.height_cells, {"cells", Closed(2, 8192), "map rows, along world y"});
  v("resolution_m", m.resolution_m, {"m", OpenClosed(0, 10), "edge of a square cell"});
}

template <class C, class Visitor>
void VisitSensor(C& s, Visitor& v) {
  v("name", s.name, {"", {}, "the sensor's name in a rig (sensors list); scans name it by index"});
  v("layers", s.layers, {"", Closed(1, 255), "points of layer >= layers are dropped"});
  v("min_angle_deg", s.min_angle_deg,
    {"deg", Closed(-360, 360), "start of the horizontal aperture, sensor frame, CCW"});
  v("max_angle_deg", s.max_angle_deg, {"deg", Finite(), "end of the horizontal aperture"});
  v("angular_resolution_deg", s.angular_resolution_deg,
    {"deg", OpenClosed(0, 10), "beam spacing; beams (and the polygon's bins) are grouped by it"});
  v("min_range_m", s.min_range_m,
    {"m", AtLeast(0), "echoes closer than this are invalid (no echo)"});
  v("max_range_m", s.max_range_m,
    {"m", Finite(), "echoes at or beyond max_range_m - no_echo_margin_m are \"no echo\""});
  v("no_echo_margin_m", s.no_echo_margin_m, {"m", AtLeast(0), "see max_range_m"});
  v("mount_x_m", s.mount_x_m, {"m", Open(-100, 100), "sensor x in the vehicle (odometry) frame"});
  v("mount_y_m", s.mount_y_m, {"m", Open(-100, 100), "sensor y in the vehicle (odometry) frame"});
  v("mount_yaw_deg", s.mount_yaw_deg,
    {"deg", Closed(-360, 360), "sensor heading relative to the vehicle's"});
  v("sweep_s", s.sweep_s,
    {"s", Closed(-1, 1),
     "time the beam takes from min_angle_deg to max_angle_deg (negative: the other way) within a "
     "scan stamped at its middle; 0: every point at the timestamp (the paper)"});
}

template <class C, class Visitor>
void VisitClutter(C& k, Visitor& v) {
  v("enabled", k.enabled, {"", {}, "DBSCAN clutter filter on or off (paper II)"});
  v("eps_m", k.eps_m,
    {"m", OpenClosed(0, 100), "neighbour distance: eps_m + eps_per_m * the larger range"});
  v("eps_per_m", k.eps_per_m,
    {"m/m", ClosedOpen(0, 1), "growth of the neighbour distance with range"});
  v("min_points", k.min_points,
    {"points", AtLeast(1), "DBSCAN core-point threshold, the point itself included"});
  v("min_cluster_size", k.min_cluster_size,
    {"points", AtLeast(1), "smaller clusters are clutter (paper: 5)"});
}

template <class C, class Visitor>
void VisitSensorModel(C& m, Visitor& v) {
  v.Enum("kind", m.kind, kSensorModelNames,
         {"", {}, "inverse sensor model: the full-scan polygon (paper II) or a ray per point"});
  v("p_free", m.p_free, {"", Open(0, 0.5), "probability of a free cell (paper V.B)"});
  v("p_occupied", m.p_occupied,
    {"", Open(0.5, 1), "probability of a cell holding a kept echo (paper V.B)"});
  v("p_min", m.p_min, {"", Open(0, 0.5), "lower clamp of a cell's probability in the map"});
  v("p_max", m.p_max, {"", Open(0.5, 1), "upper clamp of a cell's probability in the map"});
  v("free_on_outline", m.free_on_outline,
    {"", {}, "full-scan polygon: a cell its outline touches is updated free (paper II) or not"});
}

template <class C, class Visitor>
void VisitAlignment(C& a, Visitor& v) {
  v.Enum("kind", a.kind, kAlignmentNames,
         {"", {}, "vehicle on a circle, integer shifts (paper III), or the rotated-map baseline"});
  v("speed_window", a.speed_window,
    {"scans", Closed(1, 1000), "n of eq. (1): moving average of the last n speeds"});
  v("gain_s", a.gain_s, {"s", AtLeast(0), "circle radius per m/s of filtered speed"});
  v("margin_m", a.margin_m, {"m", AtLeast(0), "the vehicle stays this far inside the map"});
  v("max_speed_mps", a.max_speed_mps,
    {"m/s", Above(0),
     "a pose moving faster than this (plus jump_slack_m) is a jump; the filtered speed is "
     "clamped to it"});
  v("jump_slack_m", a.jump_slack_m, {"m", AtLeast(0), "allowed extra displacement per scan"});
  v("reset_after_jumps", a.reset_after_jumps,
    {"scans", AtLeast(1),
     "pose jumps in a row (or scans in a row far behind the clock, each later than the one "
     "before: docs/behaviour.md) after which the map restarts at the last"});
  v("time_jitter_s", a.time_jitter_s,
    {"s", AtLeast(0), "a timestamp this much before the last is jitter: no speed sample"});
  v("scan_match", a.scan_match,
    {"", {}, "correct the odometry's heading by matching each scan to the map (not in the paper)"});
  v("heading_drift_dps", a.heading_drift_dps,
    {"deg/s", Above(0),
     "how fast the odometry's heading may drift (scan_match): the share of each match it takes"});
}

template <class C, class Visitor>
void VisitClassify(C& t, Visitor& v) {
  v("t_low", t.t_low, {"", Open(0, 0.5), "free if p <= t_low (paper IV.A)"});
  v("t_high", t.t_high,
    {"", Open(0, 0.5), "also free if p <= t_high next to a t_low cell; unknown is never free"});
  v("vehicle_width_m", t.vehicle_width_m,
    {"m", AtLeast(0),
     "opening element: a disk of about this width (an odd number of cells across)"});
  v("veto_current_echoes", t.veto_current_echoes,
    {"", {}, "this scan's echo cells are not free this scan, whatever the map holds"});
}

template <class C, class Visitor>
void VisitPolygon(C& p, Visitor& v) {
  v.Enum("shape", p.shape, kPolygonShapeNames,
         {"", {}, "C_Edge cell centres (paper IV.B) or conservative: free cells only"});
  v("max_vertices", p.max_vertices, {"", Closed(3, 4096), "N: most vertices of the polygon"});
  v("epsilon_m", p.epsilon_m,
    {"m", AtLeast(0),
     "simplification tolerance (Douglas-Peucker; shape inside: of the least-area drops)"});
  v("margin_cells", p.margin_cells,
    {"cells", Closed(0, 32),
     "safety margin in front of occupied and unknown cells (not in the paper; 0 = none)"});
  v("margin_cone_deg", p.margin_cone_deg,
    {"deg", OpenClosed(0, 180), "the margin's cone around the line of sight (180: all around)"});
  v("face_tolerance_m", p.face_tolerance_m,
    {"m", Closed(0, 1),
     "the polygon keeps out cells this near a face this scan sees (not in the paper; 0 = none)"});
  v("mover_memory_s", p.mover_memory_s,
    {"s", Closed(0, 10),
     "the polygon keeps out where a vehicle seen moving may be now, this long after it was "
     "last seen (not in the paper; 0 = none)"});
}

template <class C, class Visitor>
void VisitRig(C& r, Visitor& v) {
  v("reference_x_m", r.reference_x_m,
    {"m", Open(-100, 100), "a rig's reference point (circle, border rays) in the vehicle frame"});
  v("reference_y_m", r.reference_y_m,
    {"m", Open(-100, 100), "a rig's reference point, y in the vehicle frame"});
  v("footprint_length_m", r.footprint_length_m,
    {"m", Closed(0, 50), "a rig's vehicle footprint around the reference point, fused as free"});
  v("footprint_width_m", r.footprint_width_m, {"m", Closed(0, 50), "the footprint's width"});
}

template <class C, class Visitor>
void VisitBackend(C& b, Visitor& v) {
  v.Enum("kind", b.kind, kBackendNames, {"", {}, "compute backend"});
  v("threads", b.threads,
    {"", Closed(0, 1024),
     "TBB worker threads; 0 = all cores, in the calling thread's TBB arena; N > 0: the map stages "
     "and the clutter filter in an arena of N"});
  v("opencl_platform", b.opencl_platform,
    {"", {}, "substring of the OpenCL platform's name; empty = the first with a device"});
  v("opencl_device", b.opencl_device,
    {"", {}, "substring of the OpenCL device's name; empty = the first"});
  v.Enum("opencl_wait", b.opencl_wait, kOpenClWaitNames,
         {"", {}, "how the host waits for a scan's OpenCL result"});
  v("opencl_spin_us", b.opencl_spin_us,
    {"us", Closed(0, 100000), "auto's longest spin before it sleeps; 0 never spins"});
  v("opencl_devices", b.opencl_devices,
    {"", Closed(1, 16), "CPU devices to split the OpenCL backend's passes over"});
}

template <class C, class Visitor>
void VisitFields(C& c, Visitor&& v) {
  v.Section("map");
  VisitMap(c.map, v);
  v.Section("sensor");
  VisitSensor(c.sensor, v);
  v.Section("clutter");
  VisitClutter(c.clutter, v);
  v.Section("sensor_model");
  VisitSensorModel(c.sensor_model, v);
  v.Section("alignment");
  VisitAlignment(c.alignment, v);
  v.Section("classify");
  VisitClassify(c.classify, v);
  v.Section("polygon");
  VisitPolygon(c.polygon, v);
  v.Section("backend");
  VisitBackend(c.backend, v);
  v.Section("rig");
  VisitRig(c.rig, v);
}

// Collects the known field names per section, for the unknown-key check.
class KeyCollector {
 public:
  void Section(const char* name) {
    section_ = name;
    keys_[section_];
  }
  template <class T>
  void operator()(const char* name, const T&, const Spec&) {
    keys_[section_].insert(name);
  }
  template <class E, std::size_t N>
  void Enum(const char* name, E, const EnumName<E> (&)[N], const Spec&) {
    keys_[section_].insert(name);
  }
  const std::map<std::string, std::set<std::string>>& keys() const { return keys_; }

 private:
  std::string section_;
  std::map<std::string, std::set<std::string>> keys_;
};

}  // namespace freespace::config_table
