// The BVH's storage (covering/bvh.h): the leaf blocks hold exactly the solid's non-degenerate
// covering triangles, each once, bit for bit, inside its leaf node's box, for every leaf size;
// the children pairs form one tree in treelet order.
#include "cover/covering/bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <tuple>

#include "cover/covering/bvh_walk.h"
#include "cover/covering/detail/triangles.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/predicates.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "helpers.h"

namespace cover {
namespace {

/// A triangle as comparable bits: leaf, then the 9 coordinates' bit patterns.
using Key = std::array<uint64_t, 10>;
Key key(uint32_t leaf, const Vec3& a, const Vec3& b, const Vec3& c) {
  Key k{leaf};
  const Vec3* v[3] = {&a, &b, &c};
  for (int i = 0; i < 3; ++i) std::memcpy(&k[1 + 3 * i], v[i], sizeof(Vec3));
  return k;
}

/// Solids with triangles, quads (fan triangles), faces with false-edge holes, -0.0 next to 0.0
/// and several leaves.
std::vector<std::pair<std::string, Solid>> solids() {
  std::vector<std::pair<std::string, Solid>> out;
  out.emplace_back("knot", make_leaf(read_mesh(test::source_dir() / "models/knot.off"), "knot"));
  out.emplace_back("rings",
                   make_leaf(read_mesh(test::source_dir() / "models/box_with_rings.off"), "r"));
  PolygonMesh signed_zero = make_box({-0.0, 0, -0.0}, {1, 1, 1});
  signed_zero.vertices.push_back({0, -0.0, 0});  // an unused vertex: no effect, but present
  out.emplace_back("csg", subtract({make_leaf(make_sphere({0, 0, 0}, 1, 24), "s"),
                                    make_leaf(std::move(signed_zero), "b"),
                                    make_leaf(make_box({-2, -0.5, -0.5}, {2, 0.5, 0.5}), "c")}));
  return out;
}

TEST(Bvh, LeafBlocksHoldEveryCoveringTriangleOnce) {
  for (const auto& [name, solid] : solids()) {
    // The independent path: every covering triangle per leaf, degenerate ones dropped.
    const detail::LeafTriangles lt = detail::covering_triangles(solid);
    std::vector<Key> expected;
    for (size_t l = 0; l + 1 < lt.leaf_start.size(); ++l)
      for (uint32_t i = lt.leaf_start[l]; i < lt.leaf_start[l + 1]; ++i) {
        const detail::CoverTri& t = lt.tris[i];
        if (orient2d(t.a, t.b, t.c, 0) != 0 || orient2d(t.a, t.b, t.c, 1) != 0 ||
            orient2d(t.a, t.b, t.c, 2) != 0)
          expected.push_back(key(static_cast<uint32_t>(l), t.a, t.b, t.c));
      }
    std::sort(expected.begin(), expected.end());
    ASSERT_GT(expected.size(), 100u) << name;
    for (uint32_t leaf_size : {1u, 2u, 4u, 7u, 64u, 1000u}) {
      SCOPED_TRACE(name + " leaf_size " + std::to_string(leaf_size));
      const Bvh bvh(solid, {.leaf_size = leaf_size});
      ASSERT_EQ(bvh.triangle_count(), expected.size());
      std::vector<int> seen(bvh.triangle_count(), 0);
      std::vector<Key> got;
      size_t leaves = 0;
      for (const Bvh::Node& node : bvh.nodes()) {
        if (node.count == 0) continue;
        ++leaves;
        ASSERT_LE(node.count, std::clamp(leaf_size, 1u, 64u));
        const Bvh::LeafBlock block = bvh.block(node);
        ASSERT_EQ(block.size(), node.count);
        for (uint32_t k = 0; k < block.size(); ++k) {
          const Bvh::Tri t = block[k];
          const uint32_t i = block.first() + k;
          ASSERT_LT(i, seen.size());
          ++seen[i];
          EXPECT_EQ(key(t.leaf, t.a, t.b, t.c), key(bvh.triangle(i).leaf, bvh.triangle(i).a,
                                                    bvh.triangle(i).b, bvh.triangle(i).c));
          EXPECT_EQ(t.face, bvh.triangle(i).face);
          EXPECT_EQ(solid.face_leaf[t.face], t.leaf);
          for (const Vec3& v : {t.a, t.b, t.c})
            for (int a = 0; a < 3; ++a) {
              EXPECT_LE(node.lo[a], v[a]);
              EXPECT_GE(node.hi[a], v[a]);
            }
          got.push_back(key(t.leaf, t.a, t.b, t.c));
        }
      }
      EXPECT_EQ(leaves, bvh.leaf_count());
      EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; }));
      std::sort(got.begin(), got.end());
      EXPECT_EQ(got, expected);
    }
  }
}

TEST(Bvh, TreeletLayout) {
  // Every children pair is reached once from the root, at an even index, its boxes inside its
  // parent's; the pairs of a treelet (kTreeletLevels levels below a root pair at a pair depth
  // that is a multiple of kTreeletLevels) lie within the kTreeletPairs pairs from its root's,
  // which walk_batch prefetches as one range.
  constexpr uint32_t kSpan = 2 * Bvh::kTreeletPairs;
  for (const auto& [name, solid] : solids())
    for (uint32_t leaf_size : {1u, 4u}) {
      SCOPED_TRACE(name + " leaf_size " + std::to_string(leaf_size));
      const Bvh bvh(solid, {.leaf_size = leaf_size});
      const auto& nodes = bvh.nodes();
      ASSERT_EQ(nodes[0].count, 0u);
      struct Item {
        uint32_t pair, parent, depth, treelet;
      };
      std::vector<int> reached(nodes.size(), 0);
      std::vector<Item> stack{{nodes[0].first, 0, 0, nodes[0].first}};
      size_t pairs = 0;
      while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        ++pairs;
        ASSERT_EQ(it.pair % 2, 0u);
        ASSERT_LT(it.pair + 1, nodes.size());
        ASSERT_EQ(reached[it.pair]++, 0);
        EXPECT_GE(it.pair, it.treelet);
        EXPECT_LT(it.pair, it.treelet + kSpan);
        for (const uint32_t c : {it.pair, it.pair + 1}) {
          for (int a = 0; a < 3; ++a) {
            EXPECT_GE(nodes[c].lo[a], nodes[it.parent].lo[a]);
            EXPECT_LE(nodes[c].hi[a], nodes[it.parent].hi[a]);
          }
          if (nodes[c].count > 0) continue;
          const uint32_t d = it.depth + 1;
          const uint32_t child = nodes[c].first;
          stack.push_back({child, c, d, d % Bvh::kTreeletLevels == 0 ? child : it.treelet});
        }
      }
      EXPECT_EQ(2 + 2 * pairs, nodes.size());
    }
}

}  // namespace
}  // namespace cover
