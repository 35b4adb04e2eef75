// `freespace devices`: the OpenCL platforms and devices this build sees, the one
// `backend: opencl` takes with the config (filters from --config and the environment), and with
// --check whether the kernels build there for the config's map.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "engine_options.hpp"
#include "freespace/freespace.hpp"

namespace freespace::cli {
namespace {

struct DevicesOptions {
  std::string config_path;
  bool json = false;
  bool check = false;
};

const ComputeDevice* Chosen(const DeviceList& list, const ComputePlatform** platform) {
  for (const ComputePlatform& p : list.platforms) {
    for (const ComputeDevice& d : p.devices) {
      if (d.chosen) {
        *platform = &p;
        return &d;
      }
    }
  }
  return nullptr;
}

nlohmann::json ToJson(const DeviceList& list) {
  nlohmann::json platforms = nlohmann::json::array();
  for (const ComputePlatform& p : list.platforms) {
    nlohmann::json devices = nlohmann::json::array();
    for (const ComputeDevice& d : p.devices) {
      devices.push_back({{"name", d.name},
                         {"type", d.type},
                         {"version", d.version},
                         {"driver_version", d.driver_version},
                         {"opencl_c_version", d.opencl_c_version},
                         {"compute_units", d.compute_units},
                         {"max_work_group", d.max_work_group},
                         {"global_memory_bytes", d.global_memory_bytes},
                         {"available", d.available},
                         {"compiler", d.compiler},
                         {"chosen", d.chosen}});
    }
    platforms.push_back({{"name", p.name}, {"version", p.version}, {"devices", devices}});
  }
  return {{"opencl_built", list.opencl_built},
          {"platform_filter", {{"value", list.platform_filter}, {"from", list.platform_origin}}},
          {"device_filter", {{"value", list.device_filter}, {"from", list.device_origin}}},
          {"platforms", platforms},
          {"error", list.error.empty() ? nlohmann::json() : nlohmann::json(list.error)}};
}

int Devices(const DevicesOptions& options) {
  Config config;
  EngineOptions engine;
  engine.config_path = options.config_path;
  DeviceList list;
  try {
    config = LoadEngineConfig(engine, nullptr);
    list = ListComputeDevices(config.backend);
  } catch (const std::exception& e) {
    std::cerr << "freespace devices: " << e.what() << "\n";
    return kExitSetup;
  }
  const ComputePlatform* platform = nullptr;
  const ComputeDevice* chosen = Chosen(list, &platform);

  // --check: an OpenCL estimator of the config, which builds the kernels for its map.
  nlohmann::json check;
  std::string check_error;
  if (options.check && chosen != nullptr) {
    Config opencl = config;
    opencl.backend.kind = BackendKind::kOpenCl;
    const auto start = std::chrono::steady_clock::now();
    try {
      Estimator estimator(opencl);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      check = {{"ok", true},
               {"backend", estimator.backend_name()},
               {"map_cells", {config.map.width_cells, config.map.height_cells}},
               {"setup_ms", ms}};
    } catch (const std::exception& e) {
      check_error = e.what();
      check = {{"ok", false}, {"error", check_error}};
    }
  }

  if (options.json) {
    nlohmann::json out = ToJson(list);
    if (options.check) out["check"] = check;
    std::cout << out.dump(2) << "\n";
  } else {
    if (!list.opencl_built) {
      std::printf("This build has no OpenCL backend; backend auto takes tbb.\n");
    } else {
      std::printf(
          "OpenCL platforms and devices (* = what backend opencl takes: platform \"%s\" "
          "from %s, device \"%s\" from %s)\n",
          list.platform_filter.c_str(), list.platform_origin.c_str(), list.device_filter.c_str(),
          list.device_origin.c_str());
      if (list.platforms.empty()) std::printf("  none\n");
      for (const ComputePlatform& p : list.platforms) {
        std::printf("  platform \"%s\" (%s)%s\n", p.name.c_str(), p.version.c_str(),
                    p.devices.empty() ? ": no devices" : "");
        for (const ComputeDevice& d : p.devices) {
          std::printf(
              "  %c %s \"%s\": %d compute units, work-groups up to %llu, %.1f GiB, %s, "
              "driver %s%s%s\n",
              d.chosen ? '*' : ' ', d.type.c_str(), d.name.c_str(), d.compute_units,
              static_cast<unsigned long long>(d.max_work_group),
              double(d.global_memory_bytes) / (1024.0 * 1024.0 * 1024.0),
              d.opencl_c_version.c_str(), d.driver_version.c_str(),
              d.available ? "" : " (not available)", d.compiler ? "" : " (no compiler)");
        }
        if (!p.note.empty()) std::printf("    (%s)\n", p.note.c_str());
      }
      if (chosen == nullptr) {
        std::printf("backend opencl fails; backend auto takes tbb\n");
      } else if (!options.check) {
        std::printf(
            "backend opencl takes \"%s\" on \"%s\"; backend auto takes it too if its "
            "kernels build (--check builds them)\n",
            chosen->name.c_str(), platform->name.c_str());
      } else if (check_error.empty()) {
        std::printf("backend opencl takes \"%s\" on \"%s\"; backend auto takes it too\n",
                    chosen->name.c_str(), platform->name.c_str());
        std::printf("check: the kernels built for a %d x %d map in %.0f ms\n",
                    config.map.width_cells, config.map.height_cells,
                    check["setup_ms"].get<double>());
      } else {
        std::printf(
            "backend opencl takes \"%s\" on \"%s\", but fails there; backend auto "
            "takes tbb\n",
            chosen->name.c_str(), platform->name.c_str());
        std::printf("check: failed (the reason is on stderr)\n");
      }
    }
  }
  if (!list.error.empty()) {
    std::cerr << "freespace devices: " << list.error << "\n";
    return kExitSetup;
  }
  if (!check_error.empty()) {
    std::cerr << "freespace devices: " << check_error << "\n";
    return kExitSetup;
  }
  return kExitOk;
}

}  // namespace

Command AddDevicesCommand(CLI::App& app) {
  auto options = std::make_shared<DevicesOptions>();
  CLI::App* command = app.add_subcommand(
      "devices",
      "List the OpenCL platforms and devices and mark the one `backend: opencl` takes with the\n"
      "config (backend.opencl_platform / opencl_device, replaced by FREESPACE_OPENCL_PLATFORM /\n"
      "FREESPACE_OPENCL_DEVICE when set). --check also builds the kernels there for the\n"
      "config's map. Exit code 0 when a device is chosen (and, with --check, its kernels\n"
      "build), 2 otherwise, with the reason on stderr.");
  command
      ->add_option("--config", options->config_path,
                   "YAML config (docs/configuration.md); missing fields keep their defaults")
      ->check(CLI::ExistingFile);
  command->add_flag("--json", options->json, "Print the list as JSON");
  command->add_flag("--check", options->check,
                    "Build the kernels on the chosen device for the config's map");
  return {command, [options] { return Devices(*options); }};
}

}  // namespace freespace::cli
