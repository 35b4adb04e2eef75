// The tournament tree the area simplifier keeps its drops' costs in, against a plain search for
// the least (key, id) over random key changes, ties and ids taken out, for sizes that are and
// are not powers of two.
#include "core/min_tree.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace freespace {
namespace {

TEST(MinTree, TopIsAlwaysTheLeastKeyOfTheLowestId) {
  std::mt19937 random(11);
  MinTree tree(70);
  for (const int n : {1, 2, 3, 5, 8, 33, 64, 70}) {
    // Few distinct keys, so that ties must fall to the lower id.
    std::vector<double> key(static_cast<std::size_t>(n));
    for (double& k : key) k = double(random() % 6);
    tree.Fill(key.data(), n);
    for (int step = 0; step < 3000; ++step) {
      const int id = int(random() % unsigned(n));
      const unsigned roll = random() % 8;
      key[std::size_t(id)] = roll == 0 ? MinTree::kNone : double(random() % 6);
      tree.Set(id, key[std::size_t(id)]);
      int least = 0;
      for (int j = 1; j < n; ++j) {
        if (key[std::size_t(j)] < key[std::size_t(least)]) least = j;
      }
      ASSERT_EQ(tree.top_key(), key[std::size_t(least)]) << "n " << n << " step " << step;
      if (key[std::size_t(least)] != MinTree::kNone) {
        ASSERT_EQ(tree.top(), least) << "n " << n << " step " << step;
      }
    }
  }
}

TEST(MinTree, EveryIdTakenOutLeavesNone) {
  const std::vector<double> key = {3.0, 1.0, 2.0};
  MinTree tree(3);
  tree.Fill(key.data(), 3);
  EXPECT_EQ(tree.top(), 1);
  tree.Set(1, MinTree::kNone);
  EXPECT_EQ(tree.top(), 2);
  tree.Set(2, MinTree::kNone);
  EXPECT_EQ(tree.top(), 0);
  tree.Set(0, MinTree::kNone);
  EXPECT_EQ(tree.top_key(), MinTree::kNone);
}

}  // namespace
}  // namespace freespace
