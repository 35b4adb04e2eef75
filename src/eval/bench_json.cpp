// bench.json from a BenchReport (docs/bench.md): see bench_report.hpp.
#include <cmath>

#include "eval/bench_report.hpp"

namespace freespace {
namespace {

// Non-finite numbers are written as null.
nlohmann::json Number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; }

nlohmann::json Map(const BenchReport& r) { return {r.map_width, r.map_height}; }

nlohmann::json Times(const PipelineRun& r) {
  return nlohmann::json{{"model_us", ModelUs(r)}, {"map_us", MapUs(r)}, {"total_us", TotalUs(r)}};
}

nlohmann::json Exponents(const std::map<std::string, ScaleExponent>& exponents) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [name, e] : exponents) {
    out[name] = {{"all", Number(e.all)}, {"upper", Number(e.upper)}};
  }
  return out;
}

nlohmann::json Pipelines(const BenchReport& r) {
  nlohmann::json out;
  for (const BackendPipeline& p : r.pipelines) {
    out[ToString(p.kind)] =
        p.error.empty() ? p.run.ToJson() : nlohmann::json{{"unavailable", p.error}};
  }
  return out;
}

nlohmann::json SensorModels(const BenchReport& r) {
  nlohmann::json out = {{"enhanced", Times(r.enhanced)},
                        {"conventional", Times(r.conventional)},
                        {"model_speedup", Number(r.comparisons.enhanced_model_speedup)},
                        {"map_speedup", Number(r.comparisons.enhanced_map_speedup)},
                        {"total_speedup", Number(r.comparisons.enhanced_total_speedup)},
                        {"coverage", r.coverage.ToJson()}};
  if (r.enhanced_quality) out["enhanced"]["quality"] = r.enhanced_quality->ToJson();
  if (r.conventional_quality) out["conventional"]["quality"] = r.conventional_quality->ToJson();
  return out;
}

nlohmann::json Alignment(const AlignmentComparison& a) {
  auto side = [](const PipelineRun& run, const AlignmentError& error) {
    return nlohmann::json{{"align_us", run.times.Quantile("align", 0.5)},
                          {"map_us", MapUs(run)},
                          {"total_us", TotalUs(run)},
                          {"error", error.ToJson()}};
  };
  return {{"circle", side(a.circle, a.circle_error)}, {"rotate", side(a.rotate, a.rotate_error)}};
}

nlohmann::json Scaling(const ScalingResults& s, const std::string& out_dir) {
  nlohmann::json out;
  for (const ScalePoint& p : s.map) {
    out["map"].push_back({{"backend", p.backend},
                          {"cells", p.cells},
                          {"total_us", p.total_us},
                          {"ns_per_cell", 1000.0 * p.total_us / p.x}});
  }
  out["map_plot"] = out_dir + "/" + kMapPlotFile;
  out["map_exponent"] = Exponents(s.map_exponent);
  for (const ScalePoint& p : s.points) {
    out["points"].push_back({{"backend", p.backend},
                             {"sensor_model", p.sensor_model},
                             {"points_per_scan", p.x},
                             {"resolution_deg", p.resolution_deg},
                             {"total_us", p.total_us},
                             {"model_us", p.model_us}});
  }
  out["points_scenario"] = s.points_scenario;
  out["points_plot"] = out_dir + "/" + kPointsPlotFile;
  out["points_exponent"] = Exponents(s.points_exponent);
  return out;
}

nlohmann::json Comparisons(const BenchReport& r) {
  const BenchComparisons& c = r.comparisons;
  nlohmann::json out;
  out["enhanced_model_speedup"] = Number(c.enhanced_model_speedup);
  out["enhanced_total_speedup"] = Number(c.enhanced_total_speedup);
  out["enhanced_time_saved_percent"] = Number(c.enhanced_time_saved_percent);
  out["enhanced_map_time_saved_percent"] = Number(c.enhanced_map_time_saved_percent);
  if (r.enhanced_quality) out["accuracy_enhanced"] = Number(r.enhanced_quality->accuracy);
  if (r.conventional_quality) {
    out["accuracy_conventional"] = Number(r.conventional_quality->accuracy);
  }
  out["circle_different_fraction"] = c.circle_different_fraction;
  out["rotate_different_fraction"] = c.rotate_different_fraction;
  out["circle_time_saved_percent"] = Number(c.circle_time_saved_percent);
  out["circle_map_time_saved_percent"] = Number(c.circle_map_time_saved_percent);
  if (c.opencl_over_tbb_total) out["opencl_over_tbb_total"] = Number(*c.opencl_over_tbb_total);
  const std::vector<const BackendPipeline*> ran = r.Ran();
  if (!ran.empty()) {
    out["pipeline_median_us"] = {{"backend", ran[0]->run.backend},
                                 {"map", Map(r)},
                                 {"points_per_scan", r.points_per_scan},
                                 {"total_us", TotalUs(ran[0]->run)}};
  }
  if (r.scaling) {
    for (const auto& [name, e] : r.scaling->map_exponent) {
      out["map_exponent"][name] = {{"all", Number(e.all)}, {"upper", Number(e.upper)}};
      out["map_at_most_linear"][name] = std::isfinite(e.upper) && e.upper <= kLinearExponent;
    }
  }
  return out;
}

}  // namespace

nlohmann::json BenchReportJson(const BenchReport& r, const std::string& out_dir) {
  nlohmann::json out = {
      {"source", r.source.Describe()},        {"scans", r.scans}, {"warmup", r.warmup},
      {"points_per_scan", r.points_per_scan}, {"map", Map(r)},    {"resolution_m", r.resolution_m}};
  if (!r.source.scenario.empty()) {
    out["scenario"] = {{"name", r.source.scenario}, {"seed", r.source.seed}};
  } else {
    out["log"] = r.source.log;
  }
  if (!r.pipelines.empty()) out["pipeline"] = Pipelines(r);
  out["sensor_model"] = SensorModels(r);
  out["alignment"] = Alignment(r.alignment);
  out["polygon_shape"] = {{"paper", r.paper_shape.ToJson()}, {"inside", r.inside_shape.ToJson()}};
  if (r.scaling) out["scaling"] = Scaling(*r.scaling, out_dir);
  out["comparisons"] = Comparisons(r);
  out["load_average"] = {Number(r.load_before), Number(r.load_after)};
  return out;
}

}  // namespace freespace
