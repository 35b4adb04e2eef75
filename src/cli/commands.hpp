// The subcommands of the `freespace` command-line tool. Each Add* registers its options on
// `app` and returns the subcommand with the function that runs it (returning the exit code).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "freespace/config.hpp"

namespace freespace::cli {

// Exit codes: 0 success, 1 stopped on bad input (--strict) or a failed check, 2 usage or
// setup error (bad config, unreadable log, backend unavailable).
inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 1;
inline constexpr int kExitSetup = 2;

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command AddRunCommand(CLI::App& app);
Command AddBenchCommand(CLI::App& app);
Command AddSimulateCommand(CLI::App& app);
Command AddEvalCommand(CLI::App& app);
Command AddDemoCommand(CLI::App& app);
Command AddDevicesCommand(CLI::App& app);

// Options every engine-running command shares.
struct EngineOptions {
  std::string config_path;
  std::string backend;      // empty = as configured
  int threads = -1;         // -1 = as configured
  std::string opencl_wait;  // empty = as configured
  int opencl_devices = 0;   // 0 = as configured
};
void AddEngineOptions(CLI::App* command, EngineOptions* options);

// The config of a command: `base` (the defaults unless a command has its own), replaced by
// --config (whose missing fields keep the defaults), then overridden by --backend / --threads /
// --opencl-wait.
// When the config file has no `sensor` section and `log_sensor` is given, the sensor comes
// from the log. Throws ConfigError.
Config LoadEngineConfig(const EngineOptions& options, const SensorConfig* log_sensor,
                        const Config& base = Config());

// Creates `dir` (and parents); throws InputError when it cannot.
void MakeDirectories(const std::string& dir);

}  // namespace freespace::cli
