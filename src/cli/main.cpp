// `freespace`: the command-line tool. See `freespace --help` and the README.
#include <iostream>
#include <string>
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
      "Exit codes: 0 ok; 1 run stopped on bad input (--strict); 2 bad usage, config, log,\n"
      "backend (a failed devices --check) or output; 130 / 143 stopped by Ctrl-C / SIGTERM.\n"
      "Run `freespace <command> --help` for a command's options.");

  std::vector<freespace::cli::Command> commands;
  commands.push_back(freespace::cli::AddDemoCommand(app));
  commands.push_back(freespace::cli::AddRunCommand(app));
  commands.push_back(freespace::cli::AddBenchCommand(app));
  commands.push_back(freespace::cli::AddSimulateCommand(app));
  commands.push_back(freespace::cli::AddEvalCommand(app));
  commands.push_back(freespace::cli::AddDevicesCommand(app));
  freespace::cli::CheckNumbers(&app);

  // A first word that names no command (CLI11 would only say that one is required).
  if (argc > 1 && argv[1][0] != '-') {
    std::string names;
    bool known = false;
    for (const auto& command : commands) {
      known = known || command.app->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + command.app->get_name();
    }
    if (!known) {
      std::cerr << "freespace: no command '" << argv[1] << "' (commands: " << names
                << "; freespace --help)\n";
      return freespace::cli::kExitSetup;
    }
  }
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
