// What the engine-running commands share: the engine options (--config, --set, --backend,
// --threads, --opencl-wait, --opencl-devices), the config they make, and creating the output
// folder.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "freespace/config.hpp"

namespace freespace::cli {

// Options every engine-running command shares.
struct EngineOptions {
  std::string config_path;
  std::string backend;                // empty = as configured
  int threads = -1;                   // -1 = as configured
  std::string opencl_wait;            // empty = as configured
  int opencl_devices = 0;             // 0 = as configured
  std::vector<std::string> settings;  // --set section.field=value, in order
};
void AddEngineOptions(CLI::App* command, EngineOptions* options);

// The config of a command: `base` (the defaults unless a command has its own), replaced by
// --config (whose missing fields keep the defaults); when the config file has neither a `sensor`
// section nor a `sensors` list and `log_sensor` is given, the sensor comes from the log; then
// the --set fields, then --backend / --threads / --opencl-wait / --opencl-devices. Throws
// ConfigError.
Config LoadEngineConfig(const EngineOptions& options, const SensorConfig* log_sensor,
                        const Config& base = Config());

// The same with the sensors of a log or a simulated drive: one sensor, or a rig (several, with
// its vehicle, which a `rig` section of the config file replaces).
struct LogSensors {
  std::vector<SensorConfig> sensors;
  RigConfig rig;
};
Config LoadEngineConfig(const EngineOptions& options, const LogSensors& log,
                        const Config& base = Config());

// When the config's one sensor replaced a log's one sensor of another geometry (layers,
// aperture, beam spacing, ranges): a line that says both, and that the fields a partial `sensor`
// section leaves out keep the defaults, not the log's. Empty otherwise.
std::string SensorReplacedNote(const std::vector<SensorConfig>& log, const Config& config);

// Whether the file of --config has a `sensor` section or a `sensors` list (false without
// --config). Throws ConfigError when it cannot be read.
bool ConfigSetsSensor(const EngineOptions& options);

// Throws ConfigError when a --set names a sensor field where the command takes the sensor from
// a simulated drive instead (`what`: the command and why), which would leave it unread.
void RefuseSensorSettings(const EngineOptions& options, const std::string& what);
// The same for a simulated rig of several scanners (`rig`: its name), whose scanners and vehicle
// replace a config's `sensor`, `sensors` and `rig` sections: --set sensor.* and rig.* refused.
void RefuseSimulatedRigSettings(const EngineOptions& options, const std::string& rig);

// Creates `dir` (and parents); throws OutputError when it cannot.
void MakeDirectories(const std::string& dir);

}  // namespace freespace::cli
