// DBSCAN as connected components: core points (at least min_points neighbours, the point
// itself included) joined when they are neighbours, border points attached to the cluster of
// their first core neighbour in scan order, the rest noise.
//
// Neighbour search in scan order. Two echoes at ranges r_i <= r_j and angular distance d are
// at least r_j * sin(d) apart, and neighbours when at most eps + k * r_j apart, so
// sin(d) <= eps / r_j + k <= eps / r_i + k: from echo i, only bins within asin(eps / r_i + k)
// can hold a neighbour.
//
// The passes run in parallel. Clusters are joined with a lock-free union-find that always
// links the larger root under the smaller, so every cluster ends up rooted at its smallest
// member whatever the thread interleaving: the result is deterministic. Only the size of a
// cluster matters (is it clutter?), which lets echoes deep inside large clusters skip the
// labelling altogether.
#include "core/dbscan.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/crew.hpp"

namespace freespace {
namespace {
constexpr int kGrain = 128;
constexpr int kMaxRecorded = 8;  // neighbours remembered per echo for the sure test
}  // namespace

ClutterFilter::ClutterFilter(const ClutterConfig& config, int bins, double bin_width_rad,
                             int threads)
    : config_(config),
      bins_(bins),
      bin_width_(bin_width_rad),
      arena_(threads),
      bin_start_(bins + 1, 0),
      cursor_(bins, 0) {}

int ClutterFilter::Find(int a) const {
  while (true) {
    const int p = parent_[a].load(std::memory_order_relaxed);
    if (p == a) return a;
    // Path halving: pointing a at an ancestor is always safe, roots only ever get linked.
    const int g = parent_[p].load(std::memory_order_relaxed);
    if (g != p) parent_[a].store(g, std::memory_order_relaxed);
    a = g;
  }
}

void ClutterFilter::Unite(int a, int b) {
  while (true) {
    a = Find(a);
    b = Find(b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    int expected = a;  // a is a root: hang it under the smaller root b
    if (parent_[a].compare_exchange_strong(expected, b, std::memory_order_relaxed)) return;
  }
}

void ClutterFilter::Reserve(int n) {
  if (n <= capacity_) return;
  capacity_ = std::max(n, 2 * capacity_);
  parent_ = std::make_unique<std::atomic<std::int32_t>[]>(capacity_);
}

void ClutterFilter::SortByBin(const std::vector<EchoPoint>& points) {
  const int n = int(points.size());
  // Counting sort by bin; stable, so scan order is kept within a bin.
  std::fill(bin_start_.begin(), bin_start_.end(), 0);
  for (const EchoPoint& p : points) ++bin_start_[p.bin + 1];
  for (int b = 0; b < bins_; ++b) bin_start_[b + 1] += bin_start_[b];
  std::copy(bin_start_.begin(), bin_start_.end() - 1, cursor_.begin());
  order_.resize(n);
  x_.resize(n);
  y_.resize(n);
  r_.resize(n);
  first_.resize(n);
  last_.resize(n);
  core_.resize(n);
  sure_.resize(n);
  found_.resize(std::size_t(n) * kMaxRecorded);
  found_count_.resize(n);
  cluster_.resize(n);
  Reserve(n + 1);
  for (int i = 0; i < n; ++i) {
    const int s = cursor_[points[i].bin]++;
    order_[s] = i;
    x_[s] = points[i].x;
    y_[s] = points[i].y;
    r_[s] = points[i].range;
  }
}

template <class Body>
void ClutterFilter::ForEachEcho(int n, const Body& body) {
  if (crew_ != nullptr) {
    // Chunks of kGrain echoes (more when there would be more chunks than a round can have).
    const int grain = std::max(kGrain, (n + Crew::kMaxParts - 1) / Crew::kMaxParts);
    crew_->Run((n + grain - 1) / grain, [&](int part, int) {
      const int end = std::min(n, (part + 1) * grain);
      for (int a = part * grain; a < end; ++a) body(a);
    });
    return;
  }
  arena_.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, n, kGrain),
                      [&](const tbb::blocked_range<int>& range) {
                        for (int a = range.begin(); a != range.end(); ++a) body(a);
                      });
  });
}

int ClutterFilter::KeepClustered(int n, std::vector<std::uint8_t>* keep) {
  const int big = config_.min_cluster_size, large = n;
  size_.assign(n + 1, 0);
  for (int a = 0; a < n; ++a) {
    if (cluster_[a] >= 0) ++size_[cluster_[a]];
  }
  const int large_root = Find(large);
  int clutter = 0;
  for (int a = 0; a < n; ++a) {
    const int c = cluster_[a] < 0 ? -1 : Find(cluster_[a]);
    const bool ok = c >= 0 && (c == large_root || size_[c] >= big);
    (*keep)[order_[a]] = ok ? 1 : 0;
    clutter += ok ? 0 : 1;
  }
  return clutter;
}

