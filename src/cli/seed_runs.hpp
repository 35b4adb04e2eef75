// Quality over many drives on the command line: `--seeds` and `--scenarios` of `freespace eval`
// and `freespace demo`, the table they print and OUT/seeds.json (docs/formats.md).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "eval/drive_eval.hpp"
#include "freespace/config.hpp"

namespace freespace::cli {

struct SeedOptions {
  std::string seeds;      // empty: one drive (--seed)
  std::string scenarios;  // empty: --scenario
};

void AddSeedOptions(CLI::App* command, SeedOptions* options);
// After AddSeedOptions and AddSimOptions: --scenarios needs --seeds, and --seeds excludes --seed
// (neither would be read otherwise).
void LinkSeedOptions(CLI::App* command);

// "1-10", "3", "1,4,7-9": the seeds in the order given. Throws std::invalid_argument.
std::vector<std::uint64_t> ParseSeeds(const std::string& text);

// "urban,parking" or "all"; empty: `fallback` alone. Throws std::invalid_argument for an unknown
// scenario.
std::vector<std::string> ParseScenarios(const std::string& text, const std::string& fallback);

// Prints a seed summary (SeedSummary) as a table, one row a scenario, the aims beside it.
void PrintSeedTable(std::ostream& out, const nlohmann::json& summary);

// Writes OUT/seeds.json: the config, the summary and `interrupted_by`, the signal that stopped
// the drives before the last (0: none; null in the file); throws InputError when it cannot.
void WriteSeeds(const std::string& path, const Config& config, const nlohmann::json& summary,
                int interrupted_by = 0);

}  // namespace freespace::cli
