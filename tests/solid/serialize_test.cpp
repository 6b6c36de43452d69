// solid/serialize.h: a Solid survives the trip through bytes exactly (same arrays, same tree,
// same answers), and bytes that are not a solid — every truncation, random damage — are refused
// with InputError, never read out of bounds (the checked build runs this under ASan).
#include <gtest/gtest.h>

#include <random>

#include "helpers.h"
#include "solid/errors.h"
#include "solid/primitives.h"
#include "solid/scene.h"
#include "solid/serialize.h"

namespace cover {
namespace {

void expect_same(const Solid& a, const Solid& b) {
  EXPECT_TRUE(std::equal(a.vertices.begin(), a.vertices.end(), b.vertices.begin(), b.vertices.end()));
  EXPECT_TRUE(std::equal(a.face_start.begin(), a.face_start.end(), b.face_start.begin(), b.face_start.end()));
  EXPECT_TRUE(std::equal(a.face_vertices.begin(), a.face_vertices.end(), b.face_vertices.begin(),
                         b.face_vertices.end()));
  EXPECT_TRUE(std::equal(a.face_leaf.begin(), a.face_leaf.end(), b.face_leaf.begin(), b.face_leaf.end()));
  EXPECT_TRUE(std::equal(a.face_sign.begin(), a.face_sign.end(), b.face_sign.begin(), b.face_sign.end()));
  ASSERT_EQ(a.leaves.size(), b.leaves.size());
  for (size_t l = 0; l < a.leaves.size(); ++l) {
    EXPECT_EQ(a.leaves[l].name, b.leaves[l].name);
    EXPECT_EQ(a.leaves[l].origin, b.leaves[l].origin);
    EXPECT_EQ(a.leaves[l].flipped, b.leaves[l].flipped);
    EXPECT_EQ(a.leaves[l].bbox.min, b.leaves[l].bbox.min);
    EXPECT_EQ(a.leaves[l].bbox.max, b.leaves[l].bbox.max);
  }
  ASSERT_EQ(a.tree.nodes.size(), b.tree.nodes.size());
  EXPECT_EQ(a.tree.root, b.tree.root);
  for (size_t n = 0; n < a.tree.nodes.size(); ++n) {
    EXPECT_EQ(a.tree.nodes[n].op, b.tree.nodes[n].op);
    EXPECT_EQ(a.tree.nodes[n].leaf, b.tree.nodes[n].leaf);
    EXPECT_EQ(a.tree.nodes[n].children, b.tree.nodes[n].children);
  }
}

Solid small_scene() {
  const Solid a = make_leaf(make_box({0, 0, 0}, {1, 1, 1}), "a", "/union/0");
  const Solid b = make_leaf(make_box({0.5, 0.5, 0.5}, {2, 2, 2}), "b");
  return unite({subtract({a, b}), complement(complement(b))});
}

TEST(Serialize, RoundTripIsExact) {
  const Solid scene = load_input(test::source_dir() / "models" / "default.json").solid;
  for (const Solid& s : {scene, small_scene(), Solid{}}) {
    const std::string bytes = solid_to_bytes(s);
    const Solid back = solid_from_bytes(bytes);
    expect_same(s, back);
    EXPECT_EQ(solid_to_bytes(back), bytes);
  }
}

TEST(Serialize, EveryTruncationAndTrailingByteIsRefused) {
  const std::string bytes = solid_to_bytes(small_scene());
  for (size_t n = 0; n < bytes.size(); ++n)
    EXPECT_THROW(solid_from_bytes(std::string_view(bytes).substr(0, n)), InputError) << n;
  EXPECT_THROW(solid_from_bytes(bytes + '\0'), InputError);
  try {
    solid_from_bytes("COVERSOL", "worker cache");
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "worker cache: not a Cover solid: truncated");
  }
}

TEST(Serialize, RandomDamageIsRefusedOrReadsAValidSolid) {
  const std::string bytes = solid_to_bytes(small_scene());
  std::mt19937_64 rng(7);
  size_t refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string damaged = bytes;
    const int flips = 1 + static_cast<int>(rng() % 4);
    for (int f = 0; f < flips; ++f) damaged[rng() % damaged.size()] ^= static_cast<char>(1 + rng() % 255);
    try {
      const Solid s = solid_from_bytes(damaged);
      // Accepted: then it is internally consistent (re-serializes to the same bytes).
      EXPECT_TRUE(solid_to_bytes(s) == damaged) << trial;
    } catch (const InputError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 1000u);
}

}  // namespace
}  // namespace cover
