// Preprocessing of one full scan on the host (DESIGN.md pipeline step 1): input validation,
// no-echo marking, DBSCAN clutter filter, virtual points for no-echo beams, and the
// projection of the full-scan polygon and the kept echoes into the map for kernel stage 1.
#pragma once

#include <cstdint>
#include <vector>

#include "core/backend.hpp"
#include "core/dbscan.hpp"
#include "core/face_layer.hpp"
#include "core/sweep.hpp"
#include "freespace/config.hpp"
#include "freespace/result.hpp"
#include "freespace/scan.hpp"

namespace freespace {

// One vertex of the full-scan polygon: the nearest kept echo of any layer in an angular bin,
// or a virtual point there (paper II: range min of the nearest real returns before and after).
struct Beam {
  float angle = 0.0f;  // radians, sensor frame
  float range = 0.0f;  // metres
  float x = 0.0f;      // the vertex in the sensor frame, metres
  float y = 0.0f;
  bool is_virtual = false;
};

// The beams of one layer a scan of `sensor` holds: the aperture in steps of the angular
// resolution, both ends included; a whole number, as a double so that any config's count is one
// (Config::Validate bounds it before the preprocessing takes it as an int).
double SensorBins(const SensorConfig& sensor);

class Preprocessor {
 public:
  explicit Preprocessor(const Config& config);

  // Validates and filters the scan's points (sensor frame) and builds the polygon's beams.
  // Fills the point counters of `stats`. Returns false when the scan has no kept echo, in
  // which case it makes no sensor update.
  bool Run(const Scan& scan, ScanStats* stats);

  // sensor.sweep_s: moves the beams and kept echoes of the last Run() to where they lie in the
  // sensor frame at the scan's timestamp, each taken at its angle's time in the sweep while
  // the sensor moved by `motion`. Does nothing when sweep_s is 0.
  void Deskew(const SweepMotion& motion);

  // The clutter filter's parallel passes on `crew` (Backend::HostCrew); nullptr: on TBB.
  void UseCrew(Crew* crew) { clutter_.UseCrew(crew); }

  // Projects the beams and kept echoes into the map: sensor at `sensor_cells` (map cells,
  // fractional) with heading `yaw`. Fills `job` with pointers into this object's buffers. With
  // `faces` false the face layer is left to ProjectFaces().
  void Project(const Vec2& sensor_cells, double yaw, int width, int height, RasterJob* job,
               bool faces = true);
  // The face layer of the outline the last Project() drew, on a map of width x height cells.
  void ProjectFaces(int width, int height);

  // The conventional model's rays: from the sensor's cell to each kept echo's cell.
  void ProjectRays(const Vec2& sensor_cells, double yaw, int width, int height, RayJob* job);

  const std::vector<Beam>& beams() const { return beams_; }
  // Echoes that survived the clutter filter (sensor frame).
  const std::vector<EchoPoint>& kept() const { return kept_; }
  // The map cells holding a kept echo (row * width + col), as the last Project() or
  // ProjectRays() found them; echoes outside the map left out.
  const std::vector<std::int32_t>& echo_cells() const { return occupied_; }
  // polygon.face_tolerance_m: the face layer of the last Project() (FaceCells()); empty when
  // off.
  const std::vector<std::int32_t>& face_near_cells() const { return face_near_; }
  const std::vector<std::int32_t>& face_seen_cells() const { return face_seen_; }
  int bins() const { return bins_; }

 private:
  SensorConfig sensor_;
  double resolution_m_;
  bool clear_outline_;  // !sensor_model.free_on_outline (RasterJob::clear_outline)
  FaceRule face_rule_;  // tolerance 0: no face layer
  double min_angle_;    // radians
  double bin_width_;    // radians
  int bins_;
  ClutterFilter clutter_;

  std::vector<EchoPoint> echoes_;
  std::vector<std::uint8_t> keep_;
  std::vector<EchoPoint> kept_;
  std::vector<std::uint8_t> bin_has_beam_;
  std::vector<float> bin_range_;        // nearest kept echo, +inf when none
  std::vector<std::int32_t> bin_echo_;  // index into kept_ of the nearest echo
  std::vector<double> bin_cos_;         // cos and sin of each bin's centre angle
  std::vector<double> bin_sin_;
  std::vector<Beam> beams_;
  std::vector<std::int32_t> vertices_;
  std::vector<std::int32_t> occupied_;
  std::vector<std::int32_t> ray_ends_;
  std::vector<std::int32_t> face_near_;
  std::vector<std::int32_t> face_seen_;
  std::vector<FaceLists> face_parts_;  // FaceCells() in parallel
};

}  // namespace freespace
