// Disjoint sets (solid/union_find.h): the representative is the smallest index of its set,
// whatever the order of the unions.
#include "cover/solid/union_find.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

namespace cover {
namespace {

TEST(UnionFind, RootIsTheSmallestIndexInAnyUnionOrder) {
  // Sets {0, 3, 6, 9}, {1, 4, 7}, {2, 5, 8}, {10}: pairs i ~ i + 3 for i < 7.
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (uint32_t i = 0; i + 3 < 10; ++i) pairs.emplace_back(i + 3, i);
  std::mt19937 rng(5);
  for (int round = 0; round < 20; ++round) {
    std::shuffle(pairs.begin(), pairs.end(), rng);
    UnionFind sets(11);
    for (const auto& [a, b] : pairs) sets.unite(a, b);
    for (uint32_t x = 0; x < 11; ++x) EXPECT_EQ(sets.find(x), x < 10 ? x % 3 : 10) << x;
  }
}

}  // namespace
}  // namespace cover
