// What `freespace run` counts for summary.json (docs/formats.md). Scan counts are scans of the
// log, a rig's too; a rig's cycle is one call of the estimator, one polygon, and the counts of
// what a call reports (jitter, a stalled clock, resets, the sweep, the polygon's) are calls.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eval/stage_stats.hpp"
#include "freespace/freespace.hpp"

namespace freespace::cli {

struct RunTally {
  // A rig's sensor: its scans in processed cycles, those without a usable echo, and the
  // processed cycles without a scan of it.
  struct Sensor {
    long scans = 0, no_update = 0, missing = 0;
  };

  long scans_read = 0;  // scans read (a rig: every scan of every cycle read)
  long processed = 0;   // scans of the processed calls
  long calls = 0;       // processed calls, each with its polygon line (a rig: cycles)
  long cycles_read = 0, cycles_rejected = 0;  // a rig
  long no_update = 0;                         // scans that added nothing to the map
  long malformed = 0, resets = 0, jitter = 0;
  long stalled = 0;  // calls while the clock stalled
  long swept = 0;    // calls placed from the sensors' motion during their sweep (sensor.sweep_s)
  long invalid_range = 0, out_of_aperture = 0, bad_layer = 0, clutter = 0, virtual_points = 0;
  long points = 0, max_vertices = 0, vehicle_outside = 0, no_free_space = 0;
  double vertex_sum = 0;
  std::size_t snapshots = 0;
  std::map<std::string, long> rejected;  // scans, by reason
  std::vector<Sensor> sensors;           // a rig: one per sensor; else empty
  StageHistogram times;                  // fixed memory however long the log

  explicit RunTally(int rig_sensors) : sensors(std::size_t(rig_sensors > 1 ? rig_sensors : 0)) {}

  bool rig() const { return !sensors.empty(); }
  void AddPoints(const ScanStats& st);
  // A call's scans that added nothing and a rig's sensors without a scan in it
  // (Result::cycle_silent_sensors; one sensor: its status). A cycle `cut` short by --max-scans
  // misses its dropped sensors by that cut: none counts as missing.
  struct Silent {
    long scans = 0, missing = 0;
  };
  Silent AddSilent(const Result& r, const std::vector<Scan>& cycle, bool cut);
  void AddRejected(const Result& r, long scans);
  void AddProcessed(const Result& r, long scans);
  long Rejected() const;
  // The counts of summary.json, the rig's sensors named from `config`.
  nlohmann::json Counts(const Config& config) const;
};

}  // namespace freespace::cli
