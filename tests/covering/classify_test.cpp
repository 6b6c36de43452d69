// Exact classification (covering/classify.h): boxes' corners, edges, faces; triangulated faces;
// false-edge holes; non-convex faces; result-level rules; nested expressions vs a truth table; a
// solid whose whole BVH is one leaf.
#include "cover/covering/classify.h"

#include <gtest/gtest.h>

#include <random>

#include "cover/covering/ray.h"
#include "cover/solid/parallel.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "helpers.h"

namespace cover {
namespace {

using PC = PointClass;

Solid box_solid(Vec3 lo, Vec3 hi) { return make_leaf(make_box(lo, hi), "box"); }

PC one(const Solid& s, Vec3 p) { return classify(s, std::span<const Vec3>(&p, 1))[0]; }

/// Checks corners → vertex, edge midpoints → edge, face centres → face, centre → inside, and a
/// few outside points, for the box [lo, hi] inside `s`.
void expect_box_classes(const Solid& s, Vec3 lo, Vec3 hi) {
  const double xs[3] = {lo.x, 0.5 * (lo.x + hi.x), hi.x};
  const double ys[3] = {lo.y, 0.5 * (lo.y + hi.y), hi.y};
  const double zs[3] = {lo.z, 0.5 * (lo.z + hi.z), hi.z};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        const int extremes = (i != 1) + (j != 1) + (k != 1);
        const PC expected = extremes == 3   ? PC::kVertex
                            : extremes == 2 ? PC::kEdge
                            : extremes == 1 ? PC::kFace
                                            : PC::kInside;
        const Vec3 p{xs[i], ys[j], zs[k]};
        EXPECT_EQ(one(s, p), expected) << p.x << " " << p.y << " " << p.z;
      }
  EXPECT_EQ(one(s, {hi.x + 1, ys[1], zs[1]}), PC::kOutside);
  EXPECT_EQ(one(s, {xs[1], std::nextafter(lo.y, -1e300), zs[1]}), PC::kOutside);
  EXPECT_EQ(one(s, {xs[1], ys[1], std::nextafter(hi.z, 1e300)}), PC::kOutside);
  EXPECT_EQ(one(s, {xs[1], ys[1], std::nextafter(hi.z, -1e300)}), PC::kInside);
}

TEST(Classify, BoxLeafCornersEdgesFaces) {
  expect_box_classes(box_solid({0, 0, 0}, {1, 2, 3}), {0, 0, 0}, {1, 2, 3});
  expect_box_classes(box_solid({-1.5, 0.1, 7}, {0.3, 0.7, 9.1}), {-1.5, 0.1, 7}, {0.3, 0.7, 9.1});
}

TEST(Classify, TriangulatedBoxDiagonalsAreFaces) {
  const Vec3 lo{0, 0, 0}, hi{2, 2, 2};
  const Solid s = make_leaf(test::triangulate(make_box(lo, hi)), "tri-box");
  expect_box_classes(s, lo, hi);
  // A point on a diagonal between two coplanar triangles, off the centre.
  EXPECT_EQ(one(s, {0.5, 0.5, 0}), PC::kFace);
}

TEST(Classify, BoxInUnionWithDisjointSolid) {
  const Vec3 lo{0, 0, 0}, hi{1, 1, 1};
  const Solid s = unite({box_solid(lo, hi), make_leaf(make_sphere({5, 5, 5}, 1, 16), "sphere")});
  expect_box_classes(s, lo, hi);
  EXPECT_EQ(one(s, {5, 5, 5}), PC::kInside);
}

TEST(Classify, FaceWithHoleByFalseEdges) {
  const Solid s = make_leaf(test::frame_box(0, 4, 1, 3), "frame");
  EXPECT_EQ(one(s, {2, 2, 2}), PC::kOutside);   // in the hole
  EXPECT_EQ(one(s, {0.5, 2, 2}), PC::kInside);  // in the frame
  EXPECT_EQ(one(s, {0.5, 2, 4}), PC::kFace);    // top face, frame part
  EXPECT_EQ(one(s, {2, 2, 4}), PC::kOutside);   // top plane, inside the hole
  EXPECT_EQ(one(s, {1, 2, 4}), PC::kEdge);      // hole rim on the top face
  EXPECT_EQ(one(s, {1, 1, 4}), PC::kVertex);    // hole corner
  EXPECT_EQ(one(s, {1, 2, 2}), PC::kFace);      // hole wall
  EXPECT_EQ(one(s, {0, 1, 4}), PC::kEdge);      // false edge's endpoint is on the outer edge
  // On the false edge itself (between vertex 4 and 12): interior of the top face.
  EXPECT_EQ(one(s, {0.5, 0.5, 4}), PC::kFace);
}

TEST(Classify, NonConvexFaces) {
  // L-shaped prism: top/bottom are one non-convex hexagon each.
  PolygonMesh m;
  const double L[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  for (int z = 0; z < 2; ++z)
    for (auto& p : L) m.vertices.push_back({p[0], p[1], double(z)});
  m.add_face({5, 4, 3, 2, 1, 0});    // bottom, normal −z
  m.add_face({6, 7, 8, 9, 10, 11});  // top, normal +z
  for (uint32_t i = 0; i < 6; ++i) m.add_face({i, (i + 1) % 6, 6 + (i + 1) % 6, 6 + i});
  const Solid s = make_leaf(m, "L");
  EXPECT_EQ(one(s, {1.5, 1.5, 0.5}), PC::kOutside);  // in the notch
  EXPECT_EQ(one(s, {1.5, 1.5, 1}), PC::kOutside);    // notch, on the top plane
  EXPECT_EQ(one(s, {0.5, 1.5, 0.5}), PC::kInside);
  EXPECT_EQ(one(s, {0.5, 1.5, 1}), PC::kFace);
  EXPECT_EQ(one(s, {1, 1, 0.5}), PC::kEdge);    // reflex edge
  EXPECT_EQ(one(s, {1, 1, 1}), PC::kVertex);    // reflex vertex
  EXPECT_EQ(one(s, {1, 1.5, 0.5}), PC::kFace);  // notch wall
}

TEST(Classify, ResultLevelRules) {
  const Solid a = box_solid({0, 0, 0}, {2, 2, 2});
  const Solid b = box_solid({1, -1, -1}, {3, 3, 3});
  const Solid u = unite({a, b});
  EXPECT_EQ(one(u, {2, 1, 1}), PC::kInside);  // A's face x = 2 is buried in B
  EXPECT_EQ(one(u, {1, 1, 1}), PC::kInside);  // B's face x = 1 is buried in A
  EXPECT_EQ(one(u, {1, 1, 2}), PC::kEdge);    // concave crease: A's top meets B's wall
  EXPECT_EQ(one(u, {0.5, 1, 2}), PC::kFace);
  // Two boxes sharing a face: the shared face is interior to the union.
  const Solid c = box_solid({2, 0, 0}, {4, 2, 2});
  EXPECT_EQ(one(unite({a, c}), {2, 1, 1}), PC::kInside);
  EXPECT_EQ(one(unite({a, c}), {2, 1, 2}), PC::kFace);  // flat top across the seam
  EXPECT_EQ(one(unite({a, c}), {2, 2, 2}), PC::kEdge);  // straight crease across the seam
  // Difference: carved surfaces.
  const Solid d = subtract({a, b});
  EXPECT_EQ(one(d, {1, 1, 1}), PC::kFace);  // B's wall x = 1 inside A
  EXPECT_EQ(one(d, {1.5, 1, 1}), PC::kOutside);
  EXPECT_EQ(one(d, {1, 0, 1}), PC::kEdge);  // B's wall meets A's face y = 0
  EXPECT_EQ(one(d, {1, 0, 0}), PC::kVertex);
  // Intersection of a box with itself: same classes as the box.
  expect_box_classes(intersect({a, a}), {0, 0, 0}, {2, 2, 2});
  // A minus itself is empty everywhere.
  EXPECT_EQ(one(subtract({a, a}), {1, 1, 1}), PC::kOutside);
  EXPECT_EQ(one(subtract({a, a}), {2, 1, 1}), PC::kOutside);
  // Complement: the box's boundary stays the boundary.
  EXPECT_EQ(one(complement(a), {1, 1, 1}), PC::kOutside);
  EXPECT_EQ(one(complement(a), {5, 1, 1}), PC::kInside);
  EXPECT_EQ(one(complement(a), {2, 1, 1}), PC::kFace);
  EXPECT_EQ(one(complement(a), {2, 2, 2}), PC::kVertex);
}

bool in_box(Vec3 p, Vec3 lo, Vec3 hi) {
  return p.x > lo.x && p.x < hi.x && p.y > lo.y && p.y < hi.y && p.z > lo.z && p.z < hi.z;
}

TEST(Classify, NestedExpressionTruthTable) {
  // (A − B) ∪ C with overlapping A, B, C.
  const Vec3 alo{0, 0, 0}, ahi{2, 2, 2}, blo{1, 1, -1}, bhi{3, 3, 3}, clo{1.5, 1.5, 1.5},
      chi{2.5, 2.5, 2.5};
  const Solid s =
      unite({subtract({box_solid(alo, ahi), box_solid(blo, bhi)}), box_solid(clo, chi)});
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-0.5, 3.5);
  std::vector<Vec3> pts(10000);
  for (Vec3& p : pts) p = {u(rng), u(rng), u(rng)};
  const auto classes = classify(s, pts);
  int in = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const Vec3 p = pts[i];
    const bool truth = (in_box(p, alo, ahi) && !in_box(p, blo, bhi)) || in_box(p, clo, chi);
    in += truth;
    ASSERT_EQ(classes[i], truth ? PC::kInside : PC::kOutside) << i;
  }
  EXPECT_GT(in, 500);  // the table is not trivially all-outside
  // The paper's single threshold would fail here: in B and C but not in A.
  EXPECT_EQ(one(s, {2.2, 2.2, 2.2}), PC::kInside);
}

