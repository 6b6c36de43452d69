// repair_rounding (mesh/rounding_repair.h): contacts made by points that round alike are found
// exactly and removed by collapsing rounding-scale edges; a mesh without contacts is unchanged;
// an edge longer than the rounding scale is never collapsed.
#include "cover/mesh/rounding_repair.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cover/mesh/validate.h"
#include "cover/solid/measure.h"
#include "cover/solid/predicates.h"
#include "cover/solid/primitives.h"

namespace cover {
namespace {

/// `mesh` (triangles) with edge (a, b) of faces f and g split at a new vertex placed at
/// `position`: four faces instead of two.
PolygonMesh split_edge(const PolygonMesh& mesh, uint32_t a, uint32_t b, Vec3 position) {
  PolygonMesh out;
  out.vertices = mesh.vertices;
  const uint32_t m = static_cast<uint32_t>(out.vertices.size());
  out.vertices.push_back(position);
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto t = mesh.face(f);
    bool split = false;
    for (int i = 0; i < 3 && !split; ++i) {
      const uint32_t p = t[i], q = t[(i + 1) % 3], r = t[(i + 2) % 3];
      if ((p == a && q == b) || (p == b && q == a)) {
        out.add_face({p, m, r});
        out.add_face({m, q, r});
        split = true;
      }
    }
    if (!split) out.add_face(t);
  }
  return out;
}

TEST(RoundingRepair, CollapsesTwoVerticesAtOnePoint) {
  const PolygonMesh ball = make_sphere({0.1, 0.2, 0.3}, 1, 12);
  const auto t = ball.face(7);
  const uint32_t a = t[0], b = t[1];
  PolygonMesh bad = split_edge(ball, a, b, ball.vertices[a]);  // the new vertex sits on a
  ASSERT_EQ(bad.face_count(), ball.face_count() + 2);
  EXPECT_TRUE(self_intersects(bad));
  std::vector<uint8_t> rounded(bad.vertices.size(), 0);
  rounded.back() = 1;
  const RoundingRepair r = repair_rounding(bad, rounded);
  EXPECT_EQ(r.collapsed_edges, 1);
  EXPECT_EQ(r.remaining_pairs, 0);
  EXPECT_EQ(r.dropped_faces, 2);
  EXPECT_EQ(bad.face_count(), ball.face_count());
  EXPECT_EQ(bad.vertices.size(), ball.vertices.size());
  EXPECT_EQ(r.face_origin.size(), bad.face_count());
  EXPECT_FALSE(self_intersects(bad));
  const MeshReport rep = validate_mesh(bad);
  EXPECT_TRUE(rep.closed && rep.manifold && rep.oriented);
  EXPECT_EQ(signed_volume(bad), signed_volume(ball));
}

TEST(RoundingRepair, OneUlpBeyondAnEdgeEnd) {
  // The new vertex one ulp beyond corner a of the cube edge a–b, on its line: the two faces
  // (a, m, r) fold back over (m, b, r) in their planes.
  const PolygonMesh box = make_box({1, 1, 1}, {2, 2, 2});
  PolygonMesh cube;
  cube.vertices = box.vertices;
  for (size_t f = 0; f < box.face_count(); ++f) {
    const auto q = box.face(f);
    for (size_t i = 1; i + 1 < q.size(); ++i) cube.add_face({q[0], q[i], q[i + 1]});
  }
  uint32_t a = 0, b = 0;
  for (uint32_t v = 0; v < cube.vertices.size(); ++v) {
    if (cube.vertices[v] == Vec3{1, 1, 1}) a = v;
    if (cube.vertices[v] == Vec3{2, 1, 1}) b = v;
  }
  bool adjacent = false;
  for (size_t f = 0; f < cube.face_count(); ++f) {
    const auto t = cube.face(f);
    for (int i = 0; i < 3; ++i) adjacent |= (t[i] == a && t[(i + 1) % 3] == b);
  }
  ASSERT_TRUE(adjacent);
  PolygonMesh bad = split_edge(cube, a, b, {std::nextafter(1.0, 0.0), 1, 1});
  ASSERT_TRUE(self_intersects(bad));
  std::vector<uint8_t> rounded(bad.vertices.size(), 0);
  rounded.back() = 1;
  const RoundingRepair r = repair_rounding(bad, rounded);
  EXPECT_EQ(r.remaining_pairs, 0);
  EXPECT_EQ(r.collapsed_edges, 1);
  EXPECT_FALSE(self_intersects(bad));
  const MeshReport rep = validate_mesh(bad);
  EXPECT_TRUE(rep.closed && rep.manifold && rep.oriented);
  EXPECT_EQ(signed_volume(bad), 1.0);
}

TEST(RoundingRepair, NothingToRepairOrTooLongToCollapse) {
  PolygonMesh ball = make_sphere({0, 0, 0}, 1, 8);
  const PolygonMesh before = ball;
  std::vector<uint8_t> all(ball.vertices.size(), 1);
  RoundingRepair r = repair_rounding(ball, all);
  EXPECT_FALSE(r.changed());
  EXPECT_EQ(r.remaining_pairs, 0);
  EXPECT_EQ(ball.vertices, before.vertices);
  EXPECT_EQ(ball.face_vertices, before.face_vertices);
  // A real defect far above rounding scale (a vertex pulled through the opposite side of the
  // ball): left alone and reported.
  const auto t = before.face(5);
  const Vec3 c =
      (1.0 / 3) * (before.vertices[t[0]] + before.vertices[t[1]] + before.vertices[t[2]]);
  PolygonMesh dent = split_edge(before, t[0], t[1], -1.5 * c);
  ASSERT_TRUE(self_intersects(dent));
  std::vector<uint8_t> flags(dent.vertices.size(), 1);
  r = repair_rounding(dent, flags);
  EXPECT_FALSE(r.changed());
  EXPECT_GT(r.remaining_pairs, 0);
}

TEST(IntersectingFacePairs, AxisPlanePathAgreesWithTheGeneralTest) {
  // Two triangles in one axis plane over a 4×4 grid (shared corners, touching edges, collinear
  // corners, containment): the 2D path of intersecting_face_pairs against self_intersects' 3D
  // tests, in each of the three axis planes.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> coord(0, 3), pick(0, 5);
  int meeting = 0, apart = 0;
  for (int k = 0; k < 3; ++k)
    for (int trial = 0; trial < 1500; ++trial) {
      PolygonMesh m;
      for (int i = 0; i < 6; ++i) {
        Vec3 p{static_cast<double>(coord(rng)), static_cast<double>(coord(rng)),
               static_cast<double>(coord(rng))};
        (k == 0 ? p.x : k == 1 ? p.y : p.z) = 0.5;
        m.vertices.push_back(p);
      }
      // Triangle b reuses corners of a now and then (shared vertices by index).
      std::array<uint32_t, 6> id{0, 1, 2, 3, 4, 5};
      for (int i = 3; i < 6; ++i)
        if (pick(rng) < 2) id[i] = static_cast<uint32_t>(pick(rng) % 3);
      if (id[3] == id[4] || id[4] == id[5] || id[3] == id[5]) continue;
      if (all_collinear(m.vertices, std::array<uint32_t, 3>{id[0], id[1], id[2]}) ||
          all_collinear(m.vertices, std::array<uint32_t, 3>{id[3], id[4], id[5]}))
        continue;
      m.add_face({id[0], id[1], id[2]});
      m.add_face({id[3], id[4], id[5]});
      const bool expected = self_intersects(m);
      EXPECT_EQ(!intersecting_face_pairs(m).empty(), expected) << k << " " << trial;
      (expected ? meeting : apart) += 1;
    }
  EXPECT_GT(meeting, 500);
  EXPECT_GT(apart, 500);
}

}  // namespace
}  // namespace cover
