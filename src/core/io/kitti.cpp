// KITTI Velodyne frame reader: one .bin file (float32 x y z reflectance records, Velodyne
// frame: x forward, y left, z up) becomes one ScaLa-like scan at pose zero through the layer
// cut (core/layer_cut.hpp): layers picked by elevation near the horizon, azimuth cut to the
// ScaLa aperture and binned at its resolution; per layer and bin the nearest point is the echo,
// and a bin with no point is a beam without echo.
#include "kitti.hpp"

#include <cmath>
#include <cstring>
#include <fstream>

#include "freespace/errors.hpp"
#include "readers.hpp"

namespace freespace::io {

SensorConfig KittiSensor(const LogOptions& options, const std::string& path) {
  const std::string why =
      CheckElevationCut(options.kitti_layer_elevations_deg, options.kitti_layer_tolerance_deg);
  if (!why.empty()) {
    throw InputError(path + ": KITTI layer cut (kitti_layer_elevations_deg, " +
                     "kitti_layer_tolerance_deg): " + why);
  }
  SensorConfig sensor;  // ScaLa aperture and resolution
  sensor.layers = int(options.kitti_layer_elevations_deg.size());
  sensor.max_range_m = 120.0;  // HDL-64E
  sensor.min_range_m = 1.0;    // returns from the car itself
  return sensor;
}

// A coordinate farther than this from the sensor is no Velodyne point (HDL-64E: 120 m).
constexpr double kFarM = 1000.0;

bool CutVelodyneFrame(const std::string& path, LayerCut* cut, std::vector<std::string>* problems) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  // The file is read in chunks of whole records, never held at once (frames can be large).
  std::vector<char> chunk(16 * 4096);
  std::uint64_t size = 0;
  std::size_t not_finite = 0, far = 0;
  while (in) {
    in.read(chunk.data(), std::streamsize(chunk.size()));
    const std::size_t got = std::size_t(in.gcount());
    size += got;
    for (std::size_t i = 0; i + 16 <= got; i += 16) {
      float v[4];
      std::memcpy(v, chunk.data() + i, 16);
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
        ++not_finite;
        continue;
      }
      if (std::abs(v[0]) > kFarM || std::abs(v[1]) > kFarM || std::abs(v[2]) > kFarM) {
        ++far;
        continue;
      }
      cut->Add(v[0], v[1], v[2]);
    }
  }
  if (in.bad()) {
    problems->push_back("read error after " + std::to_string(size) + " bytes");
  }
  if (size % 16 != 0) {
    problems->push_back("size " + std::to_string(size) +
                        " is not a multiple of 16 bytes (x y z reflectance float32); the last " +
                        std::to_string(size % 16) + " bytes are ignored");
  }
  if (not_finite > 0) {
    problems->push_back(std::to_string(not_finite) +
                        " records with non-finite coordinates ignored");
  }
  if (far > 0) {
    problems->push_back(std::to_string(far) + " of " + std::to_string(size / 16) +
                        " records more than 1 km from the sensor ignored (a Velodyne frame " +
                        "holds none: is this one?)");
  }
  if (size < 16) {
    problems->push_back("no point (" + std::to_string(size) + " bytes)");
  } else if (cut->used() == 0) {
    problems->push_back("no point of its " + std::to_string(size / 16) +
                        " lies in a layer of the cut, within the aperture and beyond the " +
                        "minimum range (a scan of beams without echo)");
  }
  return true;
}

namespace {

class KittiReader final : public LogReader {
 public:
  KittiReader(const std::string& path, const LogOptions& options)
      : LogReader(path, LogFormat::kKitti) {
    cuts_by_elevation_ = true;
    sensor_ = KittiSensor(options, path);
    LayerCut cut(sensor_, options.kitti_layer_elevations_deg, options.kitti_layer_tolerance_deg);
    std::vector<std::string> problems;
    if (!CutVelodyneFrame(path, &cut, &problems)) throw InputError(path + ": cannot open");
    for (std::string& p : problems) Report(0, std::move(p));
    scan_.timestamp_s = 0.0;
    scan_.pose = {};
    cut.Fill(&scan_.points);
  }

  bool Next(Scan* scan) override {
    if (done_) return false;
    done_ = true;
    *scan = scan_;
    return true;
  }
  std::size_t line() const override { return 1; }
  double progress() const override { return done_ ? 1.0 : 0.0; }

 private:
  Scan scan_;
  bool done_ = false;
};

}  // namespace

std::unique_ptr<LogReader> OpenKitti(const std::string& path, const LogOptions& options) {
  return std::make_unique<KittiReader>(path, options);
}

}  // namespace freespace::io
