// The soak run: see soak.hpp and docs/bench.md.
#include "eval/soak.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>

#include "eval/stage_stats.hpp"
#include "freespace/estimator.hpp"
#include "sim/laps.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace freespace {
namespace {

// The value in kB of a "Name:   123 kB" line of /proc/self/status; -1 when absent.
long StatusField(const std::string& status, const char* name) {
  const std::size_t at = status.find(std::string("\n") + name + ":");
  if (at == std::string::npos) return -1;
  return std::strtol(status.c_str() + at + std::char_traits<char>::length(name) + 2, nullptr, 10);
}

// Memory grown from sample `a` to sample `b`, in kB per 10,000 scans.
double GrowthPer10k(long a_kb, long b_kb, std::size_t a_scans, std::size_t b_scans) {
  if (a_kb < 0 || b_kb < 0 || b_scans <= a_scans) return 0.0;
  return double(b_kb - a_kb) * 1e4 / double(b_scans - a_scans);
}

double Round2(double v) { return std::round(v * 100.0) / 100.0; }

// Closes a window: its time quantiles and the memory now.
SoakSample TakeSample(std::vector<double>* window, std::size_t scans, std::size_t lap, double t,
                      std::size_t processed) {
  SoakSample s;
  s.scans = scans;
  s.lap = lap;
  s.t_s = t;
  s.processed = processed;
  if (!window->empty()) {
    s.median_us = Quantile(*window, 0.5);
    s.p99_us = Quantile(*window, 0.99);
    s.max_us = Quantile(*window, 1.0);
  }
  window->clear();
  s.memory = ProbeMemory();
  return s;
}

}  // namespace

MemoryProbe ProbeMemory() {
  MemoryProbe m;
  std::ifstream in("/proc/self/status");
  if (in) {
    std::ostringstream text;
    text << "\n" << in.rdbuf();
    const std::string status = text.str();
    m.rss_kb = StatusField(status, "VmRSS");
    m.hwm_kb = StatusField(status, "VmHWM");
  }
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 info = mallinfo2();
  m.heap_kb = long((info.uordblks + info.hblkhd) / 1024);
#endif
  return m;
}

SoakReport RunSoak(const Config& config, const SoakOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  SoakReport report;
  report.scenario = options.drive.scenario;
  report.seed = options.drive.seed;
  report.scans = options.scans;
  report.every = options.every > 0 ? options.every : 1;
  report.map_width = config.map.width_cells;
  report.map_height = config.map.height_cells;
  report.before = ProbeMemory();
  sim::DriveLaps drive(options.drive, options.scans);
  Estimator estimator(config);
  report.backend = estimator.backend_name();
  report.samples.reserve(options.scans / report.every + 1);
  std::vector<double> window;
  window.reserve(report.every);
  std::size_t processed = 0;
  Scan scan;
  while (drive.Next(&scan)) {
    const Result& r = estimator.Process(scan);
    if (r.status == ScanStatus::kRejected) {
      ++report.rejected;
    } else {
      window.push_back(r.times.total_us);
      ++processed;
    }
    if (drive.done() % report.every == 0 || drive.done() == drive.scan_count()) {
      report.samples.push_back(
          TakeSample(&window, drive.done(), drive.laps(), scan.timestamp_s, processed));
      processed = 0;
      if (options.on_sample) options.on_sample(report.samples.back());
    }
  }
  report.laps = drive.laps();
  report.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return report;
}

