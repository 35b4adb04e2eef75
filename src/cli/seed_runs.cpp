// --seeds and --scenarios, the seed table and seeds.json: see seed_runs.hpp.
#include "seed_runs.hpp"

#include <algorithm>
#include <cstdio>
#include <set>
#include <sstream>
#include <stdexcept>

#include "interrupt.hpp"
#include "quality_report.hpp"
#include "sim/scenarios.hpp"

namespace freespace::cli {
namespace {

std::vector<std::string> Split(const std::string& text, char by) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, by)) parts.push_back(part);
  return parts;
}

std::uint64_t Number(const std::string& text, const std::string& whole) {
  std::size_t used = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (text.empty() || used != text.size() || text[0] == '-' || text[0] == '+' ||
      (text[0] == '0' && text.size() > 1)) {
    throw std::invalid_argument("--seeds '" + whole + "': '" + text +
                                "' is not a seed (decimal digits, no leading zero, at most "
                                "18446744073709551615)");
  }
  return v;
}

}  // namespace

void AddSeedOptions(CLI::App* command, SeedOptions* o) {
  const auto not_empty = [](const std::string& text) {
    return text.empty() ? std::string("empty") : std::string();
  };
  command
      ->add_option("--seeds", o->seeds,
                   "Drives of these seeds (\"1-10\", \"1,4,7-9\"): the table of means over "
                   "seeds, worst seed and pooled figures, and OUT/seeds.json")
      ->check(not_empty);
  command
      ->add_option("--scenarios", o->scenarios,
                   "With --seeds: scenarios, comma-separated, or \"all\" (default: "
                   "--scenario)")
      ->check(not_empty);
}

void LinkSeedOptions(CLI::App* command) {
  CLI::Option* seeds = command->get_option("--seeds");
  command->get_option("--scenarios")->needs(seeds);
  seeds->excludes(command->get_option("--seed"));  // each drive's seed is one of --seeds
}

std::vector<std::uint64_t> ParseSeeds(const std::string& text) {
  std::vector<std::uint64_t> seeds;
  std::set<std::uint64_t> given;
  for (const std::string& part : Split(text, ',')) {
    const std::size_t dash = part.find('-', 1);
    const std::uint64_t first = Number(part.substr(0, dash), text);
    const std::uint64_t last =
        dash == std::string::npos ? first : Number(part.substr(dash + 1), text);
    if (last < first || last - first >= 100000) {
      throw std::invalid_argument("--seeds '" + text + "': '" + part + "' is not a range");
    }
    for (std::uint64_t s = first;; ++s) {  // to `last` inclusive, which may be the largest
      if (!given.insert(s).second) {
        throw std::invalid_argument("--seeds '" + text + "': seed " + std::to_string(s) +
                                    " given twice (a mean over seeds would count it twice)");
      }
      seeds.push_back(s);
      if (s == last) break;
    }
  }
  if (seeds.empty()) throw std::invalid_argument("--seeds '" + text + "': no seed");
  return seeds;
}

std::vector<std::string> ParseScenarios(const std::string& text, const std::string& fallback) {
  const std::vector<std::string> known = sim::ScenarioNames();
  if (text.empty()) return {fallback};
  if (text == "all") return known;
  std::vector<std::string> out;
  for (const std::string& s : Split(text, ',')) {
    if (std::find(known.begin(), known.end(), s) == known.end()) {
      throw std::invalid_argument("--scenarios '" + text + "': no scenario '" + s + "'");
    }
    if (std::find(out.begin(), out.end(), s) != out.end()) {
      throw std::invalid_argument("--scenarios '" + text + "': '" + s + "' given twice");
    }
    out.push_back(s);
  }
  return out;
}

void PrintSeedTable(std::ostream& out, const nlohmann::json& summary) {
  char line[400];
  std::snprintf(line, sizeof line, "  %-9s %5s   %-17s %-19s %-10s %-17s %s\n", "scenario", "seeds",
                "accuracy (worst)", "intrusion m2 (worst)", "of it moving", "coverage (worst)",
                "pooled coverage");
  out << line;
  for (const nlohmann::json& s : summary) {
    const auto mean = [&](const char* m) { return s.at("mean").at(m).get<double>(); };
    const auto worst = [&](const char* m) { return s.at("worst").at(m).at("value").get<double>(); };
    std::snprintf(line, sizeof line,
                  "  %-9s %5zu   %.4f (%.4f)   %.4f (%.4f)      %.4f     %.4f (%.4f)   %.4f\n",
                  s.at("scenario").get<std::string>().c_str(), s.at("seeds").size(),
                  mean("accuracy"), worst("accuracy"), mean("intrusion_m2"), worst("intrusion_m2"),
                  mean("intrusion_moving_m2"), mean("coverage"), worst("coverage"),
                  s.at("pooled").at("coverage").get<double>());
    out << line;
  }
  std::string aims = "  aims (mean, worst seed):";
  for (const QualityAim& a : kQualityAims) {
    std::snprintf(line, sizeof line, " %s %s %.3g (%.3g);", a.metric,
                  a.at_most ? "<" : ">=", a.mean, a.worst);
    aims += line;
  }
  out << aims << "\n";
  for (const nlohmann::json& s : summary) {
    std::string missed;
    for (const auto& [metric, aim] : s.at("aims").items()) {
      if (!aim.at("met").get<bool>()) missed += " " + metric;
    }
    out << "  " << s.at("scenario").get<std::string>() << ": "
        << (missed.empty() ? "every aim met" : "missed:" + missed) << "\n";
  }
}

void WriteSeeds(const std::string& path, const Config& config, const nlohmann::json& summary,
                int interrupted_by) {
  WriteJson(path,
            {{"definitions", "docs/metrics.md"},
             {"config", config.ToYaml()},
             {"scenarios", summary},
             {"interrupted_by", interrupted_by != 0 ? nlohmann::json(SignalName(interrupted_by))
                                                    : nlohmann::json()}});
}

}  // namespace freespace::cli
