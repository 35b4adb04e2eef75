// eval.json and the printed quality summary: see quality_report.hpp.
#include "quality_report.hpp"

#include <cstdio>

#include "interrupt.hpp"
#include "output/text_file.hpp"

namespace freespace::cli {
namespace {

double Get(const nlohmann::json& summary, const char* metric, const char* stat) {
  const nlohmann::json& m = summary.at(metric);
  return m.contains(stat) && m.at(stat).is_number() ? m.at(stat).get<double>() : NAN;
}

}  // namespace

nlohmann::json QualityReport(const ReportContext& c, const MetricsSeries& metrics,
                             const StageSeries& times) {
  nlohmann::json per_scan = nlohmann::json::array();
  for (const ScanMetrics& m : metrics.scans()) per_scan.push_back(m.ToJson());
  return {{"scenario", c.scenario},
          {"log", c.log},
          {"truth", c.truth},
          {"backend", c.backend},
          {"scans_read", c.scans_read},
          {"rejected", c.rejected},
          {"malformed_lines", c.malformed_lines},
          {"interrupted_by",
           c.interrupted_by != 0 ? nlohmann::json(SignalName(c.interrupted_by)) : nlohmann::json()},
          {"definitions", "docs/metrics.md"},
          {"summary", metrics.Summary()},
          {"stage_us", times.Summary()},
          {"per_scan", per_scan}};
}

void PrintQuality(std::ostream& out, const nlohmann::json& s) {
  char line[320];
  std::snprintf(line, sizeof line,
                "  cell accuracy, observed cells   mean %.4f  min %.4f  pooled %.4f   aim >= 0.985"
                "   (%.0f %% of the wrong cells border an obstacle)\n",
                Get(s, "accuracy", "mean"), Get(s, "accuracy", "min"), Get(s, "accuracy", "pooled"),
                100.0 * Get(s, "accuracy", "errors_at_border_share"));
  out << line;
  std::snprintf(line, sizeof line,
                "  false-free rate                 mean %.4f  max %.4f  pooled %.4f   static "
                "obstacles only %.4f; free mask %.4f\n",
                Get(s, "false_free_rate", "mean"), Get(s, "false_free_rate", "max"),
                Get(s, "false_free_rate", "pooled"), Get(s, "false_free_rate", "pooled_static"),
                Get(s, "false_free_mask_rate", "pooled"));
  out << line;
  std::snprintf(line, sizeof line,
                "  polygon intrusion, cells        mean %.4f m2  median %.3f  p95 %.3f  max %.3f   "
                "aim < 0.03 m2   (moving obstacles' cells: mean %.4f m2; cells the free mask "
                "calls free: mean %.4f m2; outside the scanners' apertures: mean %.4f m2)\n",
                Get(s, "intrusion_m2", "mean"), Get(s, "intrusion_m2", "median"),
                Get(s, "intrusion_m2", "p95"), Get(s, "intrusion_m2", "max"),
                Get(s, "intrusion_moving_m2", "mean"), Get(s, "intrusion_mask_m2", "mean"),
                Get(s, "intrusion_out_of_view_m2", "mean"));
  out << line;
  std::snprintf(line, sizeof line,
                "  polygon intrusion, geometric    mean %.3f m2  median %.3f  p95 %.3f  max %.3f\n",
                Get(s, "intrusion_geometric_m2", "mean"),
                Get(s, "intrusion_geometric_m2", "median"), Get(s, "intrusion_geometric_m2", "p95"),
                Get(s, "intrusion_geometric_m2", "max"));
  out << line;
  std::snprintf(
      line, sizeof line,
      "  polygon coverage, in sight now  mean %.4f  min %.4f  pooled %.4f   aim >= 0.87\n",
      Get(s, "coverage", "mean"), Get(s, "coverage", "min"), Get(s, "coverage", "pooled"));
  out << line;
  std::snprintf(line, sizeof line,
                "  coverage of all seen so far     mean %.4f  min %.4f  pooled %.4f\n",
                Get(s, "coverage_seen", "mean"), Get(s, "coverage_seen", "min"),
                Get(s, "coverage_seen", "pooled"));
  out << line;
}

void WriteJson(const std::string& path, const nlohmann::json& doc) {
  WriteTextFile(path, doc.dump(1) + "\n");
}

}  // namespace freespace::cli
