// The built-in scenarios, generated deterministically from a seed: a highway (three lanes,
// guard rails, a long curve, a broken-down car, slower traffic to overtake, a start from
// standstill to 130 km/h), an urban street (building fronts, parked cars, trees, poles,
// pedestrians, an intersection with a stop and a right turn) and a parking lot (rows of
// parked cars, a reversing manoeuvre into a bay and out again).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/trajectory.hpp"
#include "sim/world.hpp"

namespace freespace::sim {

struct Scenario {
  std::string name;
  std::string description;
  World world;
  Trajectory trajectory;  // the simulated vehicle's true motion (rear axle centre)
  double duration_s = 0.0;
};

// The scenario names BuildScenario() knows: "urban", "highway", "parking".
const std::vector<std::string>& ScenarioNames();

// Builds scenario `name` from `seed`: the same name and seed give the same world and drive.
// Throws std::invalid_argument for an unknown name.
Scenario BuildScenario(const std::string& name, std::uint64_t seed);

}  // namespace freespace::sim
