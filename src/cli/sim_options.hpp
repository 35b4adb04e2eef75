// Options shared by the commands that simulate a drive (`simulate`, `demo`): scenario, seed,
// duration, odometry noise and a few scanner settings.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "sim/simulator.hpp"

namespace freespace::cli {

struct SimOptions {
  std::string scenario = "urban";
  std::uint64_t seed = 1;
  double duration_s = 0.0;
  std::string odometry_noise = "none";
  std::string rig = "front";
  double speed_scale_error = NAN;
  double yaw_rate_bias_dps = NAN;
  double rain_probability = NAN;
  double ground_echo_probability = NAN;
};

void AddSimOptions(CLI::App* command, SimOptions* options);
// After AddSimOptions: every simulation option refused beside `by` (an option that reads a log
// instead of simulating a drive), which would leave them unread.
void ExcludeSimOptions(CLI::App* command, CLI::Option* by);
// After AddSimOptions: every simulation option refused without `by` (the option that makes the
// command simulate its drives).
void SimOptionsNeed(CLI::App* command, CLI::Option* by);

// The simulation options; throws std::invalid_argument for a bad value.
sim::SimulationOptions MakeSimulationOptions(const SimOptions& options);

// A count of the simulated points by source, for the command-line report.
struct EchoCounts {
  long scans = 0, points = 0, obstacle = 0, ground = 0, rain = 0, no_echo_range = 0,
       no_echo_weak = 0, no_echo_absorbed = 0;
  void Add(const std::vector<sim::EchoSource>& sources);
  std::string ToString() const;
};

}  // namespace freespace::cli
