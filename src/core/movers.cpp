// The mover layer: see movers.hpp.
#include "core/movers.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/point_match.hpp"
#include "core/preprocess.hpp"

namespace freespace {

namespace {

bool Overlap(const Vec2& lo_a, const Vec2& hi_a, const Vec2& lo_b, const Vec2& hi_b, double gate) {
  return lo_a.x() - gate <= hi_b.x() && lo_b.x() - gate <= hi_a.x() &&
         lo_a.y() - gate <= hi_b.y() && lo_b.y() - gate <= hi_a.y();
}

using Observation = MoverTracker::Observation;

// An observation of the run `points` at time t.
void Finish(const std::vector<Vec2>& points, double t, std::vector<Observation>* out) {
  Observation o;
  o.t = t;
  o.points = points;
  o.lo = o.hi = points.front();
  Vec2 sum = Vec2::Zero();
  for (const Vec2& p : points) {
    sum += p;
    o.lo = o.lo.cwiseMin(p);
    o.hi = o.hi.cwiseMax(p);
  }
  o.centroid = sum / double(points.size());
  o.ends[0] = points.front();
  o.ends[1] = points.back();
  out->push_back(std::move(o));
}

}  // namespace

MoverRule MoverRule::Of(const Config& config) {
  MoverRule rule;
  if (config.polygon.shape == PolygonShape::kInside) rule.memory_s = config.polygon.mover_memory_s;
  rule.join_m = 2.0 * config.clutter.eps_m;
  rule.join_per_m = 2.0 * config.clutter.eps_per_m;
  double bin_deg = config.is_rig() ? 0.0 : config.sensor.angular_resolution_deg;
  for (const SensorConfig& sensor : config.sensors)
    bin_deg = std::max(bin_deg, sensor.angular_resolution_deg);
  rule.bin_width_rad = bin_deg * M_PI / 180.0;
  rule.parallel = config.backend.threads == 0;
  return rule;
}

void MoverTracker::Clear() {
  for (auto& h : history_) h.clear();
  view_.clear();
  tracks_.clear();
  for (Pending& pending : pending_) pending.ready = false;
}

void MoverTracker::BeginCycle(double t) {
  view_.clear();
  tracks_.erase(
      std::remove_if(tracks_.begin(), tracks_.end(),
                     [&](const Track& track) { return t - track.seen.back().t > rule_.memory_s; }),
      tracks_.end());
}

void MoverTracker::Detect(int sensor, const Pose2D& pose, double t,
                          const std::vector<Beam>& beams) {
  Pending& pending = pending_[sensor];
  pending.ready = true;
  pending.found.clear();
  Outline& outline = pending.outline;
  outline = Outline();
  outline.pose = pose;
  outline.cos_yaw = std::cos(pose.yaw);
  outline.sin_yaw = std::sin(pose.yaw);
  outline.t = t;
  const std::size_t n = beams.size();
  std::vector<Vec2>& points = pending.points;
  points.resize(n);
  outline.angle.reserve(n);
  outline.range.reserve(n);
  outline.world.reserve(n);
  outline.beam.reserve(n);
  outline.real.reserve(n);
  // The beams' points, angles and ranges in one pass (several at once), then the outline.
  pending.angle.resize(n);
  pending.range.resize(n);
  const double c = outline.cos_yaw, s = outline.sin_yaw;
  Vec2* world = points.data();
  float* angle = pending.angle.data();
  float* range = pending.range.data();
  // The vertices gathered first (a Beam holds them among other fields, which keeps the loop
  // below from running on vectors), into the arrays that then take their angles and ranges.
  for (std::size_t i = 0; i < n; ++i) {
    angle[i] = beams[i].x;
    range[i] = beams[i].y;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const float x = angle[i], y = range[i];
    world[i] = Vec2(pose.x + c * x - s * y, pose.y + s * x + c * y);
    angle[i] = FastAtan2(y, x);
    range[i] = std::sqrt(x * x + y * y);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Beam& b = beams[i];
    float a = pending.angle[i];
    // Unwrapped past +-180 deg (an aperture may cross it): the angles run on from the first.
    if (!outline.angle.empty() && a < outline.angle.back() - float(M_PI)) a += float(2.0 * M_PI);
    // The deskewed beams keep their order but for a rounding: the inside test needs it strict.
    if (!outline.angle.empty() && a <= outline.angle.back()) continue;
    outline.angle.push_back(a);
    outline.range.push_back(pending.range[i]);
    outline.world.push_back(points[i]);
    outline.beam.push_back(std::uint32_t(i));
    outline.real.push_back(!b.is_virtual);
  }
  // The reference: the newest outline at least lag_s old.
  const std::deque<Outline>& history = history_[sensor];
  for (auto it = history.rbegin(); it != history.rend(); ++it) {
    if (it->t <= t - rule_.lag_s && it->t >= t - 4.0 * rule_.lag_s) {
      FindMoving(*it, beams, &pending);
      break;
    }
  }
  for (Observation& o : pending.found) o.sensor = sensor;
}

void MoverTracker::Commit() {
  ++cycle_;
  for (int sensor = 0; sensor < kMaxSensors; ++sensor) {
    Pending& pending = pending_[sensor];
    if (!pending.ready) continue;
    pending.ready = false;
    Associate(&pending.found);
    std::deque<Outline>& history = history_[sensor];
    const double t = pending.outline.t;
    history.push_back(std::move(pending.outline));
    while (history.size() > 1 && (history.size() > 256 || history[1].t <= t - rule_.lag_s)) {
      history.pop_front();
    }
    if (std::find(view_.begin(), view_.end(), sensor) == view_.end()) view_.push_back(sensor);
  }
}

void MoverTracker::FindMoving(const Outline& reference, const std::vector<Beam>& beams,
                              Pending* pending) const {
  const Outline& outline = pending->outline;
  const std::vector<Vec2>& points = pending->points;
  std::vector<Observation>* found = &pending->found;
  const double t = outline.t;
  std::vector<std::uint8_t> moving(beams.size(), 0);
  // Came nearer: this scan's echo inside the reference outline.
  const auto nearer = [&] {
    ToOutlineFrame(reference, points, &pending->near);
    std::size_t hint = 0;
    for (std::size_t i = 0; i < beams.size(); ++i) {
      const Beam& b = beams[i];
      if (b.is_virtual) continue;
      const double margin = rule_.tolerance_m + 2.0 * b.range * rule_.bin_width_rad;
      moving[i] =
          InsideOutlineAt(reference, pending->near, i, rule_.bin_width_rad, margin, kSpread, &hint);
    }
  };
  // Went away: the reference's echo inside this outline; the beams on either side of it see past
  // (marked apart: the two loops may run at once).
  std::vector<std::uint8_t> past(beams.size(), 0);
  const auto away = [&] {
    ToOutlineFrame(outline, reference.world, &pending->away);
    std::size_t at = 0;
    for (std::size_t k = 0; k < reference.angle.size(); ++k) {
      if (!reference.real[k]) continue;
      const double margin = rule_.tolerance_m + 2.0 * reference.range[k] * rule_.bin_width_rad;
      if (!InsideOutlineAt(outline, pending->away, k, rule_.bin_width_rad, margin, kSpread, &at))
        continue;
      past[outline.beam[at - 1]] = past[outline.beam[at]] = 1;
    }
  };
  if (rule_.parallel) {
    tbb::parallel_invoke(nearer, away);
  } else {
    nearer();
    away();
  }
  for (std::size_t i = 0; i < beams.size(); ++i) moving[i] |= past[i];
  // Whether the beam beyond a run's end at index `beyond` leaves that end an end of the object.
  const auto true_end = [&](std::size_t end, std::ptrdiff_t beyond) {
    if (beyond < 0 || std::size_t(beyond) >= beams.size()) return false;  // the aperture
    const Beam& b = beams[std::size_t(beyond)];
    return b.is_virtual || b.range > beams[end].range;
  };
  std::vector<Vec2> run;
  std::size_t first = 0;
  int count = 0;
  const auto close = [&](std::size_t end) {  // the run is beams[first .. end)
    if (!run.empty() && count >= kMinMovingBeams) {
      Finish(run, t, found);
      Observation& o = found->back();
      o.strong = count >= kMinMovingShare * double(run.size());
      o.true_end[0] = true_end(first, std::ptrdiff_t(first) - 1);
      o.true_end[1] = true_end(end - 1, std::ptrdiff_t(end));
    }
    run.clear();
    count = 0;
  };
  Vec2 last = Vec2::Zero();
  float last_range = 0.0f;
  for (std::size_t i = 0; i < beams.size(); ++i) {
    const Beam& b = beams[i];
    if (b.is_virtual) {
      close(i);
      continue;
    }
    const Vec2& p = points[i];
    const double join = rule_.join_m + rule_.join_per_m * std::min(last_range, b.range);
    if (!run.empty() && (p - last).norm() > join) close(i);
    if (run.empty()) first = i;
    count += moving[i];
    run.push_back(p);
    last = p;
    last_range = b.range;
  }
  close(beams.size());
  found->erase(std::remove_if(
                   found->begin(), found->end(),
                   [&](const Observation& o) { return (o.hi - o.lo).norm() > rule_.max_extent_m; }),
               found->end());
}

bool MoverTracker::Moving(const Track& track) const {
  return track.hits >= kMinHits && track.velocity.norm() >= rule_.min_speed_mps;
}

int MoverTracker::movers() const {
  int n = 0;
  for (const Track& track : tracks_) n += Moving(track);
  return n;
}

std::vector<Vec2> MoverTracker::mover_velocities() const {
  std::vector<Vec2> v;
  for (const Track& track : tracks_) {
    if (Moving(track)) v.push_back(track.velocity);
  }
  return v;
}

namespace {

// The velocity from observation `a` to the later `b`: registered from the motion of the object's
// ends both show as ends; false when they share none or the two do not fit.
bool VelocityBetween(const Observation& a, const Observation& b, Vec2* velocity) {
  const double dt = b.t - a.t;
  Vec2 sum = Vec2::Zero();
  int n = 0;
  for (int e = 0; e < 2; ++e) {
    if (!a.true_end[e] || !b.true_end[e]) continue;
    sum += b.ends[e] - a.ends[e];
    ++n;
  }
  // Without an end of the object in both, a motion along its surface would not show.
  if (n == 0) return false;
  const Vec2 motion = sum / double(n);
  const PointGrid grid(a.points);
  const Fit moved = Registered(grid, b.points, motion);
  if (!moved.fits) return false;
  // A surface that matches itself along its length (a wall, a rail) fits any shift along it: the
  // object stands still unless the shift fits clearly better than none.
  const Fit still = Registered(grid, b.points, Vec2::Zero());
  const bool stands = still.near && still.pairs >= moved.pairs - std::max(2, moved.pairs / 20);
  *velocity = (stands ? still.shift : moved.shift) / dt;
  return true;
}

}  // namespace

void MoverTracker::Associate(std::vector<Observation>* found) {
  constexpr double kGateM = 1.5;
  // Each observation to the track whose last observation, moved on by its velocity, lies within
  // the gate and nearest; several observations of one track in a scan are merged.
  std::vector<int> owner(found->size(), -1);
  for (std::size_t i = 0; i < found->size(); ++i) {
    const Observation& o = (*found)[i];
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < tracks_.size(); ++k) {
      const Observation& last = tracks_[k].seen.back();
      const Vec2 shift = tracks_[k].velocity * (o.t - last.t);
      if (!Overlap(o.lo, o.hi, last.lo + shift, last.hi + shift, kGateM)) continue;
      // Half of its echoes where the track's last ones, moved on, were: not the object next to
      // it (a row of parked cars matches itself one car along).
      const double share = MatchedShare(PointGrid(last.points), o.points, shift, 1.0);
      if (share < kMinMatchedShare) continue;
      const double d = (last.centroid + shift - o.centroid).norm();
      if (d < best) {
        best = d;
        owner[i] = int(k);
      }
    }
  }
  const std::size_t existing = tracks_.size();
  std::vector<int> merged_into(existing, -1);  // index into `found` of the track's observation
  for (std::size_t i = 0; i < found->size(); ++i) {
    Observation& o = (*found)[i];
    if (owner[i] < 0) {
      if (!o.strong) continue;  // too few moving echoes to start a track
      tracks_.emplace_back();
      tracks_.back().seen.push_back(std::move(o));
      tracks_.back().hits = 1;
      tracks_.back().last_cycle = cycle_;
      continue;
    }
    int& into = merged_into[std::size_t(owner[i])];
    if (into < 0) {
      into = int(i);
      continue;
    }
    // Two runs of one object: their points together, no known ends.
    std::vector<Vec2> points = (*found)[std::size_t(into)].points;
    points.insert(points.end(), o.points.begin(), o.points.end());
    const bool strong = o.strong || (*found)[std::size_t(into)].strong;
    std::vector<Observation> one;
    Finish(points, o.t, &one);
    one.front().strong = strong;
    one.front().sensor = o.sensor;
    (*found)[std::size_t(into)] = std::move(one.front());
  }
  for (std::size_t k = 0; k < existing; ++k) {
    if (merged_into[k] >= 0) Join(&tracks_[k], std::move((*found)[std::size_t(merged_into[k])]));
  }
}

