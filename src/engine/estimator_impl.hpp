// The estimator's inside (freespace/estimator.hpp keeps it behind a pointer): the stages of
// DESIGN.md's pipeline, each behind the interface chosen once from the config.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/alignment.hpp"
#include "core/backend.hpp"
#include "core/crew.hpp"
#include "core/preprocess.hpp"
#include "engine/map_aligner.hpp"
#include "freespace/estimator.hpp"
#include "polygon_extractor.hpp"
#include "sensor_model.hpp"

namespace freespace {

class Estimator::Impl {
 public:
  explicit Impl(const Config& config);

  const Result& Process(const Scan& scan);
  void Reset();
  MapView map() const;

  const Config& config() const { return config_; }
  const Backend& backend() const { return *backend_; }

 private:
  // The steps of Process(), in order. Each false return ends the scan (rejected).
  void Begin(const Scan& scan);
  bool CheckInput(const Scan& scan);
  bool Align(const Scan& scan);
  void UpdateMap(bool has_update, const Scan& scan);
  void ClassifyAndScan();
  void ExtractPolygon();
  const Result& Reject(RejectReason reason, const char* text);

  Config config_;
  std::unique_ptr<Backend> backend_;
  std::unique_ptr<Crew> crew_;  // the backend's helpers, if it wants any (Backend::WantedCrew)
  std::unique_ptr<Preprocessor> preprocess_;
  CircleAligner circle_;
  std::unique_ptr<MapAligner> aligner_;
  std::unique_ptr<SensorModel> sensor_model_;
  std::unique_ptr<PolygonExtractor> polygon_;
  Result result_;
  std::uint64_t scans_ = 0;
  Pose2D last_sensor_;  // sensor pose of the last accepted scan
  mutable std::vector<LogOdds> map_mirror_;
  mutable std::vector<std::uint8_t> free_mirror_;
};

}  // namespace freespace
