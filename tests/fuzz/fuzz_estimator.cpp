// libFuzzer target: the estimator on arbitrary scans. The bytes are read as a sequence of scans
// (timestamp, pose, then points of layer, angle, range, echo; raw doubles and floats, so NaN,
// infinities and extreme values all occur) on a small map and the TBB backend. The contract
// (include/freespace/estimator.hpp): Process() never throws; a scan it uses has a finite
// origin, a vehicle inside the map and a polygon of finite vertices within polygon.max_vertices.
// The same scans then go to a rig of two sensors (ProcessCycle), in cycles of two, the k-th
// scan from sensor k % 2, under the same contract.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "freespace/estimator.hpp"

namespace {

// Reads fixed-size values from the input, zeros once it runs out.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  T Take() {
    T v{};
    const std::size_t n = std::min(sizeof v, size_ - at_);
    std::memcpy(&v, data_ + at_, n);
    at_ += n;
    return v;
  }
  bool empty() const { return at_ >= size_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

freespace::Config SmallConfig() {
  freespace::Config c;
  c.map.width_cells = 64;
  c.map.height_cells = 48;
  c.map.resolution_m = 0.25;
  c.sensor.layers = 2;
  c.sensor.min_angle_deg = -60;
  c.sensor.max_angle_deg = 60;
  c.sensor.angular_resolution_deg = 2;
  c.sensor.max_range_m = 20;
  c.alignment.margin_m = 2;
  c.backend.kind = freespace::BackendKind::kTbb;
  c.backend.threads = 1;
  return c;
}

// Two sensors, front and rear, with a footprint around the reference point.
freespace::Config RigConfig() {
  freespace::Config c = SmallConfig();
  freespace::SensorConfig front = c.sensor, rear = c.sensor;
  front.name = "front";
  front.mount_x_m = 2.0;
  rear.name = "rear";
  rear.mount_x_m = -1.0;
  rear.mount_yaw_deg = 180;
  c.sensors = {front, rear};
  c.rig.reference_x_m = 0.5;
  c.rig.footprint_length_m = 3.0;
  c.rig.footprint_width_m = 1.5;
  return c;
}

void Check(bool ok) {
  if (!ok) std::abort();
}

void CheckResult(const freespace::Result& r, const freespace::Config& c) {
  using freespace::ScanStatus;
  if (r.status == ScanStatus::kRejected) {
    Check(!r.message.empty() && r.polygon.empty());
    return;
  }
  Check(std::isfinite(r.origin.x()) && std::isfinite(r.origin.y()));
  Check(r.vehicle_cells.x() >= 0 && r.vehicle_cells.x() <= c.map.width_cells);
  Check(r.vehicle_cells.y() >= 0 && r.vehicle_cells.y() <= c.map.height_cells);
  Check(std::isfinite(r.filtered_speed_mps));
  Check(int(r.polygon.size()) <= c.polygon.max_vertices);
  for (const freespace::Vec2& v : r.polygon) Check(std::isfinite(v.x()) && std::isfinite(v.y()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const freespace::Config config = SmallConfig();
  static const std::unique_ptr<freespace::Estimator> estimator =
      std::make_unique<freespace::Estimator>(config);
  static const freespace::Config rig_config = RigConfig();
  static const std::unique_ptr<freespace::Estimator> rig =
      std::make_unique<freespace::Estimator>(rig_config);
  estimator->Reset();
  rig->Reset();
  Bytes in(data, size);
  freespace::Scan scan;
  std::vector<freespace::Scan> cycle;
  for (int k = 0; k < 16 && !in.empty(); ++k) {
    scan.timestamp_s = in.Take<double>();
    scan.pose.x = in.Take<double>();
    scan.pose.y = in.Take<double>();
    scan.pose.yaw = in.Take<double>();
    const int n = in.Take<std::uint8_t>();
    scan.points.resize(n);
    for (freespace::ScanPoint& p : scan.points) {
      p.layer = in.Take<std::uint8_t>() & 3;
      p.angle_rad = in.Take<float>();
      p.range_m = in.Take<float>();
      p.echo = in.Take<std::uint8_t>() & 1;
    }
    CheckResult(estimator->Process(scan), config);
    cycle.push_back(scan);
    cycle.back().sensor = k % 2;
    if (cycle.size() == 2) {
      CheckResult(rig->ProcessCycle(cycle), rig_config);
      cycle.clear();
    }
  }
  if (!cycle.empty()) CheckResult(rig->ProcessCycle(cycle), rig_config);
  return 0;
}
