// Drives simulated, estimated and scored in memory, and their summary over seeds.
#include "eval/drive_eval.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "eval/scorer.hpp"
#include "freespace/estimator.hpp"

namespace freespace {
namespace {

// The per-drive values a seed summary reports, each a MetricsSeries summary field's mean.
constexpr const char* kMetrics[] = {"accuracy",
                                    "false_free_rate",
                                    "intrusion_m2",
                                    "intrusion_moving_m2",
                                    "intrusion_mask_m2",
                                    "intrusion_out_of_view_m2",
                                    "intrusion_geometric_m2",
                                    "coverage",
                                    "coverage_mask",
                                    "coverage_star",
                                    "coverage_seen"};
constexpr const char* kStages[] = {"preprocess", "align",   "rasterize", "fuse", "classify",
                                   "mask",       "insight", "polygon",   "total"};

double Mean(const nlohmann::json& summary, const char* metric) {
  const nlohmann::json& m = summary.at(metric);
  return m.contains("mean") && m.at("mean").is_number() ? m.at("mean").get<double>() : NAN;
}

// Larger is worse for the intrusion metrics and the false-free rate, smaller for the rest.
bool WorseIsLarger(const std::string& metric) {
  return metric.rfind("intrusion", 0) == 0 || metric == "false_free_rate";
}

nlohmann::json ScenarioSummary(const std::vector<const DriveEvaluation*>& drives) {
  nlohmann::json out, per_seed = nlohmann::json::array(), seeds = nlohmann::json::array();
  MetricsSeries all;
  std::map<std::string, std::vector<double>> values, stages;
  for (const DriveEvaluation* d : drives) {
    const nlohmann::json summary = d->metrics.Summary();
    nlohmann::json row = {{"seed", d->seed}, {"scans", d->metrics.size()}};
    for (const char* m : kMetrics) {
      row[m] = Mean(summary, m);
      values[m].push_back(Mean(summary, m));
    }
    for (const char* s : kStages) stages[s].push_back(d->times.Quantile(s, 0.5));
    per_seed.push_back(row);
    seeds.push_back(d->seed);
    for (const ScanMetrics& m : d->metrics.scans()) all.Add(m);
  }
  const nlohmann::json pooled = all.Summary();
  nlohmann::json mean, worst, pooled_out, stage_us;
  for (const char* m : kMetrics) {
    const std::vector<double>& v = values[m];
    double sum = 0.0;
    std::size_t at = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      sum += v[i];
      if (WorseIsLarger(m) ? v[i] > v[at] : v[i] < v[at]) at = i;
    }
    mean[m] = v.empty() ? NAN : sum / double(v.size());
    worst[m] = {{"value", v.empty() ? NAN : v[at]}, {"seed", v.empty() ? 0 : drives[at]->seed}};
    const nlohmann::json& p = pooled.at(m);
    pooled_out[m] = p.contains("pooled") ? p.at("pooled") : p.at("mean");
  }
  for (const char* s : kStages) {
    std::vector<double> v = stages[s];
    stage_us[s] = Quantile(v, 0.5);
  }
  nlohmann::json aims;
  for (const QualityAim& a : kQualityAims) {
    const double m = mean[a.metric], w = worst[a.metric]["value"];
    const bool met = a.at_most ? (m < a.mean && w < a.worst) : (m >= a.mean && w >= a.worst);
    aims[a.metric] = {{"mean", a.mean}, {"worst", a.worst}, {"met", met}};
  }
  out = {{"scenario", drives.front()->scenario},
         {"seeds", seeds},
         {"per_seed", per_seed},
         {"mean", mean},
         {"worst", worst},
         {"pooled", pooled_out},
         {"aims", aims},
         {"stage_us", stage_us}};
  return out;
}

}  // namespace

DriveEvaluation EvaluateDrive(const sim::SimulationOptions& options, const Config& config,
                              bool keep_sensor) {
  sim::Simulation simulation(options);
  Config c = config;
  if (!keep_sensor || simulation.rig().several()) c = sim::WithRig(c, simulation.rig());
  Estimator estimator(c);
  sim::TruthScorer scorer(simulation.truth());
  DriveEvaluation drive;
  drive.scenario = simulation.scenario().name;
  drive.seed = options.seed;
  drive.config = c;
  std::vector<Scan> cycle;
  while (simulation.NextCycle(&cycle)) {
    const Result& r = estimator.ProcessCycle(cycle);
    if (r.status == ScanStatus::kRejected) {
      ++drive.rejected;
      continue;
    }
    drive.times.Add(r.times);
    drive.metrics.Add(scorer.Score(scorer.Find(r.timestamp_s), estimator.map(), r));
  }
  return drive;
}

nlohmann::json SeedSummary(const std::vector<DriveEvaluation>& drives) {
  std::vector<std::string> order;
  std::map<std::string, std::vector<const DriveEvaluation*>> by;
  for (const DriveEvaluation& d : drives) {
    if (by.find(d.scenario) == by.end()) order.push_back(d.scenario);
    by[d.scenario].push_back(&d);
  }
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& s : order) out.push_back(ScenarioSummary(by[s]));
  return out;
}

}  // namespace freespace
