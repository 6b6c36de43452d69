// io/serialize.h: a Solid survives the trip through bytes exactly (same arrays, same tree,
// same answers), and bytes that are not a solid — every truncation, random damage — are refused
// with InputError, never read out of bounds (the checked build runs this under ASan).
#include "cover/io/serialize.h"

#include <gtest/gtest.h>

#include <random>

#include "cover/io/scene.h"
#include "cover/solid/errors.h"
#include "cover/solid/primitives.h"
#include "helpers.h"

namespace cover {
namespace {

void expect_same(const Solid& a, const Solid& b) {
  EXPECT_TRUE(
      std::equal(a.vertices.begin(), a.vertices.end(), b.vertices.begin(), b.vertices.end()));
  EXPECT_TRUE(std::equal(a.face_start.begin(), a.face_start.end(), b.face_start.begin(),
                         b.face_start.end()));
  EXPECT_TRUE(std::equal(a.face_vertices.begin(), a.face_vertices.end(), b.face_vertices.begin(),
                         b.face_vertices.end()));
  EXPECT_TRUE(
      std::equal(a.face_leaf.begin(), a.face_leaf.end(), b.face_leaf.begin(), b.face_leaf.end()));
  EXPECT_TRUE(
      std::equal(a.face_sign.begin(), a.face_sign.end(), b.face_sign.begin(), b.face_sign.end()));
  ASSERT_EQ(a.leaves.size(), b.leaves.size());
  for (size_t l = 0; l < a.leaves.size(); ++l) {
    EXPECT_EQ(a.leaves[l].name, b.leaves[l].name);
    EXPECT_EQ(a.leaves[l].origin, b.leaves[l].origin);
    EXPECT_EQ(a.leaves[l].flipped, b.leaves[l].flipped);
    EXPECT_EQ(a.leaves[l].colour, b.leaves[l].colour);
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
  Solid coloured = small_scene();
  coloured.leaves[0].colour = std::array<uint8_t, 3>{255, 0, 16};
  for (const Solid& s : {scene, small_scene(), Solid{}, coloured}) {
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
    EXPECT_EQ(std::string(e.what()), "worker cache: not a Cover solid: truncated at byte 8 of 8");
  }
}

TEST(Serialize, RandomDamageIsRefusedOrReadsAValidSolid) {
  const std::string bytes = solid_to_bytes(small_scene());
  std::mt19937_64 rng(7);
  size_t refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string damaged = bytes;
    const int flips = 1 + static_cast<int>(rng() % 4);
    for (int f = 0; f < flips; ++f)
      damaged[rng() % damaged.size()] ^= static_cast<char>(1 + rng() % 255);
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

/// The message of solid_from_bytes(bytes), or "" when it reads.
std::string refusal(const std::string& bytes) {
  try {
    solid_from_bytes(bytes);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A unit cube leaf whose mesh is `m` (taken as it is, without the loader's repairs).
Solid raw_leaf(PolygonMesh m, bool open_flag = false) {
  Solid s = make_leaf(std::move(m), "cube");
  s.leaves[0].boundary_edges = open_flag ? 1 : 0;
  return s;
}

PolygonMesh unit_cube() { return make_box({0, 0, 0}, {1, 1, 1}); }

/// The cube without its face f.
PolygonMesh cube_without_face(size_t f) {
  const PolygonMesh cube = unit_cube();
  PolygonMesh m;
  m.vertices = cube.vertices;
  for (size_t g = 0; g < cube.face_count(); ++g)
    if (g != f) m.add_face(std::vector<uint32_t>(cube.face(g).begin(), cube.face(g).end()));
  return m;
}

TEST(Serialize, FaceWithFewerThanThreeVerticesIsRefused) {
  PolygonMesh m = unit_cube();
  m.add_face(std::vector<uint32_t>{0, 1});
  EXPECT_NE(refusal(solid_to_bytes(raw_leaf(std::move(m)))).find("face 6: 2 vertices (at least 3"),
            std::string::npos);
}

TEST(Serialize, LeafFlaggedClosedWithAFaceMissingIsRefused) {
  // Read as closed it had volume 5/6 (the covering of five faces).
  const std::string why = refusal(solid_to_bytes(raw_leaf(cube_without_face(2))));
  EXPECT_NE(why.find("leaf 0 ('cube'): flagged closed, but its faces have 4 boundary edge(s)"),
            std::string::npos)
      << why;
}

TEST(Serialize, ClosedLeafFlaggedOpenIsRefused) {
  // Read as open it crashed classify, volume and voxelize (a winding tree with no boundary).
  const std::string why = refusal(solid_to_bytes(raw_leaf(unit_cube(), true)));
  EXPECT_NE(why.find("flagged open, but its faces are closed"), std::string::npos) << why;
}

TEST(Serialize, InsideOutClosedLeafIsRefused) {
  PolygonMesh m = unit_cube();
  for (size_t f = 0; f < m.face_count(); ++f)
    std::reverse(m.face_vertices.begin() + m.face_start[f],
                 m.face_vertices.begin() + m.face_start[f + 1]);
  const std::string why = refusal(solid_to_bytes(raw_leaf(std::move(m))));
  EXPECT_NE(why.find("leaf 0 ('cube'): inside-out (signed volume -1"), std::string::npos) << why;
}

TEST(Serialize, InconsistentlyOrientedClosedLeafIsRefused) {
  PolygonMesh m = unit_cube();
  std::reverse(m.face_vertices.begin() + m.face_start[3],
               m.face_vertices.begin() + m.face_start[4]);
  const std::string why = refusal(solid_to_bytes(raw_leaf(std::move(m))));
  EXPECT_NE(why.find("is not traversed equally often in each direction"), std::string::npos) << why;
}

TEST(Serialize, FaceSignsAgainstTheExpressionAreRefused) {
  // Leaf 1's faces reversed and their signs negated: its own orientation is unchanged, but the
  // union does not reverse it.
  Solid s = unite({make_leaf(unit_cube(), "a"), make_leaf(make_box({2, 0, 0}, {3, 1, 1}), "b")});
  for (uint32_t f = s.leaves[1].first_face; f < s.leaves[1].first_face + s.leaves[1].face_count;
       ++f) {
    std::reverse(s.face_vertices.begin() + s.face_start[f],
                 s.face_vertices.begin() + s.face_start[f + 1]);
    s.face_sign[f] = -1;
  }
  const std::string why = refusal(solid_to_bytes(s));
  EXPECT_NE(why.find("face 6: sign -1, but its leaf's place in the expression gives 1"),
            std::string::npos)
      << why;
}

TEST(Serialize, NodeUsedAsTwoOperandsIsRefused) {
  Solid s = small_scene();
  s.tree.nodes.push_back(CsgNode{CsgOp::kUnion, 0, {s.tree.root, 0}});  // node 0 used twice
  s.tree.root = static_cast<uint32_t>(s.tree.nodes.size() - 1);
  EXPECT_NE(refusal(solid_to_bytes(s)).find("node 0 is the operand of 2 operations"),
            std::string::npos);
}

TEST(Serialize, OpenLeafKeepsItsBoundaryCount) {
  std::vector<std::string> warnings;
  const Solid open = prepare_leaf(cube_without_face(2), "open", "open", LoadOptions{}, warnings);
  ASSERT_EQ(open.leaves[0].boundary_edges, 4);
  const Solid s = subtract({open, make_leaf(make_box({0.2, 0.2, 0.2}, {0.4, 0.4, 2}), "hole")});
  const Solid back = solid_from_bytes(solid_to_bytes(s));
  EXPECT_EQ(back.leaves[0].boundary_edges, 4);
  EXPECT_EQ(back.leaves[1].boundary_edges, 0);
  expect_same(s, back);
}

}  // namespace
}  // namespace cover
