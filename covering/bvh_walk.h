#pragma once
// The BVH's traversal loops (covering/bvh.h layout): internal to Cover's kernels (classify,
// rays, octree, evaluate), not part of the installed interface.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "cover/covering/bvh.h"

namespace cover {

/// Calls visit(t, i) for each triangle t (index i) of the leaf node whose `first` and `count`
/// are given (its block's word offset and its number of triangles).
template <typename Visit>
void for_each_triangle(const Bvh& bvh, uint32_t first, uint32_t count, Visit&& visit) {
  const Bvh::LeafBlock block(bvh.block_words() + first);
  for (uint32_t k = 0; k < count; ++k) visit(block[k], block.first() + k);
}
template <typename Visit>
void for_each_triangle(const Bvh& bvh, const Bvh::Node& leaf, Visit&& visit) {
  for_each_triangle(bvh, leaf.first, leaf.count, visit);
}

/// Depth-first walk: for every leaf node reached through nodes whose bounds satisfy
/// `meets(node)`, calls `visit(t, i)` for each of its triangles t (index i). The one traversal
/// loop of the single-query paths (cell grid half-lines, rays, octree boxes).
template <typename Meets, typename Visit>
void walk(const Bvh& bvh, Meets&& meets, Visit&& visit) {
  const auto& nodes = bvh.nodes();
  if (nodes.empty()) return;
  uint32_t stack[Bvh::kMaxStack];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const uint32_t id = stack[--top];
    const Bvh::Node& node = nodes[id];
    if (!meets(node)) continue;
    if (node.count == 0) {
      // Both children share one cache line; fetch it while the stack is updated.
      __builtin_prefetch(&nodes[node.first]);
      stack[top++] = node.first + 1;
      stack[top++] = node.first;
      continue;
    }
    for_each_triangle(bvh, node, visit);
  }
}

