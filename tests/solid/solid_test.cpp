// The non-evaluated solid (solid/solid.h): concatenation, sign flips, the kept CSG tree.
#include "cover/solid/solid.h"

#include <gtest/gtest.h>

#include "cover/solid/measure.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"

namespace cover {
namespace {

Solid box(Vec3 lo, Vec3 hi) { return make_leaf(make_box(lo, hi), "box"); }

// Transform::fit: the box's centre to `centre`, its largest extent to 2·half_size, the rotation
// about its centre; checked on points whose images are known exactly.
TEST(Solid, TransformFitPlacesTheBoxCentreAndLargestExtent) {
  const Bbox box{{1, 2, 3}, {5, 3, 4}};  // centre (3, 2.5, 3.5), largest extent 4 (x)
  const Transform t = Transform::fit(box, {10, 0, -1}, 0.5);
  EXPECT_EQ(t(Vec3{3, 2.5, 3.5}), (Vec3{10, 0, -1}));
  EXPECT_EQ(t(Vec3{5, 2.5, 3.5}), (Vec3{10.5, 0, -1}));
  EXPECT_EQ(t(Vec3{3, 3, 3.5}), (Vec3{10, 0.125, -1}));
  // A half turn about z through the centre: +x goes to −x.
  const Vec3 p = Transform::fit(box, {0, 0, 0}, 2, {0, 0, 1}, 180)(Vec3{5, 2.5, 3.5});
  EXPECT_NEAR(p.x, -2, 1e-15);
  EXPECT_NEAR(p.y, 0, 1e-15);
  EXPECT_EQ(p.z, 0);
}

TEST(Solid, UnionConcatenatesVerticesFacesAndLeaves) {
  const Solid u = unite({box({0, 0, 0}, {1, 1, 1}), box({2, 0, 0}, {3, 1, 1})});
  EXPECT_EQ(u.vertices.size(), 16u);
  EXPECT_EQ(u.face_count(), 12u);
  ASSERT_EQ(u.leaves.size(), 2u);
  EXPECT_EQ(u.leaves[1].first_vertex, 8u);
  EXPECT_EQ(u.leaves[1].first_face, 6u);
  for (size_t f = 6; f < 12; ++f) {
    EXPECT_EQ(u.face_leaf[f], 1u);
    for (uint32_t v : u.face(f)) EXPECT_GE(v, 8u);
  }
  EXPECT_EQ(u.tree.nodes[u.tree.root].op, CsgOp::kUnion);
}

TEST(Solid, DifferenceFlipsTheSubtrahend) {
  const Solid d = subtract({box({0, 0, 0}, {2, 2, 2}), box({0.5, 0.5, 0.5}, {1, 1, 1})});
  for (size_t f = 0; f < 6; ++f) EXPECT_EQ(d.face_sign[f], 1);
  for (size_t f = 6; f < 12; ++f) EXPECT_EQ(d.face_sign[f], -1);
  // The summed covering is vol(A) − vol(B) ([Segura2004 §4]); each leaf keeps its own orientation.
  PolygonMesh all;
  all.vertices = d.vertices;
  for (size_t f = 0; f < d.face_count(); ++f) all.add_face(d.face(f));
  EXPECT_DOUBLE_EQ(signed_volume(all), 8.0 - 0.125);
  EXPECT_DOUBLE_EQ(signed_volume(leaf_mesh(d, 1)), 0.125);
}

TEST(Solid, ComplementTwiceRestoresFaces) {
  const Solid a = box({0, 0, 0}, {1, 1, 1});
  const Solid cc = complement(complement(a));
  EXPECT_EQ(cc.face_vertices, a.face_vertices);
  EXPECT_EQ(cc.face_sign, a.face_sign);
  EXPECT_EQ(cc.tree.nodes.size(), 3u);
}

TEST(Solid, TreeEvaluatesAnyNesting) {
  // (A − B) ∪ C
  const Solid s = unite({subtract({box({0, 0, 0}, {1, 1, 1}), box({0, 0, 0}, {1, 1, 1})}),
                         box({0, 0, 0}, {1, 1, 1})});
  auto eval = [&](bool a, bool b, bool c) {
    const std::vector<uint8_t> in{a, b, c};
    return s.tree.evaluate(in);
  };
  for (int m = 0; m < 8; ++m) {
    const bool a = m & 1, b = m & 2, c = m & 4;
    EXPECT_EQ(eval(a, b, c), (a && !b) || c) << m;
  }
  const Solid i = intersect({box({0, 0, 0}, {1, 1, 1}), complement(box({0, 0, 0}, {1, 1, 1}))});
  EXPECT_FALSE(i.tree.evaluate(std::vector<uint8_t>{1, 1}));
  EXPECT_TRUE(i.tree.evaluate(std::vector<uint8_t>{1, 0}));
}

TEST(Solid, PrimitivesAreClosedAndOutward) {
  EXPECT_GT(signed_volume(make_sphere({1, 2, 3}, 0.5, 7)), 0);
  EXPECT_GT(signed_volume(make_cylinder({0, 0, 0}, {1, 1, 1}, 0.2, 5)), 0);
  EXPECT_GT(signed_volume(make_cylinder({0, 0, 0}, {0, 0, -1}, 0.2, 3)), 0);
  EXPECT_DOUBLE_EQ(signed_volume(make_box({-1, -1, -1}, {1, 1, 1})), 8.0);
}

}  // namespace
}  // namespace cover
