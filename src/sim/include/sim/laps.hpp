// A drive of any length for soak runs: lap after lap of a built-in scenario, simulated one scan
// at a time, nothing kept per scan. Lap k is the scenario's drive with seed `seed + k` (its own
// world, traffic and noise); its poses are moved by one rigid transform so that it starts where
// lap k - 1 ended, and its times so that it starts one scan period later: to the estimator one
// continuous drive, whose surroundings change at each seam.
#pragma once

#include <cstddef>
#include <memory>

#include "freespace/scan.hpp"
#include "sim/simulator.hpp"

namespace freespace::sim {

class DriveLaps {
 public:
  // `scans` scans in all; options.duration_s is each lap's (0: the scenario's). Throws
  // std::invalid_argument for a bad scenario or option.
  DriveLaps(const SimulationOptions& options, std::size_t scans);

  // The next scan (pose: the odometry, carried onto the previous laps); false when done.
  bool Next(Scan* scan);

  std::size_t scan_count() const { return total_; }
  std::size_t done() const { return done_; }
  std::size_t laps() const { return laps_; }  // laps begun so far
  const SimulationOptions& options() const { return options_; }
  const Simulation& lap() const { return *lap_; }  // the lap being driven

 private:
  void StartLap();

  SimulationOptions options_;
  std::unique_ptr<Simulation> lap_;
  std::size_t total_ = 0, done_ = 0, laps_ = 0;
  bool first_of_lap_ = true;
  Pose2D carry_;         // lap pose -> drive pose
  double t_offset_ = 0;  // lap time -> drive time
  Pose2D last_pose_;     // the drive's last pose and time
  double last_t_ = 0;
};

}  // namespace freespace::sim