int ClutterFilter::Run(const std::vector<EchoPoint>& points, std::vector<std::uint8_t>* keep) {
  const int n = int(points.size());
  keep->assign(n, 1);
  if (!config_.enabled || n == 0) return 0;
  // The crew's helpers may sleep between scans: wake them now, while the sort below runs, and
  // keep them polling into the backend's stages that follow.
  if (crew_ != nullptr) crew_->Wake();

  SortByBin(points);
  parent_[n].store(n, std::memory_order_relaxed);

  const float eps = float(config_.eps_m), k = float(config_.eps_per_m);
  const float* x = x_.data();
  const float* y = y_.data();
  const float* r = r_.data();
  auto near = [=](int a, int b) {
    const float e = eps + k * std::max(r[a], r[b]);
    const float dx = x[a] - x[b], dy = y[a] - y[b];
    return dx * dx + dy * dy <= e * e;
  };
  // Each echo's window, then core points, searching outwards from each echo: in dense places
  // the first few candidates decide. The first min_cluster_size - 1 neighbours found are kept for
  // the next pass.
  const int min_points = config_.min_points, big = config_.min_cluster_size;
  const int wanted = std::max(min_points - 1, std::min(big - 1, kMaxRecorded));
  const std::int32_t* bin_start = bin_start_.data();
  ForEachEcho(n, [&](int a) {
    // Bin window of the echo (see the file comment): [first_, last_) in sorted order.
    const double s = config_.eps_m / std::max(double(r[a]), 1e-6) + config_.eps_per_m;
    // asin(s) <= 1.05 s for s <= 0.5; the exact asin only for echoes near the sensor.
    const double reach =
        (s <= 0.5 ? 1.05 * s : (s < 1.0 ? std::asin(s) : 2.0 * M_PI)) / bin_width_ + 1.0;
    const int bin = points[order_[a]].bin;
    const int lo = bin_start[int(std::max<double>(0, bin - reach))];
    const int hi = bin_start[int(std::min<double>(bins_ - 1, bin + reach)) + 1];
    first_[a] = lo;
    last_[a] = hi;
    parent_[a].store(a, std::memory_order_relaxed);

    // Counted up to `wanted`, the first kMaxRecorded of them kept (min_points may ask more).
    std::int32_t* found = found_.data() + std::size_t(a) * kMaxRecorded;
    int count = 0;
    const auto add = [&](int b) {
      if (count < kMaxRecorded) found[count] = b;
      ++count;
    };
    for (int d = 1; count < wanted && (a - d >= lo || a + d < hi); ++d) {
      if (a - d >= lo && near(a, a - d)) add(a - d);
      if (count < wanted && a + d < hi && near(a, a + d)) add(a + d);
    }
    found_count_[a] = std::uint8_t(std::min(count, kMaxRecorded));
    core_[a] = count + 1 >= min_points;
  });

  // A core echo with at least min_cluster_size - 1 core neighbours is in a large enough
  // cluster: they all share its cluster. Such "sure" echoes need no component labelling, which
  // leaves it to the few echoes at cluster edges, in small clusters and in noise. (Only the
  // neighbours found above are looked at: missing a sure echo costs time, never correctness.)
  const std::uint8_t* core = core_.data();
  ForEachEcho(n, [&](int a) {
    sure_[a] = 0;
    if (!core[a] || big - 1 > kMaxRecorded) return;
    const std::int32_t* found = found_.data() + std::size_t(a) * kMaxRecorded;
    int count = 0;
    for (int i = 0; i < found_count_[a]; ++i) count += core[found[i]];
    sure_[a] = count >= big - 1;
  });

  // The other core echoes: joined with their core neighbours; a join with a sure echo joins
  // the cluster node `n` that stands for every large cluster.
  const int large = n;
  const std::uint8_t* sure = sure_.data();
  ForEachEcho(n, [&](int a) {
    if (!core[a] || sure[a]) return;
    for (int b = first_[a]; b < last_[a]; ++b) {
      if (b == a || !core[b] || !near(a, b)) continue;
      Unite(a, sure[b] ? large : b);
    }
  });

  // Cluster of every echo: a sure echo's is the large node; another core echo's its root; a
  // border echo takes its first core neighbour's in scan order.
  ForEachEcho(n, [&](int a) {
    if (core[a]) {
      cluster_[a] = sure[a] ? large : Find(a);
      return;
    }
    cluster_[a] = -1;
    for (int b = first_[a]; b < last_[a]; ++b) {
      if (core[b] && near(a, b)) {
        cluster_[a] = sure[b] ? large : Find(b);
        return;
      }
    }
  });

  return KeepClustered(n, keep);
}

}  // namespace freespace
