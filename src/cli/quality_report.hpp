// The quality report of `freespace eval` and `freespace demo`: eval.json (docs/formats.md)
// and the summary printed on the terminal, with the project's aims beside the measured values.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "eval/metrics.hpp"
#include "eval/stage_stats.hpp"

namespace freespace::cli {

// What eval.json holds besides the metrics.
struct ReportContext {
  std::string scenario;
  std::string log;
  std::string truth;
  std::string backend;
  long scans_read = 0;
  long rejected = 0;
  long malformed_lines = 0;  // the log's lines the reader reported and skipped
  int interrupted_by = 0;    // the signal that stopped the scans before the log's end; 0: none
};

nlohmann::json QualityReport(const ReportContext& context, const MetricsSeries& metrics,
                             const StageSeries& times);

// Prints the summary's headline numbers: accuracy, false-free rate, intrusion, coverage.
void PrintQuality(std::ostream& out, const nlohmann::json& summary);

// Writes `doc` as indented JSON; throws InputError when it cannot.
void WriteJson(const std::string& path, const nlohmann::json& doc);

}  // namespace freespace::cli
