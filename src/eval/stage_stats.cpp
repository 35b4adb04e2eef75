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
  const std::pair<const char*, const std::vector<double>*> stages[] = {{"preprocess", &preprocess_},
                                                                       {"align", &align_},
                                                                       {"rasterize", &rasterize_},
                                                                       {"fuse", &fuse_},
                                                                       {"classify", &classify_},
                                                                       {"mask", &mask_},
                                                                       {"insight", &insight_},
                                                                       {"polygon", &polygon_},
                                                                       {"total", &total_}};
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

namespace {

constexpr double kLowUs = 0.01;   // the first bin's lower edge
constexpr double kGrowth = 1.01;  // each bin 1 % wider than the one before
constexpr int kBins = 2315;       // up to kLowUs * kGrowth^kBins = 1e8 us (100 s)
const double kLogGrowth = std::log(kGrowth);

int BinOf(double us) {
  if (!(us > kLowUs)) return 0;
  return std::min(kBins - 1, int(std::log(us / kLowUs) / kLogGrowth));
}

// The geometric middle of a bin: within half a bin (0.5 %) of every time in it.
double BinValue(int bin) { return kLowUs * std::pow(kGrowth, bin + 0.5); }

const char* const kStageNames[StageHistogram::kStages] = {
    "preprocess", "align", "rasterize", "fuse", "classify", "mask", "insight", "polygon", "total"};

}  // namespace

StageHistogram::StageHistogram() : bins_(std::size_t(kStages) * kBins, 0) {}

void StageHistogram::Add(const StageTimes& t) {
  const double values[kStages] = {t.preprocess_us, t.align_us,    t.rasterize_us,
                                  t.fuse_us,       t.classify_us, t.mask_us,
                                  t.insight_us,    t.polygon_us,  t.total_us};
  for (int s = 0; s < kStages; ++s) ++bins_[std::size_t(s) * kBins + BinOf(values[s])];
  ++count_;
}

double StageHistogram::Quantile(int stage, double q) const {
  if (count_ == 0) return 0.0;
  // Nearest rank, as freespace::Quantile: the k-th smallest, 0-based.
  const std::size_t k =
      std::min(count_ - 1, std::size_t(std::ceil(q * double(count_))) - (q > 0 ? 1 : 0));
  std::size_t seen = 0;
  const std::uint32_t* bins = bins_.data() + std::size_t(stage) * kBins;
  for (int b = 0; b < kBins; ++b) {
    seen += bins[b];
    if (seen > k) return b == 0 ? 0.0 : BinValue(b);
  }
  return BinValue(kBins - 1);
}

nlohmann::json StageHistogram::Summary() const {
  nlohmann::json out = nlohmann::json::object();
  for (int s = 0; s < kStages; ++s) {
    const double median = Quantile(s, 0.5), p99 = Quantile(s, 0.99);
    out[kStageNames[s]] = {{"median", std::round(median * 100) / 100},
                           {"p99", std::round(p99 * 100) / 100}};
  }
  return out;
}

double StageHistogram::MedianTotal() const { return Quantile(kStages - 1, 0.5); }

}  // namespace freespace
