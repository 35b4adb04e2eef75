// What `freespace run` counts: see run_tally.hpp.
#include "run_tally.hpp"

#include <algorithm>

namespace freespace::cli {

void RunTally::AddPoints(const ScanStats& st) {
  points += st.points;
  invalid_range += st.invalid_range;
  out_of_aperture += st.out_of_aperture;
  bad_layer += st.bad_layer;
  clutter += st.clutter;
  virtual_points += st.virtual_points;
}

RunTally::Silent RunTally::AddSilent(const Result& r, const std::vector<Scan>& cycle, bool cut) {
  Silent silent;
  if (!rig()) {
    silent.scans = r.status == ScanStatus::kNoSensorUpdate ? 1 : 0;
    no_update += silent.scans;
    return silent;
  }
  for (const int s : r.cycle_silent_sensors) {
    if (s < 0 || std::size_t(s) >= sensors.size()) continue;
    const bool scanned =
        std::any_of(cycle.begin(), cycle.end(), [&](const Scan& scan) { return scan.sensor == s; });
    if (scanned) {
      ++sensors[std::size_t(s)].no_update;
      ++silent.scans;
    } else if (!cut) {
      ++sensors[std::size_t(s)].missing;
      ++silent.missing;
    }
  }
  no_update += silent.scans;
  return silent;
}

void RunTally::AddRejected(const Result& r, long scans) {
  rejected[ToString(r.reject_reason)] += scans;
  cycles_rejected += rig() ? 1 : 0;
}

void RunTally::AddProcessed(const Result& r, long scans) {
  processed += scans;
  ++calls;
  for (const int s : r.cycle_sensors) {
    if (s >= 0 && std::size_t(s) < sensors.size()) ++sensors[std::size_t(s)].scans;
  }
  times.Add(r.times);
  vertex_sum += double(r.polygon.size());
  max_vertices = std::max<long>(max_vertices, long(r.polygon.size()));
  // A call without a polygon (nothing free around yet) misses nothing: counted apart.
  if (r.polygon_status == PolygonStatus::kOk) {
    vehicle_outside += r.polygon_contains_vehicle ? 0 : 1;
  } else {
    ++no_free_space;
  }
}

long RunTally::Rejected() const {
  long total = 0;
  for (const auto& [reason, n] : rejected) total += n;
  return total;
}

nlohmann::json RunTally::Counts(const Config& config) const {
  nlohmann::json by_reason = nlohmann::json::object();
  for (const auto& [reason, n] : rejected) by_reason[reason] = n;
  nlohmann::json cycles;  // null for one sensor
  if (rig()) {
    nlohmann::json per_sensor = nlohmann::json::object();
    for (std::size_t s = 0; s < sensors.size(); ++s) {
      per_sensor[config.sensor_at(int(s)).name] = {{"scans", sensors[s].scans},
                                                   {"no_update", sensors[s].no_update},
                                                   {"missing", sensors[s].missing}};
    }
    cycles = {{"read", cycles_read},
              {"processed", calls},
              {"rejected", cycles_rejected},
              {"sensors", per_sensor}};
  }
  return {
      {"scans_read", scans_read},
      {"scans", processed},
      {"skipped", Rejected() + malformed},
      {"rejected", by_reason},
      {"malformed_lines", malformed},
      {"no_sensor_update", no_update},
      {"cycles", cycles},
      {"map_resets", resets},
      {"timestamp_jitter", jitter},
      {"clock_stalled", stalled},
      {"sweep_corrected", swept},
      {"points",
       {{"total", points},
        {"invalid_range", invalid_range},
        {"out_of_aperture", out_of_aperture},
        {"bad_layer", bad_layer},
        {"clutter", clutter},
        {"virtual", virtual_points}}},
      {"polygon",
       {{"max_vertices", max_vertices},
        {"mean_vertices", calls ? vertex_sum / double(calls) : 0.0},
        {"vehicle_outside", vehicle_outside},
        {"no_free_space", no_free_space}}},
      {"snapshots", snapshots},
  };
}

}  // namespace freespace::cli
