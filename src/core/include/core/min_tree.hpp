// A tournament tree of keys by id: every inner node holds the least (key, id) of its two
// children, so the root holds the least key, of equal keys the lowest id's. A key change walks
// one leaf's path to the root, a fixed log2 steps, each picking a child by a comparison's value
// rather than by a branch; a binary heap's sifts branch on keys at every level and mispredict
// about every other time. The area simplifier of the polygon keeps its drops' costs in one
// (core/area_simplifier.hpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace freespace {

class MinTree {
 public:
  static constexpr double kNone = std::numeric_limits<double>::infinity();

  // Ids 0 .. capacity - 1; all memory is allocated here.
  explicit MinTree(int capacity)
      : key_(std::size_t(2 * LeafCount(capacity))), id_(std::size_t(2 * LeafCount(capacity))) {}

  // Ids 0 .. n - 1 (n at most the capacity) with keys[id]; no other id is ever the least.
  void Fill(const double* keys, int n) {
    leaves_ = LeafCount(n);
    for (int id = 0; id < leaves_; ++id) {
      key_[std::size_t(leaves_ + id)] = id < n ? keys[id] : kNone;
      id_[std::size_t(leaves_ + id)] = id;
    }
    for (int at = leaves_ - 1; at >= 1; --at) {
      const std::size_t pick =
          std::size_t(2 * at + (key_[std::size_t(2 * at + 1)] < key_[std::size_t(2 * at)]));
      key_[std::size_t(at)] = key_[pick];
      id_[std::size_t(at)] = id_[pick];
    }
  }
  // The least key's id and key. The key is kNone when every id is kNone or taken out.
  int top() const { return id_[1]; }
  double top_key() const { return key_[1]; }
  // Sets id's key; kNone takes it out of the running. The winner so far rides up the path in
  // registers and meets each sibling, which the walk does not change: the steps wait on no store.
  void Set(int id, double key) {
    int at = leaves_ + id;
    key_[std::size_t(at)] = key;
    double best = key;
    int who = id;
    for (; at > 1; at >>= 1) {
      const double other = key_[std::size_t(at ^ 1)];
      // The left child's ids are all below the right's: the left wins ties. Selected by masks:
      // the compiler makes branches of conditional expressions here.
      const int sibling = int(other < best) | (int(other == best) & (at & 1));
      const int mask = -sibling;
      who = (who & ~mask) | (id_[std::size_t(at ^ 1)] & mask);
      best = std::min(other, best);
      key_[std::size_t(at >> 1)] = best;
      id_[std::size_t(at >> 1)] = who;
    }
  }

 private:
  static int LeafCount(int n) {
    int leaves = 1;
    while (leaves < n) leaves *= 2;
    return leaves;
  }

  // Node 1 the root, node k's children 2k and 2k + 1, the leaves last: each node's least key
  // and its id.
  std::vector<double> key_;
  std::vector<int> id_;
  int leaves_ = 1;
};

}  // namespace freespace