void MoverTracker::Join(Track* track, Observation o) {
  if (track->last_cycle != cycle_) {
    ++track->hits;
    track->last_cycle = cycle_;
  }
  std::deque<Observation>& seen = track->seen;
  // The velocity over the window, from the oldest observation of the same sensor in it at least
  // 0.1 s back: another scanner sees other ends of the object.
  for (const Observation& old : seen) {
    if (old.sensor != o.sensor || old.t < o.t - kVelocityWindowS) continue;
    Vec2 measured;
    if (o.t - old.t >= 0.1 && VelocityBetween(old, o, &measured)) {
      track->velocity = track->measured ? 0.5 * (track->velocity + measured) : measured;
      track->measured = true;
    }
    break;
  }
  // In time order (a rig's scans of one cycle come in sensor order); of one sensor's, the newest
  // and one each kStoreS before it.
  auto at = seen.end();
  while (at != seen.begin() && std::prev(at)->t > o.t) --at;
  const auto same = [&](std::deque<Observation>::iterator from) {
    while (from != seen.begin()) {
      --from;
      if (from->sensor == o.sensor) return from;
    }
    return seen.end();
  };
  const auto previous = same(at);
  if (previous != seen.end()) {
    const auto before = same(previous);
    if (before != seen.end() && o.t - before->t < kStoreS) {
      at = seen.erase(previous);
      while (at != seen.end() && at->t <= o.t) ++at;
    }
  }
  seen.insert(at, std::move(o));
  while (seen.front().t < seen.back().t - kKeepS) seen.pop_front();
}

