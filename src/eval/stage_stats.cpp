// Timing statistics of many scans: quantiles by nearest rank and per-stage summaries.
#include "eval/stage_stats.hpp"

#include <algorithm>
#include <cmath>

namespace freespace {

double Quantile(std::vector<double>& values, double q) {
  if (values.empty()) return 0.0;
  const std::size_t k =
      std::min(values.size() - 1, std::size_t(std::ceil(q * values.size())) - (q > 0 ? 1 : 0));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

void StageSeries::Add(const StageTimes& t) {
  preprocess_.push_back(t.preprocess_us);
  align_.push_back(t.align_us);
  rasterize_.push_back(t.rasterize_us);
  fuse_.push_back(t.fuse_us);
  classify_.push_back(t.classify_us);
  mask_.push_back(t.mask_us);
  insight_.push_back(t.insight_us);
  polygon_.push_back(t.polygon_us);
  total_.push_back(t.total_us);
}

nlohmann::json StageSeries::Summary() const {
  nlohmann::json out = nlohmann::json::object();
  const std::pair<const char*, const std::vector<double>*> stages[] = {
      {"preprocess", &preprocess_}, {"align", &align_},
      {"rasterize", &rasterize_},   {"fuse", &fuse_},
      {"classify", &classify_},     {"mask", &mask_},
      {"insight", &insight_},
      {"polygon", &polygon_},       {"total", &total_}};
  for (const auto& [name, series] : stages) {
    std::vector<double> v = *series;
    const double median = freespace::Quantile(v, 0.5), p99 = freespace::Quantile(v, 0.99);
    out[name] = {{"median", std::round(median * 100) / 100}, {"p99", std::round(p99 * 100) / 100}};
  }
  return out;
}

const std::vector<double>* StageSeries::Stage(const std::string& name) const {
  if (name == "preprocess") return &preprocess_;
  if (name == "align") return &align_;
  if (name == "rasterize") return &rasterize_;
  if (name == "fuse") return &fuse_;
  if (name == "classify") return &classify_;
  if (name == "mask") return &mask_;
  if (name == "insight") return &insight_;
  if (name == "polygon") return &polygon_;
  return &total_;
}

double StageSeries::Quantile(const std::string& stage, double q) const {
  std::vector<double> v = *Stage(stage);
  return freespace::Quantile(v, q);
}

double StageSeries::Mean(const std::string& stage) const {
  const std::vector<double>& v = *Stage(stage);
  double sum = 0.0;
  for (const double x : v) sum += x;
  return v.empty() ? 0.0 : sum / double(v.size());
}

double StageSeries::MedianTotal() const {
  std::vector<double> v = total_;
  return freespace::Quantile(v, 0.5);
}

}  // namespace freespace
