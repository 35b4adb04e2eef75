// The engine options of the commands and the config they make: see engine_options.hpp.
#include "engine_options.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "freespace/errors.hpp"

namespace freespace::cli {

void AddEngineOptions(CLI::App* command, EngineOptions* options) {
  command
      ->add_option("--config", options->config_path,
                   "YAML config (docs/configuration.md); missing fields keep their defaults")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--set", options->settings,
                   "Sets one config field, section.field=value (e.g. polygon.margin_cells=0), "
                   "over --config; repeatable")
      ->allow_extra_args(false);
  command->add_option("--backend", options->backend, "Compute backend, overrides the config")
      ->check(CLI::IsMember({"tbb", "opencl", "auto"}));
  command
      ->add_option("--threads", options->threads,
                   "TBB worker threads (0 = all cores), overrides the config")
      ->check(CLI::Range(0, 1024));
  command
      ->add_option("--opencl-wait", options->opencl_wait,
                   "How the host waits for the OpenCL device, overrides the config")
      ->check(CLI::IsMember({"auto", "block", "spin"}));
  command
      ->add_option("--opencl-devices", options->opencl_devices,
                   "CPU devices to split the OpenCL kernels over, overrides the config "
                   "(FREESPACE_OPENCL_DEVICES overrides both)")
      ->check(CLI::Range(1, 16));
}

namespace {

Config Load(const EngineOptions& options, const LogSensors* log, const Config& base) {
  Config config = base;
  bool has_sensor = false, has_rig = false;
  if (!options.config_path.empty()) {
    std::ifstream in(options.config_path);
    if (!in) throw ConfigError("config: cannot open '" + options.config_path + "'");
    std::stringstream text;
    text << in.rdbuf();
    config = Config::FromYaml(text.str(), options.config_path);
    for (const std::string& s : YamlSections(text.str())) {
      has_sensor |= (s == "sensor" || s == "sensors");
      has_rig |= (s == "rig");
    }
  }
  if (!has_sensor && log != nullptr && log->sensors.size() == 1) {
    config.sensor = log->sensors.front();
    config.sensors.clear();
  } else if (!has_sensor && log != nullptr && log->sensors.size() > 1) {
    config.sensors = log->sensors;
    if (!has_rig) config.rig = log->rig;
  }
  config = WithSettings(config, options.settings);
  if (options.backend == "tbb") config.backend.kind = BackendKind::kTbb;
  if (options.backend == "opencl") config.backend.kind = BackendKind::kOpenCl;
  if (options.backend == "auto") config.backend.kind = BackendKind::kAuto;
  if (options.threads >= 0) config.backend.threads = options.threads;
  if (options.opencl_wait == "auto") config.backend.opencl_wait = OpenClWait::kAuto;
  if (options.opencl_wait == "block") config.backend.opencl_wait = OpenClWait::kBlock;
  if (options.opencl_wait == "spin") config.backend.opencl_wait = OpenClWait::kSpin;
  if (options.opencl_devices > 0) config.backend.opencl_devices = options.opencl_devices;
  config.Validate();
  return config;
}

}  // namespace

Config LoadEngineConfig(const EngineOptions& options, const SensorConfig* log_sensor,
                        const Config& base) {
  if (log_sensor == nullptr) return Load(options, nullptr, base);
  LogSensors log;
  log.sensors.push_back(*log_sensor);
  return Load(options, &log, base);
}

Config LoadEngineConfig(const EngineOptions& options, const LogSensors& log, const Config& base) {
  return Load(options, &log, base);
}

namespace {
std::string Geometry(const SensorConfig& s) {
  std::ostringstream out;
  out << s.layers << " layer(s), " << s.min_angle_deg << " .. " << s.max_angle_deg << " deg at "
      << s.angular_resolution_deg << " deg, " << s.min_range_m << " .. " << s.max_range_m << " m";
  return out.str();
}
}  // namespace

std::string SensorReplacedNote(const std::vector<SensorConfig>& log, const Config& config) {
  if (log.size() != 1 || config.is_rig()) return "";
  const SensorConfig &a = log.front(), &b = config.sensor;
  if (a.layers == b.layers && a.min_angle_deg == b.min_angle_deg &&
      a.max_angle_deg == b.max_angle_deg && a.angular_resolution_deg == b.angular_resolution_deg &&
      a.min_range_m == b.min_range_m && a.max_range_m == b.max_range_m) {
    return "";
  }
  return "the config's sensor section replaces the log's sensor (" + Geometry(a) + ") with " +
         Geometry(b) +
         "; the fields it leaves out keep their defaults, not the log's (leave the section out "
         "to take the log's sensor)";
}

bool ConfigSetsSensor(const EngineOptions& options) {
  if (options.config_path.empty()) return false;
  std::ifstream in(options.config_path);
  if (!in) throw ConfigError("config: cannot open '" + options.config_path + "'");
  std::stringstream text;
  text << in.rdbuf();
  for (const std::string& s : YamlSections(text.str())) {
    if (s == "sensor" || s == "sensors") return true;
  }
  return false;
}

void RefuseSensorSettings(const EngineOptions& options, const std::string& what) {
  for (const std::string& setting : options.settings) {
    if (setting.rfind("sensor.", 0) == 0) {
      throw ConfigError("--set " + setting + ": " + what);
    }
  }
}

void RefuseSimulatedRigSettings(const EngineOptions& options, const std::string& rig) {
  RefuseSensorSettings(options, "the scanners of --rig " + rig + " are the sensors of its drives");
  for (const std::string& setting : options.settings) {
    if (setting.rfind("rig.", 0) == 0) {
      throw ConfigError("--set " + setting + ": the vehicle of --rig " + rig +
                        " is its drives' rig section");
    }
  }
}

void MakeDirectories(const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw OutputError(dir + ": cannot create directory: " + error.message());
}

}  // namespace freespace::cli
