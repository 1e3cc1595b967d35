// Disjoint sets against a brute-force partition: the sets joined so far, by their members.

#include <scanplan/core/disjoint_sets.h>

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

namespace scanplan {
namespace {

TEST(DisjointSets, JoinKeepsTheTargetsRootAndTruncateForgetsTheLast) {
  DisjointSets sets(4);
  EXPECT_TRUE(sets.join(3, 1));
  EXPECT_EQ(sets.find(3), 1);
  EXPECT_TRUE(sets.join(1, 0));
  EXPECT_EQ(sets.find(3), 0);
  EXPECT_FALSE(sets.join(3, 0));  // one set already
  EXPECT_EQ(sets.find(2), 2);
  sets.add();
  EXPECT_EQ(sets.size(), 5u);
  EXPECT_EQ(sets.find(4), 4);
  sets.truncate(4);
  EXPECT_EQ(sets.size(), 4u);
}

TEST(DisjointSets, SetsMatchABruteForcePartitionOverRandomJoins) {
  constexpr int n = 60;
  std::mt19937 random(7);
  std::uniform_int_distribution<int> pick(0, n - 1);
  DisjointSets sets(n);
  std::vector<int> label(n);  // brute force: every member relabelled on each join
  for (int i = 0; i < n; ++i) label[i] = i;
  for (int join = 0; join < 45; ++join) {
    const int a = pick(random), b = pick(random);
    EXPECT_EQ(sets.join(a, b), label[a] != label[b]);
    const int from = label[a], to = label[b];
    for (int& l : label)
      if (l == from) l = to;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        ASSERT_EQ(sets.find(i) == sets.find(j), label[i] == label[j]) << i << ", " << j;
  }
  std::set<int> roots;
  for (int i = 0; i < n; ++i) roots.insert(sets.find(i));
  EXPECT_EQ(roots.size(), std::set<int>(label.begin(), label.end()).size());
}

}  // namespace
}  // namespace scanplan
