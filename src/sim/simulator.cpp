// The drive, scan by scan, and its files: see simulator.hpp.
#include "sim/simulator.hpp"

#include <cmath>
#include <stdexcept>

#include "geometry/geometry.hpp"

namespace freespace::sim {
namespace {

// The precision of the log's text fields (NativeLogWriter): t and x, y to 1e-6, yaw to 1e-9.
// Dividing by the exact power of ten gives the double nearest the decimal the log will hold.
double Round(double v, double per_unit) { return std::round(v * per_unit) / per_unit; }

}  // namespace

Simulation::Simulation(const SimulationOptions& options)
    : options_(options),
      scenario_(BuildScenario(options.scenario, options.seed)),
      odometry_(options.odometry, options.seed) {
  options_.scanner.Validate();
  if (options.duration_s < 0.0) throw std::invalid_argument("simulation: duration must be >= 0");
  scanner_ = std::make_unique<ScanSimulator>(options_.scanner, scenario_.world, options.seed);
  const double duration = options.duration_s > 0.0 ? options.duration_s : scenario_.duration_s;
  count_ = std::size_t(std::floor(duration / options_.scanner.scan_period_s + 1e-9)) + 1;
  truth_.scenario = scenario_.name;
  truth_.description = scenario_.description;
  truth_.seed = options.seed;
  truth_.scanner = options_.scanner;
  truth_.odometry_noise = options.odometry;
  truth_.world = scenario_.world;
  truth_.world.tracks.clear();
  if (options.keep_truth_scans) truth_.scans.reserve(count_);
}

bool Simulation::Next(Scan* scan, std::vector<EchoSource>* sources) {
  if (next_ >= count_) return false;
  const double t = Round(double(next_) * options_.scanner.scan_period_s, 1e6);
  scanner_->Simulate(t, scenario_.trajectory, scan, sources);
  const MotionState m = scenario_.trajectory.At(t);
  const Pose2D odometry = odometry_.Update(t, m.pose);
  scan->timestamp_s = t;
  scan->pose = {Round(odometry.x, 1e6), Round(odometry.y, 1e6), Round(odometry.yaw, 1e9)};

  last_.index = next_;
  last_.t = t;
  last_.pose = m.pose;
  last_.odometry = scan->pose;
  last_.sensor = Compose(m.pose, options_.scanner.mount());
  last_.speed = m.speed;
  last_.movers = scenario_.world.MoverPoses(t);
  if (options_.keep_truth_scans) truth_.scans.push_back(last_);
  ++next_;
  return true;
}

SimulationWriter::SimulationWriter(const std::string& dir, const Truth& header)
    : dir_(dir),
      native_(dir + "/sim.fslog", header.scanner.EngineSensor()),
      carmen_(dir + "/sim.clf", header.scanner.EngineSensor()),
      truth_(dir + "/truth.json", header) {}

void SimulationWriter::Write(const Scan& scan, const TruthScan& truth) {
  native_.Write(scan);
  carmen_.Write(scan);
  truth_.Add(truth);
}

void SimulationWriter::Close() {
  native_.Close();
  carmen_.Close();
  truth_.Close();
}

std::size_t WriteDrive(Simulation* simulation, SimulationWriter* writer,
                       const std::function<void(const std::vector<EchoSource>&)>& each) {
  Scan scan;
  std::vector<EchoSource> sources;
  std::size_t written = 0;
  while (simulation->Next(&scan, &sources)) {
    writer->Write(scan, simulation->last());
    if (each) each(sources);
    ++written;
  }
  return written;
}

}  // namespace freespace::sim
