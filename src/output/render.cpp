// Snapshot rendering with OpenCV.
#include "output/render.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "freespace/errors.hpp"

namespace freespace {

int SnapshotScale(int width, int height) { return std::max(1, 900 / std::max(width, height)); }

cv::Mat RenderSnapshot(const MapView& map, const Result& result, const SnapshotOverlay& overlay) {
  const int scale = SnapshotScale(map.width, map.height);
  cv::Mat grey(map.height, map.width, CV_8UC1);
  for (int r = 0; r < map.height; ++r) {
    std::uint8_t* out = grey.ptr<std::uint8_t>(map.height - 1 - r);
    for (int c = 0; c < map.width; ++c) {
      out[c] = std::uint8_t(std::lround(255.0 * (1.0 - map.Probability(r, c))));
    }
  }
  cv::Mat image;
  cv::cvtColor(grey, image, cv::COLOR_GRAY2BGR);
  cv::resize(image, image, cv::Size(), scale, scale, cv::INTER_NEAREST);

  // Cells (continuous) to pixels: y flipped so that north is up.
  const auto pixel = [&](const Vec2& cells) {
    return cv::Point(int(std::lround(cells.x() * scale)),
                     int(std::lround((map.height - cells.y()) * scale)));
  };
  const double c = std::cos(map.map_yaw), s = std::sin(map.map_yaw);
  const auto world_pixel = [&](const Vec2& world) {
    const Vec2 d = (world - map.origin) / map.resolution_m;
    return pixel(Vec2(c * d.x() + s * d.y(), -s * d.x() + c * d.y()));
  };

  if (overlay.truth != nullptr) {
    for (const auto& line : *overlay.truth) {
      std::vector<cv::Point> points;
      for (const Vec2& w : line) points.push_back(world_pixel(w));
      cv::polylines(image, points, false, cv::Scalar(40, 170, 40), 1, cv::LINE_AA);
    }
  }

  if (overlay.rays != nullptr) {
    static const cv::Scalar kColours[] = {{60, 60, 220},  {220, 120, 40}, {40, 160, 220},
                                          {180, 60, 180}, {60, 180, 120}, {120, 120, 120}};
    for (std::size_t k = 0; k < overlay.rays->size(); ++k) {
      const ScannerRays& scanner = (*overlay.rays)[k];
      const cv::Scalar& colour = kColours[k % (sizeof kColours / sizeof kColours[0])];
      const cv::Point origin = world_pixel(scanner.origin);
      for (const Vec2& e : scanner.echoes) {
        cv::line(image, origin, world_pixel(e), colour, 1, cv::LINE_4);
      }
      cv::circle(image, origin, std::max(2, scale), colour, -1, cv::LINE_AA);
    }
  }

  if (result.polygon_cells.size() >= 3) {
    std::vector<cv::Point> points;
    for (const Vec2& v : result.polygon_cells) points.push_back(pixel(v));
    cv::Mat fill = image.clone();
    cv::fillPoly(fill, std::vector<std::vector<cv::Point>>{points}, cv::Scalar(255, 200, 120),
                 cv::LINE_AA);
    cv::addWeighted(fill, 0.35, image, 0.65, 0.0, image);
    cv::polylines(image, points, true, cv::Scalar(200, 60, 0), 2, cv::LINE_AA);
    for (const cv::Point& p : points) cv::circle(image, p, 2, cv::Scalar(200, 60, 0), -1);
  }

  const double radius_px = result.circle_radius_m / map.resolution_m * scale;
  if (radius_px >= 1.0) {
    cv::circle(image, pixel(result.circle_centre_cells), int(std::lround(radius_px)),
               cv::Scalar(0, 200, 230), 1, cv::LINE_AA);
  }
  const cv::Point vehicle = pixel(result.vehicle_cells);
  const Vec2 heading(std::cos(result.yaw), std::sin(result.yaw));
  cv::arrowedLine(image, vehicle, pixel(result.vehicle_cells + heading * (12.0 / scale + 4.0)),
                  cv::Scalar(0, 200, 230), 2, cv::LINE_AA, 0, 0.3);
  cv::circle(image, vehicle, std::max(3, scale), cv::Scalar(0, 0, 230), -1, cv::LINE_AA);

  if (!overlay.caption.empty()) {
    cv::putText(image, overlay.caption, cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.5,
                cv::Scalar(255, 255, 255), 3, cv::LINE_AA);
    cv::putText(image, overlay.caption, cv::Point(8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.5,
                cv::Scalar(20, 20, 20), 1, cv::LINE_AA);
  }
  return image;
}

std::vector<ScannerRays> CycleRays(const std::vector<Scan>& scans, const Result& result, int step) {
  std::vector<ScannerRays> rays;
  for (std::size_t k = 0; k < result.cycle_sensors.size(); ++k) {
    const Pose2D& sensor = result.cycle_sensor_poses[k];
    ScannerRays r;
    r.origin = Vec2(sensor.x, sensor.y);
    for (const Scan& scan : scans) {
      if (scan.sensor != result.cycle_sensors[k]) continue;
      int n = 0;
      for (const ScanPoint& p : scan.points) {
        if (!p.echo || p.layer != 0 || n++ % step != 0) continue;
        const double a = sensor.yaw + double(p.angle_rad);
        r.echoes.push_back(r.origin + Vec2(std::cos(a), std::sin(a)) * double(p.range_m));
      }
    }
    rays.push_back(std::move(r));
  }
  return rays;
}

void WritePng(const std::string& path, const cv::Mat& image) {
  bool ok = false;
  try {
    ok = cv::imwrite(path, image);
  } catch (const cv::Exception& e) {
    throw OutputError(path + ": cannot write PNG: " + e.what());
  }
  if (!ok) throw OutputError(path + ": cannot write PNG");
}

}  // namespace freespace
