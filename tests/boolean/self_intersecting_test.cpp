// evaluate() on self-intersecting leaves (boolean/evaluate.h): each leaf is its nonzero-winding
// set, as in classify(). Every result must be a closed, outward 2-manifold without
// self-intersections (brep validate + the exact self_intersects of mesh/validate.h) that agrees
// with classify() of the non-evaluated scene on 20,000 random points (0 disagreements off the
// boundary); the procedural leaves also have known volumes. Scenes: libcgal-demo meshes that
// intersect themselves (cow, camel, bull, bones, man, elk) with boxes, spheres and each other; two
// overlapping boxes in one leaf, nested and repeated shells (winding 2), a reversed shell (winding
// 0 inside), shells touching along a face, a figure-eight prism (winding +1 and −1 lobes,
// overlapping fan caps), and a prism through a reversed box whose result touches itself along
// single edges.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cover/boolean/evaluate.h"
#include "cover/brep/halfedge.h"
#include "cover/covering/classify.h"
#include "cover/covering/volume.h"
#include "cover/io/mesh_io.h"
#include "cover/mesh/repair.h"
#include "cover/mesh/validate.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "helpers.h"

namespace cover {
namespace {

/// The mesh with vertices of equal coordinates merged (mesh/repair.h): where the result
/// touches itself (two lobes of a figure-eight meeting along a line) evaluate() duplicates
/// vertices per fan, and the touching faces then share indices, so a self-intersection test
/// counts only crossings.
PolygonMesh welded(PolygonMesh m) {
  weld_duplicate_vertices(m);
  return m;
}

/// `b` appended to `a` (one leaf of several shells); `reverse` flips b's faces.
PolygonMesh concat(PolygonMesh a, const PolygonMesh& b, bool reverse = false) {
  const uint32_t base = static_cast<uint32_t>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  std::vector<uint32_t> loop;
  for (size_t f = 0; f < b.face_count(); ++f) {
    loop.clear();
    for (uint32_t v : b.face(f)) loop.push_back(base + v);
    if (reverse) std::reverse(loop.begin(), loop.end());
    a.add_face(loop);
  }
  return a;
}

/// A libcgal-demo mesh scaled to extent 2·size about `centre`, turned by `degrees` about z.
PolygonMesh model(const std::string& name, Vec3 centre, double size, double degrees) {
  PolygonMesh m = test::triangulate(read_mesh(test::cgal_mesh(name + ".off")));
  apply_transform(Transform::fit(face_bbox(m), centre, size, {0, 0, 1}, degrees), m);
  return m;
}

/// Prism of height 1 over the figure-eight x = cos θ, y = sin θ cos θ (n points, none at the
/// crossing), caps fanned from an off-centre point: winding +1 in one lobe, −1 in the other.
PolygonMesh figure_eight(int n) {
  PolygonMesh m;
  for (int z = 0; z < 2; ++z) {
    for (int i = 0; i < n; ++i) {
      const double t = 2 * M_PI * (i + 0.5) / n;
      m.vertices.push_back({std::cos(t), std::sin(t) * std::cos(t), double(z)});
    }
  }
  m.vertices.push_back({0.3, 0.1, 0});
  m.vertices.push_back({0.3, 0.1, 1});
  const uint32_t cb = 2 * n, ct = 2 * n + 1;
  for (uint32_t i = 0; i < uint32_t(n); ++i) {
    const uint32_t j = (i + 1) % n;
    m.add_face({i, j, n + j, n + i});
    m.add_face({ct, n + i, n + j});
    m.add_face({cb, j, i});
  }
  return m;
}

/// Evaluates, checks validity and agreement with classify() of the scene; returns the volume.
double check(const Solid& scene, const std::string& label) {
  const EvaluateResult r = evaluate(scene);
  EXPECT_EQ(r.face_leaf.size(), r.mesh.face_count()) << label;
  if (r.mesh.face_count() > 0) {
    const brep::BrepReport rep = brep::validate(brep::HalfedgeMesh::from_polygon_mesh(r.mesh));
    EXPECT_TRUE(rep.consistent && rep.closed && rep.manifold) << label;
    EXPECT_FALSE(self_intersects(welded(r.mesh))) << label;  // exact, CGAL predicates
    EXPECT_GT(r.volume, 0) << label;
  }
  Bbox box = face_bbox(leaf_mesh(scene, 0));
  for (uint32_t l = 1; l < scene.leaves.size(); ++l) {
    const Bbox b = face_bbox(leaf_mesh(scene, l));
    box.add(b.min);
    box.add(b.max);
  }
  std::mt19937_64 rng(7);
  std::vector<Vec3> pts(20000);
  for (Vec3& p : pts) {
    double x[3];
    for (int a = 0; a < 3; ++a) {
      const double lo = box.min[a], hi = box.max[a], pad = 0.05 * (hi - lo);
      x[a] = std::uniform_real_distribution<double>(lo - pad, hi + pad)(rng);
    }
    p = {x[0], x[1], x[2]};
  }
  const std::vector<PointClass> want = classify(scene, pts);
  std::vector<PointClass> got(pts.size(), PointClass::kOutside);
  if (r.mesh.face_count() > 0) got = classify(make_leaf(r.mesh, "result"), pts);
  size_t disagree = 0, inside = 0;
  auto solid = [](PointClass c) { return c == PointClass::kInside || c == PointClass::kOutside; };
  for (size_t i = 0; i < pts.size(); ++i) {
    if (!solid(want[i]) || !solid(got[i])) continue;
    disagree += want[i] != got[i];
    inside += want[i] == PointClass::kInside;
  }
  EXPECT_EQ(disagree, 0u) << label;
  std::printf("%-34s faces %7zu pairs %7zu  volume %.12g  inside %zu / 20000\n", label.c_str(),
              r.mesh.face_count(), r.candidate_pairs, r.volume, inside);
  return r.volume;
}

Solid leaf(PolygonMesh m, const std::string& name) {
  EXPECT_TRUE(self_intersects(m)) << name << " should intersect itself";
  return make_leaf(std::move(m), name);
}

TEST(EvaluateSelfIntersecting, OverlappingBoxesInOneLeaf) {
  const PolygonMesh two = concat(make_box({0, 0, 0}, {2, 2, 2}), make_box({1, 1, 1}, {3, 3, 3}));
  EXPECT_NEAR(check(leaf(two, "two"), "two boxes (w = 2 overlap)"), 15, 1e-12);
  // Against another leaf: the union minus a slab through both shells.
  const Solid d =
      subtract({leaf(two, "two"), make_leaf(make_box({-1, 1.5, -1}, {4, 1.75, 4}), "s")});
  EXPECT_NEAR(check(d, "two boxes − slab"), 15 - 0.25 * 7, 1e-12);
}

TEST(EvaluateSelfIntersecting, WindingTwoAndZero) {
  const PolygonMesh outer = make_box({0, 0, 0}, {2, 2, 2});
  // Nested, same orientation (apart, so no self-intersection): winding 2 inside the inner box.
  EXPECT_NEAR(check(make_leaf(concat(outer, make_box({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5})), "nested"),
                    "nested shells (w = 2)"),
              8, 1e-12);
  // The same shell twice (coincident faces, equal orientation), minus a box.
  const Solid twice = subtract(
      {make_leaf(concat(outer, outer), "twice"), make_leaf(make_box({1, 1, 1}, {3, 3, 3}), "b")});
  EXPECT_NEAR(check(twice, "repeated shell − box"), 7, 1e-12);
  // A reversed shell in a corner (coincident faces, opposite orientation): winding 0 there.
  EXPECT_NEAR(check(make_leaf(concat(outer, make_box({0, 0, 0}, {1, 1, 1}), true), "corner"),
                    "reversed corner shell (w = 0)"),
              7, 1e-12);
  // Two shells touching along a face: one box, the shared face gone.
  EXPECT_NEAR(
      check(make_leaf(concat(make_box({0, 0, 0}, {1, 1, 1}), make_box({1, 0, 0}, {2, 1, 1})),
                      "touching"),
            "shells sharing a face"),
      2, 1e-12);
  // A shell and its reversed copy: winding 0 everywhere, an empty result.
  EXPECT_EQ(check(make_leaf(concat(outer, outer, true), "void"), "shell and its reverse"), 0);
}

TEST(EvaluateSelfIntersecting, FigureEight) {
  const PolygonMesh f = figure_eight(24);
  const double v = check(leaf(f, "eight"), "figure-eight prism");
  VolumeOptions vo;
  vo.target_relative_error = 1e-3;
  const VolumeResult cov = volume(make_leaf(f, "eight"), vo);
  EXPECT_NEAR(v, cov.volume, 2 * cov.error_bound + 1e-9);
  check(unite({leaf(f, "eight"), make_leaf(make_box({-0.2, -0.2, 0.5}, {0.2, 0.2, 1.5}), "b")}),
        "figure-eight ∪ box");
  check(intersect({leaf(f, "eight"), make_leaf(make_sphere({0.6, 0, 0.5}, 0.5, 16), "s")}),
        "figure-eight ∩ sphere");
}

TEST(EvaluateSelfIntersecting, TouchingCurveOfOneEdge) {
  // Leaf 0: a triangular prism along x through a reversed box (x ≥ 1): for x > 1 the prism's
  // inside winds 0, the rest of the box −1. Leaf 1: boxes over x ≥ 1 except the strip
  // 1.2 < y < 1.4. In the strip the prism's inside (x < 1) and the box outside the prism (x > 1)
  // touch along two edges on the plane x = 1, each ending where the solids merge: assembly
  // must split each doubled edge, or two edges would join the same two vertices.
  PolygonMesh prism;
  prism.vertices = {{0, 0.5, 0.2}, {0, 1.8, 0.5}, {0, 0.5, 0.9},
                    {2, 0.5, 0.2}, {2, 1.8, 0.5}, {2, 0.5, 0.9}};
  prism.add_face({0, 2, 1});
  prism.add_face({3, 4, 5});
  prism.add_face({0, 1, 4, 3});
  prism.add_face({1, 2, 5, 4});
  prism.add_face({2, 0, 3, 5});
  const Solid a = leaf(concat(prism, make_box({1, 0, 0}, {3, 2, 1}), true), "prism");
  const Solid b = make_leaf(
      concat(make_box({1, 0, 0}, {3, 1.2, 1}), make_box({1, 1.4, 0}, {3, 2, 1})), "boxes");
  check(unite({a, b}), "prism ∪ boxes (touching edges)");
}

TEST(EvaluateSelfIntersecting, LibcgalMeshes) {
  const Solid cow = leaf(model("cow", {0, 0, 0}, 1, 0), "cow");
  check(cow, "cow");
  const Solid box = make_leaf(make_box({-0.3, -0.5, -0.25}, {0.6, 0.4, 0.2}), "box");
  check(unite({cow, box}), "cow ∪ box");
  check(subtract({cow, box}), "cow − box");
  check(intersect({cow, box}), "cow ∩ box");
  const Solid elk = leaf(model("elk", {0.2, 0.1, 0}, 0.8, 30), "elk");
  check(subtract({elk, make_leaf(make_sphere({0.3, 0, 0}, 0.45, 24), "sphere")}), "elk − sphere");
  check(unite({cow, elk}), "cow ∪ elk");
  const Solid bones = leaf(model("bones", {0, 0, 0}, 1, 10), "bones");
  check(intersect({bones, make_leaf(make_box({-0.5, -0.6, -0.6}, {0.5, 0.6, 0.6}), "b")}),
        "bones ∩ box");
}

TEST(EvaluateSelfIntersecting, CamelBullMan) {
  const Solid camel = leaf(model("camel", {0, 0, 0}, 1, 0), "camel");
  const Solid bull = leaf(model("bull", {0.1, 0.05, 0}, 0.9, 20), "bull");
  const Solid man = leaf(model("man", {-0.05, 0, 0.05}, 1, 40), "man");
  const Solid box = make_leaf(make_box({-0.4, -0.5, -0.3}, {0.5, 0.4, 0.25}), "box");
  check(unite({camel, box}), "camel ∪ box");
  check(subtract({bull, camel}), "bull − camel");
  check(intersect({man, box}), "man ∩ box");
  check(unite({man, bull}), "man ∪ bull");
}

}  // namespace
}  // namespace cover
