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
  std::string rig = "front";  // sim/rig.hpp: the scanners, each `scanner` at its mount
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
  // Simulates the next cycle of the rig: one scan per scanner, all stamped alike (the rig's
  // scanners are synchronised), scan.sensor its index; the truth's sensor pose is the rig's
  // reference point. With the front rig, one scan as Next() gives. False when done.
  // `sources`, when given, gets every scan's point sources one after the other.
  bool NextCycle(std::vector<Scan>* scans, std::vector<EchoSource>* sources = nullptr);

  std::size_t scan_count() const { return count_; }  // scans the drive has
  const Scenario& scenario() const { return scenario_; }
  const Rig& rig() const { return truth_.rig; }
  // The header and, with keep_truth_scans, the scans so far.
  const Truth& truth() const { return truth_; }
  const TruthScan& last() const { return last_; }  // the truth of the last scan (cycle)

 private:
  SimulationOptions options_;
  Scenario scenario_;
  std::unique_ptr<ScanSimulator> scanner_;
  std::vector<std::unique_ptr<ScanSimulator>> rig_scanners_;  // a rig's other scanners
  std::vector<EchoSource> more_;
  Odometry odometry_;
  Truth truth_;
  TruthScan last_;
  std::size_t count_ = 0;
  // Simulates scan `next_` (its truth into last_, appended when kept); the first scanner's
  // scan into `scan`.
  double Step(Scan* scan, std::vector<EchoSource>* sources, const Pose2D& sensor_mount);
  std::size_t next_ = 0;
};

// Writes a drive into a folder scan by scan: sim.fslog (FREESPACE_LOG), sim.clf (one
// ROBOTLASER1 line per layer; not for a rig of several scanners, which CARMEN's records cannot
// name) and truth.json (TruthWriter), nothing kept per scan. Throws OutputError when a file
// cannot be created or written.
class SimulationWriter {
 public:
  // `header`: the drive's truth without scans (Simulation::truth(); its scans are not written),
  // its rig the logs' sensors.
  SimulationWriter(const std::string& dir, const Truth& header);
  // One cycle of the rig (one scan with the front rig) and its truth.
  void Write(const std::vector<Scan>& cycle, const TruthScan& truth);
  void Write(const Scan& scan, const TruthScan& truth);
  void Close();  // ends the files
  bool writes_carmen() const { return carmen_ != nullptr; }

  // The files' names in the folder.
  static constexpr const char* kLogName = "sim.fslog";
  static constexpr const char* kCarmenName = "sim.clf";
  static constexpr const char* kTruthName = "truth.json";
  std::string log_path() const { return dir_ + "/" + kLogName; }
  std::string carmen_path() const { return dir_ + "/" + kCarmenName; }
  std::string truth_path() const { return dir_ + "/" + kTruthName; }

 private:
  std::string dir_;
  NativeLogWriter native_;
  std::unique_ptr<RobotLaserWriter> carmen_;
  TruthWriter truth_;
};

// Simulates the rest of `simulation` into `writer` cycle by cycle (Close() left to the
// caller), calling `each` (when set) with every cycle's echo sources, until the drive ends or
// `stop` (when set), asked before each cycle, says to. Returns the cycles written. With
// keep_truth_scans false, memory stays the same however long the drive.
std::size_t WriteDrive(Simulation* simulation, SimulationWriter* writer,
                       const std::function<void(const std::vector<EchoSource>&)>& each = nullptr,
                       const std::function<bool()>& stop = nullptr);

}  // namespace freespace::sim
