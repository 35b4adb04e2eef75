// Lap after lap of a scenario as one drive: see laps.hpp.
#include "sim/laps.hpp"

#include "geometry/geometry.hpp"

namespace freespace::sim {

DriveLaps::DriveLaps(const SimulationOptions& options, std::size_t scans)
    : options_(options), total_(scans) {
  options_.keep_truth_scans = false;  // nothing per scan: the drive may be any length
  StartLap();
}

void DriveLaps::StartLap() {
  SimulationOptions lap = options_;
  lap.seed = options_.seed + laps_;
  lap_ = std::make_unique<Simulation>(lap);
  ++laps_;
  first_of_lap_ = true;
}

bool DriveLaps::Next(Scan* scan) {
  if (done_ >= total_) return false;
  if (!lap_->Next(scan)) {
    StartLap();
    if (!lap_->Next(scan)) return false;  // a lap of no scans (cannot happen: count >= 1)
  }
  if (first_of_lap_) {
    first_of_lap_ = false;
    if (done_ == 0) {
      carry_ = Pose2D{};
      t_offset_ = 0.0;
    } else {
      // The lap's first pose lands on the drive's last one, one scan period later.
      carry_ = Compose(last_pose_, Inverse(scan->pose));
      t_offset_ = last_t_ + options_.scanner.scan_period_s - scan->timestamp_s;
    }
  }
  scan->pose = Compose(carry_, scan->pose);
  scan->timestamp_s += t_offset_;
  last_pose_ = scan->pose;
  last_t_ = scan->timestamp_s;
  ++done_;
  return true;
}

}  // namespace freespace::sim
