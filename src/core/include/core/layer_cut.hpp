// The cut of a 3-D point cloud into a ScaLa-like multi-layer scan, shared by the KITTI reader
// and the ROS PointCloud2 reader: each point joins a layer (the nearest configured elevation
// within a tolerance, or a layer given by the cloud's ring field), its azimuth is binned at the
// sensor's resolution inside its aperture, and per layer and bin the nearest point is the echo;
// a bin that no point reaches is a beam without echo.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "freespace/config.hpp"
#include "freespace/scan.hpp"

namespace freespace::io {

// Checks an elevation cut: 1 to 255 finite elevations in (-90, 90) deg, strictly increasing
// (layer 0 the lowest), and a finite tolerance in (0, 10] deg. Returns "" when valid, else what
// is wrong, for the caller to prefix with the option or field it came from.
std::string CheckElevationCut(const std::vector<double>& elevations_deg, double tolerance_deg);

// One scan's cut. Points are in the sensor frame: x forward, y left, z up, metres.
class LayerCut {
 public:
  // `sensor` gives the aperture, the resolution, the layer count and min_range_m (closer
  // points are the vehicle itself and never shadow a real echo). `elevations_deg` may be empty
  // when every point comes with its layer (AddOnLayer).
  LayerCut(const SensorConfig& sensor, std::vector<double> elevations_deg, double tolerance_deg);

  // Forgets the points added so far.
  void Clear();
  // Adds a point to the layer whose elevation is nearest (within the tolerance). Returns false
  // when the point falls in no layer, outside the aperture or within min_range_m.
  bool Add(double x, double y, double z);
  // Adds a point to `layer` (0 .. layers - 1), whatever its elevation; same return.
  bool AddOnLayer(int layer, double x, double y);
  // The scan's points: every layer's bins in order (layers x bins points), echoes at the
  // nearest horizontal range, empty bins as beams without echo at the bin's centre angle.
  void Fill(std::vector<ScanPoint>* points) const;

  int bins() const { return bins_; }
  int layers() const { return layers_; }
  // The points added since Clear() that became an echo candidate.
  std::size_t used() const { return used_; }

 private:
  SensorConfig sensor_;
  std::vector<double> elevations_deg_;
  double tolerance_deg_;
  int bins_ = 0, layers_ = 0;
  std::size_t used_ = 0;
  std::vector<float> nearest_;  // horizontal range per layer x bin, +inf when empty
  std::vector<float> angle_;    // the nearest point's azimuth, radians
};

}  // namespace freespace::io
