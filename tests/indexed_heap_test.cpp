// The indexed heap the paper polygon's simplifier keeps its segments in, against a plain
// search for the least key over random pushes, key changes and removals.
#include "core/indexed_heap.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace freespace {
namespace {

TEST(IndexedHeap, TopIsAlwaysTheLeastKeyOfTheIdsIn) {
  constexpr int kIds = 40;
  std::mt19937 random(7);
  std::vector<int> key(kIds);
  std::vector<bool> in(kIds, false);
  // Few distinct keys, so that ties fall to the lower id.
  const auto before = [&](int a, int b) { return key[a] < key[b] || (key[a] == key[b] && a < b); };
  IndexedHeap heap(kIds);
  for (auto& k : key) k = int(random() % 10);
  heap.Fill(kIds / 2, before);
  for (int id = 0; id < kIds / 2; ++id) in[std::size_t(id)] = true;
  for (int step = 0; step < 5000; ++step) {
    const int id = int(random() % kIds);
    if (!in[std::size_t(id)]) {
      key[std::size_t(id)] = int(random() % 10);
      heap.Push(id, before);
      in[std::size_t(id)] = true;
    } else if (random() % 2 == 0) {
      key[std::size_t(id)] = int(random() % 10);
      heap.Update(id, before);
    } else {
      heap.Remove(id, before);
      in[std::size_t(id)] = false;
    }
    int least = -1;
    for (int j = 0; j < kIds; ++j) {
      ASSERT_EQ(heap.contains(j), bool(in[std::size_t(j)])) << "step " << step << " id " << j;
      if (in[std::size_t(j)] && (least < 0 || before(j, least))) least = j;
    }
    ASSERT_EQ(heap.empty(), least < 0);
    if (least >= 0) {
      ASSERT_EQ(heap.top(), least) << "step " << step;
    }
    if (step % 1000 == 999) {  // Clear() takes every id out; Fill() starts again from 0 .. n - 1
      heap.Clear();
      for (int j = 0; j < kIds; ++j) EXPECT_FALSE(heap.contains(j));
      heap.Fill(kIds / 4, before);
      for (int j = 0; j < kIds; ++j) in[std::size_t(j)] = j < kIds / 4;
    }
  }
}

}  // namespace
}  // namespace freespace