TEST(Classify, MirroredSolidKeepsClasses) {
  PolygonMesh m = make_box({0, 0, 0}, {1, 1, 1});
  apply_transform(Transform::trs({-1, 2, 1}, {0, 0, 1}, 0, {0, 0, 0}), m);  // det < 0
  const Solid s = make_leaf(m, "mirrored");
  expect_box_classes(s, {-1, 0, 0}, {0, 2, 1});
}

TEST(Classify, SameResultsWithOneAndTwoThreads) {
  const Solid s = unite(
      {subtract({box_solid({0, 0, 0}, {2, 2, 2}), make_leaf(make_sphere({2, 2, 2}, 1.2, 24), "s")}),
       make_leaf(make_cylinder({0, 0, 0}, {0, 0, 3}, 0.5, 12), "c")});
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> grid(-2, 10);  // many points exactly on faces and edges
  std::vector<Vec3> pts(3000);
  for (Vec3& p : pts) p = {grid(rng) * 0.25, grid(rng) * 0.25, grid(rng) * 0.25};
  std::vector<PC> one_thread, two_threads;
  {
    ThreadLimit limit(1);
    one_thread = classify(s, pts);
  }
  {
    ThreadLimit limit(2);
    two_threads = classify(s, pts);
  }
  EXPECT_EQ(one_thread, two_threads);
}