SoakSummary Summarize(const SoakReport& report) {
  SoakSummary s;
  const std::vector<SoakSample>& v = report.samples;
  if (v.empty()) return s;
  const SoakSample &first = v.front(), &last = v.back(), &half = v[(v.size() - 1) / 2];
  s.rss_first_kb = first.memory.rss_kb;
  s.rss_last_kb = last.memory.rss_kb;
  // The kernel raises VmHWM lazily (it can read below an earlier VmRSS): the peak is the most
  // either showed.
  for (const SoakSample& x : v) {
    s.rss_peak_kb = std::max({s.rss_peak_kb, x.memory.rss_kb, x.memory.hwm_kb});
  }
  s.rss_growth_kb_per_10k =
      GrowthPer10k(half.memory.rss_kb, last.memory.rss_kb, half.scans, last.scans);
  s.heap_growth_kb_per_10k =
      GrowthPer10k(half.memory.heap_kb, last.memory.heap_kb, half.scans, last.scans);
  s.median_early_us = first.median_us;
  s.median_late_us = last.median_us;
  s.p99_early_us = first.p99_us;
  s.p99_late_us = last.p99_us;
  return s;
}

std::string SoakCsv(const SoakReport& report) {
  std::ostringstream out;
  out << "scans,lap,t_s,rss_kb,hwm_kb,heap_kb,processed,median_us,p99_us,max_us\n";
  for (const SoakSample& s : report.samples) {
    out << s.scans << ',' << s.lap << ',' << Round2(s.t_s) << ',' << s.memory.rss_kb << ','
        << s.memory.hwm_kb << ',' << s.memory.heap_kb << ',' << s.processed << ','
        << Round2(s.median_us) << ',' << Round2(s.p99_us) << ',' << Round2(s.max_us) << '\n';
  }
  return out.str();
}

nlohmann::json SoakJson(const SoakReport& report) {
  const SoakSummary s = Summarize(report);
  return {{"scenario", report.scenario},
          {"seed", report.seed},
          {"backend", report.backend},
          {"map_cells", {report.map_width, report.map_height}},
          {"scans", report.scans},
          {"every", report.every},
          {"laps", report.laps},
          {"rejected", report.rejected},
          {"wall_s", Round2(report.wall_s)},
          {"samples", report.samples.size()},
          {"rss_before_kb", report.before.rss_kb},
          {"rss_first_kb", s.rss_first_kb},
          {"rss_last_kb", s.rss_last_kb},
          {"rss_peak_kb", s.rss_peak_kb},
          {"rss_growth_kb_per_10k_scans", Round2(s.rss_growth_kb_per_10k)},
          {"heap_growth_kb_per_10k_scans", Round2(s.heap_growth_kb_per_10k)},
          {"median_early_us", Round2(s.median_early_us)},
          {"median_late_us", Round2(s.median_late_us)},
          {"p99_early_us", Round2(s.p99_early_us)},
          {"p99_late_us", Round2(s.p99_late_us)}};
}

void PrintSoakReport(std::FILE* out, const SoakReport& report) {
  const SoakSummary s = Summarize(report);
  std::fprintf(out,
               "soak: %zu scans of %s (seeds %llu..%llu, %zu laps), %s backend, map %d x %d, "
               "%.1f s; %zu rejected\n",
               report.scans, report.scenario.c_str(), (unsigned long long)report.seed,
               (unsigned long long)(report.seed + report.laps - 1), report.laps,
               report.backend.c_str(), report.map_width, report.map_height, report.wall_s,
               report.rejected);
  std::fprintf(
      out,
      "  RSS: %.1f MB before the drive and the estimator, first sample %.1f MB, last %.1f MB, "
      "peak %.1f MB\n",
      report.before.rss_kb / 1024.0, s.rss_first_kb / 1024.0, s.rss_last_kb / 1024.0,
      s.rss_peak_kb / 1024.0);
  std::fprintf(out,
               "  growth over the second half, per 10,000 scans: RSS %+.1f kB, heap %+.1f kB\n",
               s.rss_growth_kb_per_10k, s.heap_growth_kb_per_10k);
  std::fprintf(out,
               "  scan time, first window / last window of %zu scans: median %.1f / %.1f us, "
               "p99 %.1f / %.1f us\n",
               report.every, s.median_early_us, s.median_late_us, s.p99_early_us, s.p99_late_us);
}

}  // namespace freespace
