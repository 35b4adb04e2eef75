// `freespace`: the command-line tool. See `freespace --help` and the README.
#include <iostream>
#include <vector>

#include "commands.hpp"
#include "freespace/baselines.hpp"
#include "freespace/log.hpp"
#include "freespace/version.hpp"
#include "number_checks.hpp"

int main(int argc, char** argv) {
  freespace::RegisterBaselines();  // alignment.kind rotate, for configs that ask for it
  // The library never prints; the tool prints what it reports.
  freespace::SetLogCallback([](freespace::LogLevel level, const std::string& message) {
    std::cerr << "freespace: " << (level == freespace::LogLevel::kWarning ? "warning: " : "")
              << message << "\n";
  });
  CLI::App app{
      "freespace: static free-space detection with a laser scanner on occupancy grid maps.\n"
      "Turns full scans plus odometry into a local occupancy grid and one free-space polygon\n"
      "of at most N vertices per scan (Eraqi, Honer, Zuther)."};
  app.set_version_flag("--version", std::string("freespace ") + freespace::LibraryVersion());
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 ok; 1 stopped on bad input (--strict) or a failed check; 2 bad usage,\n"
      "config, log or backend. Run `freespace <command> --help` for a command's options.");

  std::vector<freespace::cli::Command> commands;
  commands.push_back(freespace::cli::AddDemoCommand(app));
  commands.push_back(freespace::cli::AddRunCommand(app));
  commands.push_back(freespace::cli::AddBenchCommand(app));
  commands.push_back(freespace::cli::AddSimulateCommand(app));
  commands.push_back(freespace::cli::AddEvalCommand(app));
  commands.push_back(freespace::cli::AddDevicesCommand(app));
  freespace::cli::CheckNumbers(&app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the help or the error; its own codes (105 for a failed check, ...) are
    // mapped onto the documented ones: a usage error is 2.
    return app.exit(e) == 0 ? freespace::cli::kExitOk : freespace::cli::kExitSetup;
  }
  for (auto& command : commands) {
    if (command.app->parsed()) return command.run();
  }
  return freespace::cli::kExitSetup;
}