TEST(Classify, TetrahedronWholeBvhIsOneLeaf) {
  // Four triangles: the BVH root is itself a leaf (the batch walk's first case).
  const Solid s = make_leaf(test::unit_tetrahedron(), "tetra");
  const Prepared prepared(s);
  const Bvh& bvh = prepared.bvh();
  ASSERT_EQ(bvh.nodes().size(), 2u);  // the root and the unused pair padding
  ASSERT_GT(bvh.nodes()[0].count, 0u);
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> grid(-1, 5);  // eighths: on faces, edges, vertices too
  std::vector<Vec3> pts(500);
  for (Vec3& p : pts) p = {grid(rng) * 0.25, grid(rng) * 0.25, grid(rng) * 0.25};
  const std::vector<PC> got = classify(prepared, pts);
  EXPECT_EQ(got, classify_brute_force(s, pts));
  EXPECT_EQ(one(s, {0.1, 0.1, 0.1}), PC::kInside);
  EXPECT_EQ(one(s, {0.5, 0.5, 0}), PC::kEdge);
  EXPECT_EQ(one(s, {0, 0, 0}), PC::kVertex);
  EXPECT_EQ(one(s, {0.6, 0.6, 0.6}), PC::kOutside);
  // Rays: the batch cast() walks the same one-leaf tree.
  std::vector<Ray> rays;
  for (int i = 0; i < 40; ++i) rays.push_back({{-1, 0.02 * i, 0.1}, {1, 0.01 * i, 0.05}});
  const std::vector<RayResult> batch = cast(prepared, rays);
  for (size_t i = 0; i < rays.size(); ++i) {
    const RayResult single = cast_depth_first(bvh, s.tree, s.leaves.size(), rays[i]);
    ASSERT_EQ(batch[i].hits.size(), single.hits.size()) << i;
    for (size_t h = 0; h < single.hits.size(); ++h) EXPECT_EQ(batch[i].hits[h].t, single.hits[h].t);
    EXPECT_EQ(cast(bvh, s.tree, s.leaves.size(), rays[i]).hits.size(), single.hits.size()) << i;
  }
  EXPECT_EQ(batch[0].hits.size(), 2u);
}

TEST(Classify, WindingOfNestedShells) {
  // Two nested outward boxes in one leaf: winding 2 inside the inner one (nonzero rule: inside).
  PolygonMesh m = make_box({0, 0, 0}, {4, 4, 4});
  const PolygonMesh inner = make_box({1, 1, 1}, {3, 3, 3});
  for (Vec3 v : inner.vertices) m.vertices.push_back(v);
  for (size_t f = 0; f < inner.face_count(); ++f) {
    std::vector<uint32_t> loop(inner.face(f).begin(), inner.face(f).end());
    for (uint32_t& v : loop) v += 8;
    m.add_face(loop);
  }
  const Solid s = make_leaf(m, "nested");
  std::vector<int> w;
  std::vector<uint8_t> on;
  leaf_windings(s, {2, 2, 2}, w, on);
  EXPECT_EQ(w[0], 2);
  leaf_windings(s, {0.5, 2, 2}, w, on);
  EXPECT_EQ(w[0], 1);
  EXPECT_EQ(one(s, {2, 2, 2}), PC::kInside);
  EXPECT_EQ(one(s, {1, 2, 2}), PC::kInside);  // inner surface: winding 2 | 1, inside both sides
}

}  // namespace
}  // namespace cover
