// A simulated drive, scan by scan: the scenario's world and trajectory, the scanner model and
// the odometry, producing the scans the estimator consumes (pose = odometry) and the truth of
// each. SimulationWriter stores them as the project's log formats plus the truth file.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "freespace/io.hpp"
#include "freespace/scan.hpp"
#include "sim/odometry.hpp"
#include "sim/scanner.hpp"
#include "sim/scenarios.hpp"
#include "sim/truth.hpp"

namespace freespace::sim {

struct SimulationOptions {
  std::string scenario = "urban";
  std::uint64_t seed = 1;
  double duration_s = 0.0;  // 0: the scenario's own duration
  OdometryNoise odometry;
  ScannerConfig scanner;
  // Keep every scan's truth in truth().scans (for scoring the drive in memory); false keeps
  // only the last scan's, so that memory does not grow with the drive.
  bool keep_truth_scans = true;
};

class Simulation {
 public:
  // Builds the scenario; throws std::invalid_argument for a bad name or option.
  explicit Simulation(const SimulationOptions& options);

  // Simulates the next scan into `scan` (pose: the odometry, rounded as the log writes it, so
  // that a log read back gives the same scans) and takes its truth (last(); appended to
  // truth().scans when kept). False when done.
  bool Next(Scan* scan, std::vector<EchoSource>* sources = nullptr);

  std::size_t scan_count() const { return count_; }  // scans the drive has
  const Scenario& scenario() const { return scenario_; }
  // The header and, with keep_truth_scans, the scans so far.
  const Truth& truth() const { return truth_; }
  const TruthScan& last() const { return last_; }  // the truth of the last scan

 private:
  SimulationOptions options_;
  Scenario scenario_;
  std::unique_ptr<ScanSimulator> scanner_;
  Odometry odometry_;
  Truth truth_;
  TruthScan last_;
  std::size_t count_ = 0;
  std::size_t next_ = 0;
};

// Writes a drive into a folder scan by scan: sim.fslog (FREESPACE_LOG), sim.clf (one
// ROBOTLASER1 line per layer) and truth.json (TruthWriter), nothing kept per scan. Throws
// OutputError when a file cannot be created or written.
class SimulationWriter {
 public:
  // `header`: the drive's truth without scans (Simulation::truth(); its scans are not written).
  SimulationWriter(const std::string& dir, const Truth& header);
  void Write(const Scan& scan, const TruthScan& truth);
  void Close();  // ends the three files

  std::string log_path() const { return dir_ + "/sim.fslog"; }
  std::string carmen_path() const { return dir_ + "/sim.clf"; }
  std::string truth_path() const { return dir_ + "/truth.json"; }

 private:
  std::string dir_;
  NativeLogWriter native_;
  RobotLaserWriter carmen_;
  TruthWriter truth_;
};

// Simulates the rest of `simulation` into `writer` (Close() left to the caller), calling `each`
// (when set) with every scan's echo sources. Returns the scans written. With
// keep_truth_scans false, memory stays the same however long the drive.
std::size_t WriteDrive(Simulation* simulation, SimulationWriter* writer,
                       const std::function<void(const std::vector<EchoSource>&)>& each = nullptr);

}  // namespace freespace::sim