/// The same node tests as walk() for each query j < n of a batch, and leaf(j, first, count) for
/// every leaf node that meets (its `first` and `count`, as for_each_triangle takes them), made
/// breadth first over the whole batch with prefetching: a node's children are fetched a few
/// entries before they are tested, and a leaf's triangles a few entries before leaf() reads them.
/// Why: one query's walk is a chain of dependent loads, and once the structure outgrows the cache
/// (80 MB at 1M triangles) each is a miss; across a batch the loads are independent, so their
/// misses overlap. Each level (and the leaf pass) first prefetches its first few entries, so a
/// small batch gets its loads overlapped too: cast() of one ray is this walk with n = 1 (a level
/// of one ray holds a few nodes). A small level also fetches whole treelets at their top (one
/// wait for memory per kTreeletLevels levels; its leaves' blocks are not fetched as soon as they
/// meet, which would slow a single ray down by about a tenth at 10k–100k triangles). A
/// leaf's first and count are copied when its node is tested, so the leaf pass reads blocks
/// only, no node lines. Measured in bench/bench_queries
/// (BM_ClassifyPoint, batches of 1000 random points; BM_CastRay, one ray per call; 1 thread): see
/// docs/benchmarks.md. Each query's calls are walk()'s, in another order: callers must not depend
/// on it.
/// meets_both(j, a, b) tests two boxes at once (bit 0: a meets query j, bit 1: b does), so that a
/// caller can test a node's children in SIMD lanes; the root is tested as (root, root).
template <typename MeetsBoth, typename Leaf>
void walk_batch(const Bvh& bvh, uint32_t n, MeetsBoth&& meets_both, Leaf&& leaf) {
  const auto& nodes = bvh.nodes();
  if (nodes.empty() || n == 0) return;
  struct Entry {
    uint32_t query;
    uint32_t node;  ///< the first of the children pair of a node that meets
  };
  struct LeafEntry {
    uint32_t query;
    uint32_t first, count;  ///< the leaf node's
  };
  struct Scratch {
    std::vector<Entry> level, next;
    std::vector<LeafEntry> leaves;
  };
  // Entries between a prefetch and the use of what it fetched: a node pair is one cache line, a
  // leaf block about four, so leaves are fetched fewer entries ahead (the core tracks a few
  // dozen outstanding misses; prefetches beyond that stall).
  constexpr size_t kAhead = 16, kLeafAhead = 4;
  thread_local Scratch scratch;  // reused across calls; one TLS lookup, not one per access
  auto& [level, next, leaves] = scratch;
  // A block's size is not in the node: fetch its records and count + 2 vertices (a mesh patch
  // of count triangles has about that many; more are read without prefetch).
  auto prefetch_triangles = [&](const LeafEntry& x) {
    const auto begin = reinterpret_cast<uintptr_t>(&bvh.block_words()[x.first]);
    const uintptr_t end =
        begin + Bvh::LeafBlock::vertices_offset(x.count) + sizeof(Vec3) * (x.count + 2);
    for (uintptr_t p = begin & ~uintptr_t{63}; p < end; p += 64)
      __builtin_prefetch(reinterpret_cast<const void*>(p));
  };
  level.clear();
  leaves.clear();
  for (uint32_t j = 0; j < n; ++j)
    if (meets_both(j, nodes[0], nodes[0]) & 1) {
      if (nodes[0].count > 0)
        leaves.push_back({j, nodes[0].first, nodes[0].count});
      else
        level.push_back({j, nodes[0].first});
    }
  int depth = 0;  // of the pairs in `level` (0: the root's children)
  while (!level.empty()) {
    // Every entry is an inner node: test its two children, keep the ones that meet. The
    // children are written unconditionally and the counts advanced by the outcome (no branch
    // on it: it is unpredictable, and mispredictions cost more than the box tests).
    next.resize(2 * level.size());
    const size_t leaf_base = leaves.size();
    leaves.resize(leaf_base + 2 * level.size());
    Entry* inner_out = next.data();
    LeafEntry* leaf_out = leaves.data() + leaf_base;
    for (size_t e = 0; e < std::min(kAhead, level.size()); ++e)
      __builtin_prefetch(&nodes[level[e].node]);
    // A small level (one ray's walk) at a treelet's top fetches the whole treelets: their lines
    // are contiguous (bvh.cpp treelet_order), at most kTreeletPairs pairs each (the first is
    // the entry's own, fetched above).
    if (level.size() <= kAhead && depth % Bvh::kTreeletLevels == 0)
      for (const Entry& x : level)
        for (uint32_t i = 1; i < Bvh::kTreeletPairs; ++i)
          __builtin_prefetch(&nodes[std::min<size_t>(x.node + 2 * i, nodes.size() - 1)]);
    ++depth;
    for (size_t e = 0; e < level.size(); ++e) {
      if (e + kAhead < level.size()) __builtin_prefetch(&nodes[level[e + kAhead].node]);
      const Entry x = level[e];
      const uint32_t l = x.node, r = l + 1;
      const unsigned both = meets_both(x.query, nodes[l], nodes[r]);
      const bool l_leaf = nodes[l].count > 0, r_leaf = nodes[r].count > 0;
      *inner_out = {x.query, nodes[l].first};
      inner_out += (both & 1) & !l_leaf;
      *leaf_out = {x.query, nodes[l].first, nodes[l].count};
      leaf_out += (both & 1) & l_leaf;
      *inner_out = {x.query, nodes[r].first};
      inner_out += (both >> 1) & !r_leaf;
      *leaf_out = {x.query, nodes[r].first, nodes[r].count};
      leaf_out += (both >> 1) & r_leaf;
    }
    next.resize(static_cast<size_t>(inner_out - next.data()));
    leaves.resize(static_cast<size_t>(leaf_out - leaves.data()));
    level.swap(next);
  }
  for (size_t e = 0; e < std::min(kLeafAhead, leaves.size()); ++e) prefetch_triangles(leaves[e]);
  for (size_t e = 0; e < leaves.size(); ++e) {
    if (e + kLeafAhead < leaves.size()) prefetch_triangles(leaves[e + kLeafAhead]);
    leaf(leaves[e].query, leaves[e].first, leaves[e].count);
  }
}

}  // namespace cover
