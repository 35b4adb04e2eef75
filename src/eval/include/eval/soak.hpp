// The soak run of `freespace bench --soak N` (docs/bench.md): one estimator over a long
// simulated drive (sim::DriveLaps, generated scan by scan, never held), sampling the process's
// memory and the scan times every K scans, to show that neither grows with the drive.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "freespace/config.hpp"
#include "sim/simulator.hpp"

namespace freespace {

// The process's memory now, in kB: VmRSS and VmHWM of /proc/self/status (-1 where there is no
// such file) and the bytes malloc has handed out and not taken back (mallinfo2; -1 without
// glibc).
struct MemoryProbe {
  long rss_kb = -1;
  long hwm_kb = -1;
  long heap_kb = -1;
};
MemoryProbe ProbeMemory();

// One sample, taken after `scans` scans, over the window of scans since the previous sample.
struct SoakSample {
  std::size_t scans = 0;  // scans through the estimator so far
  std::size_t lap = 0;    // the lap being driven (1-based)
  double t_s = 0.0;       // drive time of the last scan
  MemoryProbe memory;
  std::size_t processed = 0;  // scans of the window the estimator processed (not rejected)
  double median_us = 0.0, p99_us = 0.0, max_us = 0.0;  // total time per scan in the window
};

struct SoakOptions {
  sim::SimulationOptions drive;  // scenario, first seed, each lap's duration, noise
  std::size_t scans = 100000;
  std::size_t every = 1000;                          // scans per sample
  std::function<void(const SoakSample&)> on_sample;  // called with each sample (progress)
};

struct SoakReport {
  std::string scenario;
  std::uint64_t seed = 0;
  std::string backend;
  int map_width = 0, map_height = 0;
  std::size_t scans = 0, every = 0, laps = 0, rejected = 0;
  double wall_s = 0.0;
  MemoryProbe before;  // before the estimator was made
  std::vector<SoakSample> samples;
};

// Runs an estimator of `config` over options.scans scans of the laps. Throws what the
// Estimator and the simulation throw (ConfigError, BackendError, std::invalid_argument).
SoakReport RunSoak(const Config& config, const SoakOptions& options);

// The figures the summary prints, from the samples: the peak is the largest VmRSS or VmHWM of
// any sample; growth is between the first sample of the second half and the last, per 10,000
// scans; early and late are the first and the last window.
struct SoakSummary {
  long rss_first_kb = -1, rss_last_kb = -1, rss_peak_kb = -1;
  double rss_growth_kb_per_10k = 0.0, heap_growth_kb_per_10k = 0.0;
  double median_early_us = 0.0, median_late_us = 0.0, p99_early_us = 0.0, p99_late_us = 0.0;
};
SoakSummary Summarize(const SoakReport& report);

// soak.csv (one line per sample, a header line first), soak.json (the run and its summary)
// and the printed summary.
inline constexpr const char* kSoakCsvFile = "soak.csv";
inline constexpr const char* kSoakJsonFile = "soak.json";
std::string SoakCsv(const SoakReport& report);
nlohmann::json SoakJson(const SoakReport& report);
void PrintSoakReport(std::FILE* out, const SoakReport& report);

}  // namespace freespace
