// `freespace simulate`: simulates a drive of a built-in scenario and writes its logs
// (FREESPACE_LOG and ROBOTLASER1) and its truth file (docs/formats.md).
#include <chrono>
#include <iostream>

#include "commands.hpp"
#include "engine_options.hpp"
#include "freespace/errors.hpp"
#include "interrupt.hpp"
#include "sim_options.hpp"

namespace freespace::cli {
namespace {

struct SimulateOptions {
  SimOptions sim;
  std::string out = "out/sim";
};

// Ctrl-C (SIGINT) or SIGTERM stops the drive after the cycle at hand: the logs and the truth
// are closed whole with the cycles done, then the command ends by the signal.
int Simulate(const SimulateOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const InterruptGuard interrupt;
  int signal = 0;
  try {
    sim::SimulationOptions sim_options = MakeSimulationOptions(options.sim);
    sim_options.keep_truth_scans = false;  // written scan by scan: memory bounded
    sim::Simulation simulation(sim_options);
    MakeDirectories(options.out);
    sim::SimulationWriter writer(options.out, simulation.truth());
    std::cerr << "freespace simulate: " << simulation.scenario().name << " (seed "
              << options.sim.seed << "): " << simulation.scenario().description << "; "
              << simulation.scan_count() << " scans\n";
    EchoCounts counts;
    const std::size_t written = sim::WriteDrive(
        &simulation, &writer,
        [&counts](const std::vector<sim::EchoSource>& sources) { counts.Add(sources); },
        [&] { return (signal = interrupt.caught()) != 0; });
    writer.Close();
    if (signal != 0) {
      std::cerr << "freespace simulate: interrupted by " << SignalName(signal) << " after "
                << written << " of " << simulation.scan_count()
                << " cycles; the logs and the truth hold those\n";
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    std::cerr << "freespace simulate: " << counts.ToString() << "\n"
              << "freespace simulate: wrote " << writer.log_path()
              << (writer.writes_carmen() ? ", " + writer.carmen_path() : "") << " and "
              << writer.truth_path() << " in " << seconds << " s\n";
  } catch (const std::invalid_argument& e) {
    std::cerr << "freespace simulate: " << e.what() << "\n";
    return kExitSetup;
  } catch (const std::exception& e) {
    std::cerr << "freespace simulate: " << e.what() << "\n";
    return kExitSetup;
  }
  return interrupt.Finish(signal);
}

}  // namespace

Command AddSimulateCommand(CLI::App& app) {
  auto options = std::make_shared<SimulateOptions>();
  CLI::App* command = app.add_subcommand(
      "simulate",
      "Simulate a drive with a ScaLa-like scanner (4 layers, 145 deg at 0.25 deg, 150 m, 25 Hz)\n"
      "in a built-in scenario and write OUT/sim.fslog (FREESPACE_LOG; `freespace run` reads\n"
      "it), OUT/sim.clf (one ROBOTLASER1 line per layer) and OUT/truth.json (world, true\n"
      "poses; `freespace eval` scores against it). The same seed gives the same files.");
  AddSimOptions(command, &options->sim);
  command->add_option("--out", options->out, "Output directory")->capture_default_str();
  return {command, [options] { return Simulate(*options); }};
}

}  // namespace freespace::cli
