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
  truth_.rig = MakeRig(options.rig, options_.scanner);
  options_.scanner = truth_.rig.scanners.front();
  scanner_ = std::make_unique<ScanSimulator>(options_.scanner, scenario_.world, options.seed);
  // Each further scanner of a rig draws from its own seed, so the first one's scans do not
  // depend on the rig.
  for (std::size_t k = 1; k < truth_.rig.scanners.size(); ++k) {
    rig_scanners_.push_back(std::make_unique<ScanSimulator>(truth_.rig.scanners[k], scenario_.world,
                                                            options.seed * 1000003ull + k));
  }
  const double duration = options.duration_s > 0.0 ? options.duration_s : scenario_.duration_s;
  count_ = std::size_t(std::floor(duration / options_.scanner.scan_period_s + 1e-9)) + 1;
  truth_.scenario = scenario_.name;
  truth_.description = scenario_.description;
  truth_.seed = options.seed;
  truth_.scanner = options_.scanner;
  truth_.odometry_noise = options.odometry;
  truth_.world = scenario_.world;
  truth_.world.tracks.clear();
  truth_.scans.reserve(count_);
}

bool Simulation::Next(Scan* scan, std::vector<EchoSource>* sources) {
  if (next_ >= count_) return false;
  Step(scan, sources, options_.scanner.mount());
  return true;
}

bool Simulation::NextCycle(std::vector<Scan>* scans, std::vector<EchoSource>* sources) {
  if (next_ >= count_) return false;
  scans->resize(truth_.rig.scanners.size());
  const RigConfig& v = truth_.rig.vehicle;
  const Pose2D reference = truth_.rig.several() ? Pose2D{v.reference_x_m, v.reference_y_m, 0.0}
                                                : options_.scanner.mount();
  const double t = Step(&(*scans)[0], sources, reference);
  for (std::size_t k = 1; k < scans->size(); ++k) {
    Scan& scan = (*scans)[k];
    rig_scanners_[k - 1]->Simulate(t, scenario_.trajectory, &scan, sources ? &more_ : nullptr);
    if (sources) sources->insert(sources->end(), more_.begin(), more_.end());
    scan.timestamp_s = t;
    scan.pose = (*scans)[0].pose;
    scan.sensor = int(k);
  }
  return true;
}

double Simulation::Step(Scan* scan, std::vector<EchoSource>* sources, const Pose2D& sensor_mount) {
  const double t = Round(double(next_) * options_.scanner.scan_period_s, 1e6);
  scanner_->Simulate(t, scenario_.trajectory, scan, sources);
  const MotionState m = scenario_.trajectory.At(t);
  const Pose2D odometry = odometry_.Update(t, m.pose);
  scan->timestamp_s = t;
  scan->pose = {Round(odometry.x, 1e6), Round(odometry.y, 1e6), Round(odometry.yaw, 1e9)};

  TruthScan truth;
  truth.index = next_;
  truth.t = t;
  truth.pose = m.pose;
  truth.odometry = scan->pose;
  truth.sensor = Compose(m.pose, sensor_mount);
  truth.speed = m.speed;
  truth.movers = scenario_.world.MoverPoses(t);
  truth_.scans.push_back(std::move(truth));
  ++next_;
  scan->sensor = 0;
  return t;
}

namespace {

std::vector<SensorConfig> EngineSensors(const Rig& rig) {
  const Config config = WithRig(Config(), rig);
  return config.is_rig() ? config.sensors : std::vector<SensorConfig>{config.sensor};
}

}  // namespace

SimulationWriter::SimulationWriter(const std::string& dir, const ScannerConfig& scanner)
    : dir_(dir),
      native_(dir + "/sim.fslog", scanner.EngineSensor()),
      carmen_(std::make_unique<RobotLaserWriter>(dir + "/sim.clf", scanner.EngineSensor())) {}

SimulationWriter::SimulationWriter(const std::string& dir, const Rig& rig)
    : dir_(dir), native_(dir + "/sim.fslog", EngineSensors(rig), rig.vehicle) {
  if (!rig.several()) {
    carmen_ = std::make_unique<RobotLaserWriter>(dir + "/sim.clf", EngineSensors(rig).front());
  }
}

void SimulationWriter::Write(const Scan& scan) {
  native_.Write(scan);
  if (carmen_) carmen_->Write(scan);
}

void SimulationWriter::Close(const Truth& truth) {
  native_.Close();
  if (carmen_) carmen_->Close();
  WriteTruth(truth_path(), truth);
}

}  // namespace freespace::sim
