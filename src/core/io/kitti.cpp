// KITTI Velodyne frame reader: one .bin file (float32 x y z reflectance records, Velodyne
// frame: x forward, y left, z up) becomes one ScaLa-like scan: 4 layers picked by elevation
// near the horizon, azimuth cut to the ScaLa aperture and binned at its resolution; per layer
// and bin the nearest point is the echo, and a bin with no point is a beam without echo.
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <vector>

#include "freespace/errors.hpp"
#include "readers.hpp"

namespace freespace::io {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

class KittiReader final : public LogReader {
 public:
  KittiReader(const std::string& path, const LogOptions& options)
      : LogReader(path, LogFormat::kKitti) {
    sensor_ = SensorConfig{};  // ScaLa aperture and resolution
    sensor_.layers = int(options.kitti_layer_elevations_deg.size());
    sensor_.max_range_m = 120.0;  // HDL-64E
    sensor_.min_range_m = 1.0;    // returns from the car itself
    if (sensor_.layers < 1 || sensor_.layers > 255) {
      throw InputError(path + ": KITTI cut needs 1 to 255 layer elevations");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open");
    const int bins = int(std::floor((sensor_.max_angle_deg - sensor_.min_angle_deg) /
                                        sensor_.angular_resolution_deg +
                                    0.5)) +
                     1;
    const int layers = sensor_.layers;
    std::vector<float> nearest(std::size_t(bins) * layers, std::numeric_limits<float>::infinity());
    std::vector<float> angle(std::size_t(bins) * layers, 0.0f);
    // The file is read in chunks of whole records, never held at once (frames can be large).
    std::vector<char> chunk(16 * 4096);
    std::uint64_t size = 0;
    std::size_t not_finite = 0;
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
        AddRecord(v, options, bins, &nearest, &angle);
      }
    }
    if (size % 16 != 0) {
      Report(0, "size " + std::to_string(size) +
                    " is not a multiple of 16 bytes (x y z reflectance float32); the last " +
                    std::to_string(size % 16) + " bytes are ignored");
    }
    if (not_finite > 0) {
      Report(0, std::to_string(not_finite) + " records with non-finite coordinates ignored");
    }
    scan_.timestamp_s = 0.0;
    scan_.pose = {};
    scan_.points.reserve(std::size_t(bins) * layers);
    for (int l = 0; l < layers; ++l) {
      for (int b = 0; b < bins; ++b) {
        const std::size_t k = std::size_t(l) * bins + b;
        ScanPoint p;
        p.layer = std::uint8_t(l);
        p.echo = std::isfinite(nearest[k]);
        p.range_m = p.echo ? nearest[k] : 0.0f;
        p.angle_rad =
            p.echo
                ? angle[k]
                : float((sensor_.min_angle_deg + b * sensor_.angular_resolution_deg) / kRadToDeg);
        scan_.points.push_back(p);
      }
    }
  }

  // One record (x, y, z finite): the nearest horizontal range per layer and azimuth bin.
  void AddRecord(const float v[4], const LogOptions& options, int bins, std::vector<float>* nearest,
                 std::vector<float>* angle) const {
    const double horizontal = std::hypot(double(v[0]), double(v[1]));
    if (horizontal <= 0.0) return;
    const double elevation = std::atan2(double(v[2]), horizontal) * kRadToDeg;
    int layer = -1;
    double best = options.kitti_layer_tolerance_deg;
    for (int l = 0; l < sensor_.layers; ++l) {
      const double d = std::abs(elevation - options.kitti_layer_elevations_deg[l]);
      if (d <= best) {
        best = d;
        layer = l;
      }
    }
    if (layer < 0) return;
    const double azimuth = std::atan2(double(v[1]), double(v[0])) * kRadToDeg;
    const double b = (azimuth - sensor_.min_angle_deg) / sensor_.angular_resolution_deg;
    const long bin = std::lround(b);
    if (bin < 0 || bin >= bins) return;
    float& r = (*nearest)[std::size_t(layer) * bins + bin];
    if (horizontal < r) {
      r = float(horizontal);
      (*angle)[std::size_t(layer) * bins + bin] = float(azimuth / kRadToDeg);
    }
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
