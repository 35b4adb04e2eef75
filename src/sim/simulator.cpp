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
  if (options.keep_truth_scans) truth_.scans.reserve(count_);
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

  last_.index = next_;
  last_.t = t;
  last_.pose = m.pose;
  last_.odometry = scan->pose;
  last_.sensor = Compose(m.pose, sensor_mount);
  last_.speed = m.speed;
  last_.movers = scenario_.world.MoverPoses(t);
  if (options_.keep_truth_scans) truth_.scans.push_back(last_);
  ++next_;
  scan->sensor = 0;
  return t;
}

SimulationWriter::SimulationWriter(const std::string& dir, const Truth& header)
    : dir_(dir),
      native_(dir + "/" + kLogName, EngineSensors(header.rig), header.rig.vehicle),
      truth_(dir + "/" + kTruthName, header) {
  if (!header.rig.several()) {
    carmen_ =
        std::make_unique<RobotLaserWriter>(dir + "/" + kCarmenName, header.scanner.EngineSensor());
  }
}

void SimulationWriter::Write(const std::vector<Scan>& cycle, const TruthScan& truth) {
  for (const Scan& scan : cycle) {
    native_.Write(scan);
    if (carmen_) carmen_->Write(scan);
  }
  truth_.Add(truth);
}

void SimulationWriter::Write(const Scan& scan, const TruthScan& truth) {
  native_.Write(scan);
  if (carmen_) carmen_->Write(scan);
  truth_.Add(truth);
}

void SimulationWriter::Close() {
  native_.Close();
  if (carmen_) carmen_->Close();
  truth_.Close();
}

std::size_t WriteDrive(Simulation* simulation, SimulationWriter* writer,
                       const std::function<void(const std::vector<EchoSource>&)>& each,
                       const std::function<bool()>& stop) {
  std::vector<Scan> cycle;
  std::vector<EchoSource> sources;
  std::size_t written = 0;
  while (!(stop && stop()) && simulation->NextCycle(&cycle, each ? &sources : nullptr)) {
    writer->Write(cycle, simulation->last());
    if (each) each(sources);
    sources.clear();
    ++written;
  }
  return written;
}

}  // namespace freespace::sim
