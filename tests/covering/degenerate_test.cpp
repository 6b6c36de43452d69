// Degenerate geometry (hardening issue): slivers and zero-area triangles, duplicate faces,
// coincident leaves, leaves sharing faces / edges / vertices, points and rays exactly on faces and
// edges, and self-intersecting real meshes under the nonzero winding rule. Every classification
// is checked against the brute-force covering path.
#include <gtest/gtest.h>

#include <random>

#include "cover/covering/classify.h"
#include "cover/covering/ray.h"
#include "cover/covering/volume.h"
#include "cover/io/scene.h"
#include "cover/solid/primitives.h"
#include "helpers.h"

namespace cover {
namespace {

using PC = PointClass;

Solid box(Vec3 lo, Vec3 hi) { return make_leaf(make_box(lo, hi), "box"); }

/// Lattice points (many exactly on faces, edges, vertices) plus random ones.
std::vector<Vec3> probe_points(double lo, double hi, double step, uint64_t seed) {
  std::vector<Vec3> p;
  for (double x = lo; x <= hi; x += step)
    for (double y = lo; y <= hi; y += step)
      for (double z = lo; z <= hi; z += step) p.push_back({x, y, z});
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  for (int i = 0; i < 500; ++i) p.push_back({u(rng), u(rng), u(rng)});
  return p;
}

void expect_paths_agree(const Solid& s, const std::vector<Vec3>& pts) {
  ClassifyOptions grid;
  grid.grid_min_points = 1;
  const auto a = classify(s, pts), b = classify(s, pts, grid), c = classify_brute_force(s, pts);
  EXPECT_EQ(a, c);
  EXPECT_EQ(b, c);
}

TEST(Degenerate, CoincidentLeaves) {
  const Solid a = box({0, 0, 0}, {1, 1, 1});
  const auto pts = probe_points(-0.5, 1.5, 0.25, 1);
  const auto ref = classify(a, pts);
  EXPECT_EQ(classify(unite({a, a}), pts), ref);                             // A ∪ A = A
  EXPECT_EQ(classify(intersect({a, a}), pts), ref);                         // A ∩ A = A
  for (PC c : classify(subtract({a, a}), pts)) EXPECT_EQ(c, PC::kOutside);  // A − A = ∅
  EXPECT_NEAR(volume(unite({a, a})).volume, 1.0, 1e-4);
  EXPECT_NEAR(volume(intersect({a, a})).volume, 1.0, 1e-4);
  EXPECT_NEAR(volume(subtract({a, a})).volume, 0.0, 1e-4);
  expect_paths_agree(subtract({a, a}), pts);
}

TEST(Degenerate, LeavesSharingFacesEdgesAndVertices) {
  const Solid a = box({0, 0, 0}, {1, 1, 1});
  const auto pts = probe_points(-0.5, 2.5, 0.25, 2);
  for (const Solid& b : {box({1, 0, 0}, {2, 1, 1}),             // shared face
                         box({1, 1, 0}, {2, 2, 1}),             // shared edge
                         box({1, 1, 1}, {2, 2, 2}),             // shared vertex
                         box({0.5, 0.5, 1}, {1.5, 1.5, 2})}) {  // partly shared face
    expect_paths_agree(unite({a, b}), pts);
    expect_paths_agree(subtract({a, b}), pts);
    expect_paths_agree(intersect({a, b}), pts);
  }
  // The shared face of two face-adjacent boxes is interior to their union.
  EXPECT_EQ(classify(unite({a, box({1, 0, 0}, {2, 1, 1})}), std::vector<Vec3>{{1, 0.5, 0.5}})[0],
            PC::kInside);
}

TEST(Degenerate, SliversZeroAreaTrianglesAndDuplicateFaces) {
  // A box with every face split by a zero-area triangle (a repeated vertex) and a sliver pair.
  PolygonMesh m = make_box({0, 0, 0}, {1, 1, 1});
  PolygonMesh t = test::triangulate(m);
  const uint32_t extra = static_cast<uint32_t>(t.vertices.size());
  t.vertices.push_back({0.5, 0, 0});  // on the edge (0,0,0)-(1,0,0)
  t.add_face({0, extra, 1});          // collinear: zero area
  t.add_face({1, extra, 0});          // its reverse: the pair cancels in the covering
  const Solid s = make_leaf(t, "slivers");
  const auto pts = probe_points(-0.25, 1.25, 0.125, 3);
  expect_paths_agree(s, pts);
  EXPECT_EQ(classify(s, pts), classify(box({0, 0, 0}, {1, 1, 1}), pts));
  // A face listed twice in one leaf: winding 2 on one side of it, 1 on the other — still inside
  // under the nonzero rule; the surface there is still classified exactly.
  PolygonMesh d = m;
  d.add_face(m.face(0));
  expect_paths_agree(make_leaf(d, "duplicate"), pts);
}

TEST(Degenerate, RaysExactlyAlongFacesAndThroughEdges) {
  const Solid s = unite({box({0, 0, 0}, {1, 1, 1}), box({1, 0, 0}, {2, 1, 1})});
  const Bvh bvh(s);
  // Along the shared face x = 1, through the common edge, along a face plane, through vertices.
  const std::vector<Ray> rays = {{{1, 0.5, -1}, {0, 0, 1}}, {{1, 1, -1}, {0, 0, 1}},
                                 {{-1, 0, 0.5}, {1, 0, 0}}, {{-1, 0, 0}, {1, 0, 0}},
                                 {{-1, -1, -1}, {1, 1, 1}}, {{0.5, 0.5, -1}, {0, 0, 1}}};
  for (const Ray& r : rays) {
    const RayResult res = cast(bvh, s.tree, s.leaves.size(), r);
    // Every span is inside: its midpoint classifies inside or on the boundary, never outside.
    for (const Span& span : res.spans) {
      const double t = 0.5 * (span.t0 + span.t1);
      const Vec3 mid = r.origin + t * r.dir;
      EXPECT_NE(classify_brute_force(s, std::vector<Vec3>{mid})[0], PC::kOutside);
    }
    // Windings return to 0 after the last hit (consistent counting of edge and vertex hits).
    std::vector<int> w(s.leaves.size(), 0);
    for (const RayHit& h : res.hits) w[h.leaf] += h.sign;
    for (int x : w) EXPECT_EQ(x, 0);
  }
  // The ray through the middle of the union spans exactly [1, 2] (z from 0 to 1).
  const RayResult mid = cast(bvh, s.tree, s.leaves.size(), rays.back());
  ASSERT_EQ(mid.spans.size(), 1u);
  EXPECT_DOUBLE_EQ(mid.spans[0].t0, 1.0);
  EXPECT_DOUBLE_EQ(mid.spans[0].t1, 2.0);
}

TEST(Degenerate, DuplicateVerticesAndRayOriginsOnFaces) {
  // An unwelded box: every face has its own copies of its corners.
  const PolygonMesh welded = make_box({0, 0, 0}, {1, 1, 1});
  PolygonMesh soup;
  for (size_t f = 0; f < welded.face_count(); ++f) {
    std::vector<uint32_t> loop;
    for (uint32_t v : welded.face(f)) {
      loop.push_back(static_cast<uint32_t>(soup.vertices.size()));
      soup.vertices.push_back(welded.vertices[v]);
    }
    soup.add_face(loop);
  }
  const Solid s = make_leaf(soup, "soup");
  const auto pts = probe_points(-0.5, 1.5, 0.25, 4);
  EXPECT_EQ(classify(s, pts), classify(box({0, 0, 0}, {1, 1, 1}), pts));
  expect_paths_agree(s, pts);
  // Rays starting exactly on a face, an edge and a vertex, pointing in and out.
  const Bvh bvh(s);
  const std::vector<Ray> rays = {{{0.5, 0.5, 0}, {0, 0, 1}},
                                 {{0.5, 0.5, 0}, {0, 0, -1}},
                                 {{0.5, 0, 0}, {0, 1, 1}},
                                 {{0, 0, 0}, {1, 1, 1}},
                                 {{1, 1, 1}, {1, 1, 1}}};
  const std::vector<size_t> spans = {1, 0, 1, 1, 0};
  for (size_t i = 0; i < rays.size(); ++i) {
    const RayResult r = cast(bvh, s.tree, s.leaves.size(), rays[i]);
    EXPECT_EQ(r.spans.size(), spans[i]) << i;
  }
}

class SelfIntersecting : public ::testing::TestWithParam<const char*> {};

TEST_P(SelfIntersecting, NonzeroRuleBothPathsAgree) {
  LoadOptions o;
  o.require_closed = false;  // some of these scans have holes; classification still defined
  const Solid s = load_input(test::cgal_mesh(GetParam()), o).solid;
  const Bbox b = s.bbox();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> ux(b.min.x, b.max.x), uy(b.min.y, b.max.y),
      uz(b.min.z, b.max.z);
  std::vector<Vec3> pts(1500);
  for (Vec3& p : pts) p = {ux(rng), uy(rng), uz(rng)};
  EXPECT_EQ(classify(s, pts), classify_brute_force(s, pts)) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Cgal, SelfIntersecting,
                         ::testing::Values("cow.off", "camel.off", "bull.off", "man.off",
                                           "bones.off", "elk.off"),
                         [](const auto& info) {
                           std::string n = info.param;
                           return n.substr(0, n.find('.'));
                         });

}  // namespace
}  // namespace cover