bool MoverTracker::InView(const Vec2& p) const {
  for (const int sensor : view_) {
    const Outline* outline = &history_[sensor].back();
    if (InsideOutline(*outline, p, rule_.bin_width_rad, 0.0)) return true;
  }
  return false;
}

void MoverTracker::Hazard(double t, const MapFrame& frame, std::vector<std::int32_t>* cells) {
  const std::size_t map_cells = std::size_t(frame.width) * frame.height;
  if (marks_.size() * 64 < map_cells) marks_.assign((map_cells + 63) / 64, 0);
  const double c = std::cos(frame.yaw), s = std::sin(frame.yaw), k = 1.0 / frame.resolution_m;
  // Each predicted point's cell with the widest radius asked for it (cells), then its disc.
  std::vector<std::pair<std::int64_t, double>> centres;
  for (const Track& track : tracks_) {
    if (!Moving(track)) continue;
    for (const Observation& o : track.seen) {
      const double age = std::max(0.0, t - o.t);
      const Vec2 shift = track.velocity * age;
      // Cells; no wider than the map, which keeps the keys below apart.
      const double radius = std::min((rule_.dilation_m + rule_.speed_sigma_mps * age) * k,
                                     double(frame.width + frame.height));
      for (const Vec2& p : o.points) {
        const Vec2 d = p + shift - frame.origin;
        const double u = (c * d.x() + s * d.y()) * k, v = (-s * d.x() + c * d.y()) * k;
        if (!(u >= -radius && v >= -radius && u <= frame.width + radius &&
              v <= frame.height + radius))
          continue;  // off the map (or not a number)
        const std::int64_t col = std::int64_t(std::floor(u)), row = std::int64_t(std::floor(v));
        centres.emplace_back((row + 65536) * 262144 + (col + 65536), radius);
      }
    }
  }
  std::sort(centres.begin(), centres.end());
  const std::size_t first = cells->size();
  for (std::size_t i = 0; i < centres.size(); ++i) {
    if (i + 1 < centres.size() && centres[i + 1].first == centres[i].first)
      continue;  // widest last
    const int row = int(centres[i].first / 262144 - 65536);
    const int col = int(centres[i].first % 262144 - 65536);
    const double radius = centres[i].second;
    const int reach = int(std::ceil(radius));
    for (int r = std::max(0, row - reach); r <= std::min(frame.height - 1, row + reach); ++r) {
      for (int q = std::max(0, col - reach); q <= std::min(frame.width - 1, col + reach); ++q) {
        const double dr = r - row, dq = q - col;
        if (dr * dr + dq * dq > radius * radius) continue;
        const std::size_t at = std::size_t(r) * frame.width + q;
        std::uint64_t& word = marks_[at >> 6];
        const std::uint64_t bit = std::uint64_t{1} << (at & 63);
        if (word & bit) continue;
        word |= bit;
        cells->push_back(std::int32_t(at));
      }
    }
  }
  // Clear the marks; keep the cells no scan of this cycle sees free now.
  std::size_t kept = first;
  for (std::size_t i = first; i < cells->size(); ++i) {
    const std::int32_t at = (*cells)[i];
    marks_[std::size_t(at) >> 6] = 0;
    const double u = (at % frame.width + 0.5) * frame.resolution_m;
    const double v = (at / frame.width + 0.5) * frame.resolution_m;
    const Vec2 p = frame.origin + Vec2(c * u - s * v, s * u + c * v);
    if (!InView(p)) (*cells)[kept++] = at;
  }
  cells->resize(kept);
}

}  // namespace freespace
