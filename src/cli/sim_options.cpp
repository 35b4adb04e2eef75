// Simulation options of the command line: see sim_options.hpp.
#include "sim_options.hpp"

#include <cmath>
#include <cstdio>

namespace freespace::cli {

void AddSimOptions(CLI::App* command, SimOptions* o) {
  command->add_option("--scenario", o->scenario, "Scenario")
      ->check(CLI::IsMember(sim::ScenarioNames()))
      ->capture_default_str();
  command->add_option("--seed", o->seed, "Seed of the world, the scanner noise and the odometry")
      ->capture_default_str();
  command
      ->add_option("--duration", o->duration_s,
                   "Seconds to drive (0: the scenario's own: urban 32, highway 35, parking 41.8)")
      ->check(CLI::Range(0.0, 3600.0));
  command
      ->add_option("--odometry-noise", o->odometry_noise,
                   "Odometry errors: none (the truth), typical (0.5 % speed scale, 0.1 deg/s "
                   "yaw-rate bias) or poor (2 %, 0.5 deg/s)")
      ->check(CLI::IsMember({"none", "typical", "poor"}))
      ->capture_default_str();
  command
      ->add_option("--rig", o->rig,
                   "Scanners on the car: front (one ScaLa-like scanner on the front bumper) or "
                   "surround (four at the corners, 360 deg; the engine fuses each cycle)")
      ->check(CLI::IsMember(sim::RigNames()))
      ->capture_default_str();
  command->add_option("--speed-scale-error", o->speed_scale_error,
                      "Overrides the preset's relative speed error (0.01 = +1 %)");
  command->add_option("--yaw-rate-bias", o->yaw_rate_bias_dps,
                      "Overrides the preset's yaw-rate bias, deg/s");
  command
      ->add_option("--rain-probability", o->rain_probability,
                   "Rain / dust echo probability per beam and layer (default 0.0005)")
      ->check(CLI::Range(0.0, 1.0));
  command
      ->add_option("--ground-echo-probability", o->ground_echo_probability,
                   "Echo probability of a beam reaching the road (default 0.03)")
      ->check(CLI::Range(0.0, 1.0));
}

namespace {
constexpr const char* kSimOptionNames[] = {"--scenario",
                                           "--seed",
                                           "--duration",
                                           "--odometry-noise",
                                           "--rig",
                                           "--speed-scale-error",
                                           "--yaw-rate-bias",
                                           "--rain-probability",
                                           "--ground-echo-probability"};
}  // namespace

void ExcludeSimOptions(CLI::App* command, CLI::Option* by) {
  for (const char* name : kSimOptionNames) {
    CLI::Option* option = command->get_option_no_throw(name);
    if (option != nullptr && !by->get_excludes().count(option)) by->excludes(option);
  }
}

void SimOptionsNeed(CLI::App* command, CLI::Option* by) {
  for (const char* name : kSimOptionNames) {
    CLI::Option* option = command->get_option_no_throw(name);
    if (option != nullptr) option->needs(by);
  }
}

sim::SimulationOptions MakeSimulationOptions(const SimOptions& o) {
  sim::SimulationOptions s;
  s.scenario = o.scenario;
  s.seed = o.seed;
  s.duration_s = o.duration_s;
  s.rig = o.rig;
  s.odometry = sim::OdometryNoise::Preset(o.odometry_noise);
  if (std::isfinite(o.speed_scale_error)) s.odometry.speed_scale_error = o.speed_scale_error;
  if (std::isfinite(o.yaw_rate_bias_dps)) s.odometry.yaw_rate_bias_dps = o.yaw_rate_bias_dps;
  if (std::isfinite(o.rain_probability)) s.scanner.rain_probability = o.rain_probability;
  if (std::isfinite(o.ground_echo_probability)) {
    s.scanner.ground_echo_probability = o.ground_echo_probability;
  }
  return s;
}

void EchoCounts::Add(const std::vector<sim::EchoSource>& sources) {
  ++scans;
  points += long(sources.size());
  for (const sim::EchoSource s : sources) {
    switch (s) {
      case sim::EchoSource::kObstacle:
        ++obstacle;
        break;
      case sim::EchoSource::kGround:
        ++ground;
        break;
      case sim::EchoSource::kRain:
        ++rain;
        break;
      case sim::EchoSource::kNoEchoRange:
        ++no_echo_range;
        break;
      case sim::EchoSource::kNoEchoWeak:
        ++no_echo_weak;
        break;
      case sim::EchoSource::kNoEchoAbsorbed:
        ++no_echo_absorbed;
        break;
    }
  }
}

std::string EchoCounts::ToString() const {
  const double n = scans > 0 ? double(scans) : 1.0;
  char text[400];
  std::snprintf(text, sizeof text,
                "per scan: %.0f beams, %.0f echoes (%.0f obstacle, %.1f ground, %.1f rain/dust), "
                "no echo %.0f (%.0f open or road, %.0f too weak, %.0f through glass)",
                points / n, (obstacle + ground + rain) / n, obstacle / n, ground / n, rain / n,
                (no_echo_range + no_echo_weak + no_echo_absorbed) / n, no_echo_range / n,
                no_echo_weak / n, no_echo_absorbed / n);
  return text;
}

}  // namespace freespace::cli
