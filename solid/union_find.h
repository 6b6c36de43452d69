#pragma once
// Disjoint sets over the indices 0..n−1 (components of meshes, patches, corner fans, points of
// equal value).

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace cover {

/// Disjoint sets over 0..n−1 with path halving. The root of a set is its smallest index, so the
/// sets' representatives do not depend on the order of the unions.
class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }

  /// The smallest index in x's set. Precondition: x < n.
  uint32_t find(uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }

  /// Merges the sets of a and b. Precondition: a, b < n.
  void unite(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<uint32_t> parent_;
};

}  // namespace cover
