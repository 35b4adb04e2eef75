// The subcommands of the `freespace` command-line tool. Each Add* registers its options on
// `app` and returns the subcommand with the function that runs it (returning the exit code).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

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

}  // namespace freespace::cli
