// Tests for mesh/validate.h: topology counts on generated meshes (cubes, torus, a box with a
// through-hole whose faces hold two loops joined by false edges), exact degeneracy, exact
// self-intersection, and the libcgal-demo meshes.

#include "cover/mesh/validate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <ostream>
#include <string>
#include <tuple>
#include <vector>

#include "cover/io/mesh_io.h"
#include "helpers.h"

namespace cover {
namespace {

/// Axis-aligned cube [o, o+s]^3: 8 vertices (index x + 2y + 4z), 6 outward quads.
PolygonMesh cube(Vec3 o = {}, double s = 1) {
  PolygonMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({o.x + s * (i & 1), o.y + s * ((i >> 1) & 1), o.z + s * ((i >> 2) & 1)});
  m.add_face({0, 2, 3, 1});  // z = 0
  m.add_face({4, 5, 7, 6});  // z = 1
  m.add_face({0, 1, 5, 4});  // y = 0
  m.add_face({2, 6, 7, 3});  // y = 1
  m.add_face({0, 4, 6, 2});  // x = 0
  m.add_face({1, 3, 7, 5});  // x = 1
  return m;
}

/// Concatenates b's vertices and faces after a's.
PolygonMesh concat(PolygonMesh a, const PolygonMesh& b) {
  const auto offset = static_cast<uint32_t>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (size_t f = 0; f < b.face_count(); ++f) {
    std::vector<uint32_t> loop(b.face(f).begin(), b.face(f).end());
    for (uint32_t& v : loop) v += offset;
    a.add_face(loop);
  }
  return a;
}

/// Merges vertices with equal coordinates into one index.
PolygonMesh weld(const PolygonMesh& m) {
  PolygonMesh out;
  std::map<std::tuple<double, double, double>, uint32_t> index;
  std::vector<uint32_t> remap;
  for (const Vec3& v : m.vertices) {
    auto [it, added] =
        index.try_emplace({v.x, v.y, v.z}, static_cast<uint32_t>(out.vertices.size()));
    if (added) out.vertices.push_back(v);
    remap.push_back(it->second);
  }
  for (size_t f = 0; f < m.face_count(); ++f) {
    std::vector<uint32_t> loop;
    for (uint32_t v : m.face(f)) loop.push_back(remap[v]);
    out.add_face(loop);
  }
  return out;
}

/// Reverses the loop of face f (or of every face when f is negative).
PolygonMesh reversed(PolygonMesh m, int f = -1) {
  for (size_t g = 0; g < m.face_count(); ++g)
    if (f < 0 || static_cast<size_t>(f) == g)
      std::reverse(m.face_vertices.begin() + m.face_start[g],
                   m.face_vertices.begin() + m.face_start[g + 1]);
  return m;
}

/// Torus of radii R > r with n × k planar quads, outward.
PolygonMesh torus(uint32_t n, uint32_t k, double R = 3, double r = 1) {
  PolygonMesh m;
  const double tau = 2 * std::numbers::pi;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < k; ++j) {
      const double u = tau * i / n, v = tau * j / k;
      m.vertices.push_back({(R + r * std::cos(v)) * std::cos(u),
                            (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)});
    }
  auto id = [&](uint32_t i, uint32_t j) { return (i % n) * k + j % k; };
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < k; ++j)
      m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

/// Square frame [0,3]² minus the hole [1,2]², z in [0,1] (genus 1). Top and bottom are single
/// faces whose outer loop and hole loop are joined by a false edge ([Segura2004 §3 Fig. 1]).
PolygonMesh picture_frame() {
  PolygonMesh m;
  const double outer[4][2] = {{0, 0}, {3, 0}, {3, 3}, {0, 3}};
  const double hole[4][2] = {{1, 1}, {2, 1}, {2, 2}, {1, 2}};
  for (double z : {0.0, 1.0}) {  // 0..3 outer, 4..7 hole at z = 0; 8..11, 12..15 at z = 1
    for (const auto& p : outer) m.vertices.push_back({p[0], p[1], z});
    for (const auto& p : hole) m.vertices.push_back({p[0], p[1], z});
  }
  m.add_face({9, 10, 11, 8, 12, 15, 14, 13, 12, 8});  // top: 8→12 and 12→8 are false edges
  m.add_face({3, 2, 1, 0, 4, 5, 6, 7, 4, 0});         // bottom: 0→4 and 4→0 are false edges
  for (uint32_t k = 0; k < 4; ++k) {
    const uint32_t k1 = (k + 1) % 4;
    m.add_face({k, k1, 8 + k1, 8 + k});            // outer wall
    m.add_face({4 + k1, 4 + k, 12 + k, 12 + k1});  // hole wall
  }
  return m;
}

/// Prism over the L-shaped hexagon (non-convex top and bottom faces), z in [0,1].
PolygonMesh l_prism() {
  PolygonMesh m;
  const double l[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  for (double z : {0.0, 1.0})
    for (const auto& p : l) m.vertices.push_back({p[0], p[1], z});
  m.add_face({6, 7, 8, 9, 10, 11});
  m.add_face({5, 4, 3, 2, 1, 0});
  for (uint32_t k = 0; k < 6; ++k) m.add_face({k, (k + 1) % 6, 6 + (k + 1) % 6, 6 + k});
  return m;
}

void expect_valid_solid(const MeshReport& r, int64_t genus) {
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.manifold);
  EXPECT_TRUE(r.oriented);
  EXPECT_TRUE(r.outward);
  EXPECT_EQ(r.boundary_edges, 0);
  EXPECT_EQ(r.nonmanifold_edges, 0);
  EXPECT_EQ(r.genus, genus);
  EXPECT_EQ(r.degenerate_faces, 0);
}

TEST(ValidateMesh, ClosedCube) {
  const MeshReport r = validate_mesh(cube());
  expect_valid_solid(r, 0);
  EXPECT_EQ(r.components, 1);
  EXPECT_DOUBLE_EQ(r.volume, 1.0);
  ASSERT_TRUE(r.self_intersecting.has_value());
  EXPECT_FALSE(*r.self_intersecting);
}

TEST(ValidateMesh, SelfIntersectionCheckCanBeSkipped) {
  const MeshReport r = validate_mesh(cube(), {.check_self_intersection = false});
  EXPECT_FALSE(r.self_intersecting.has_value());
}

TEST(ValidateMesh, OneFaceReversedIsNotOriented) {
  const MeshReport r = validate_mesh(reversed(cube(), 2));
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.manifold);
  EXPECT_FALSE(r.oriented);
  EXPECT_FALSE(r.outward);
  EXPECT_EQ(r.genus, -1);
}

TEST(ValidateMesh, InsideOutCubeIsOrientedButNotOutward) {
  const MeshReport r = validate_mesh(reversed(cube()));
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.oriented);
  EXPECT_FALSE(r.outward);
  EXPECT_DOUBLE_EQ(r.volume, -1.0);
  EXPECT_EQ(r.genus, 0);
}

TEST(ValidateMesh, OpenCubeHasFourBoundaryEdges) {
  PolygonMesh open;
  const PolygonMesh c = cube();
  open.vertices = c.vertices;
  for (size_t f = 0; f < c.face_count(); ++f)
    if (f != 1) open.add_face(c.face(f));
  const MeshReport r = validate_mesh(open);
  EXPECT_FALSE(r.closed);
  EXPECT_EQ(r.boundary_edges, 4);
  EXPECT_TRUE(r.manifold);
  EXPECT_TRUE(r.oriented);
  EXPECT_FALSE(r.outward);
  EXPECT_EQ(r.genus, -1);
  EXPECT_EQ(r.components, 1);
}

TEST(ValidateMesh, CubesSharingAnEdgeAreNotManifold) {
  const MeshReport r = validate_mesh(weld(concat(cube(), cube({1, 1, 0}))));
  EXPECT_TRUE(r.closed);
  EXPECT_FALSE(r.manifold);
  EXPECT_GE(r.nonmanifold_edges, 1);
  EXPECT_EQ(r.genus, -1);
  EXPECT_EQ(r.components, 1);
  EXPECT_FALSE(self_intersects(weld(concat(cube(), cube({1, 1, 0})))));
}

TEST(ValidateMesh, CubesSharingOnlyAVertexArePinched) {
  const PolygonMesh m = weld(concat(cube(), cube({1, 1, 1})));
  ASSERT_EQ(m.vertices.size(), 15u);
  const MeshReport r = validate_mesh(m);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.nonmanifold_edges, 0);
  EXPECT_FALSE(r.manifold);
  EXPECT_EQ(r.genus, -1);
  EXPECT_EQ(r.components, 2);
  EXPECT_FALSE(*r.self_intersecting);
}

TEST(ValidateMesh, OpenFansMeetingAtAVertexArePinched) {
  PolygonMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  m.add_face({0, 1, 2});
  m.add_face({0, 3, 4});  // touches the first triangle at vertex 0 only
  MeshReport r = validate_mesh(m);
  EXPECT_EQ(r.boundary_edges, 6);
  EXPECT_FALSE(r.manifold);
  EXPECT_EQ(r.components, 2);
  m.add_face({0, 2, 3});  // now one fan around vertex 0
  r = validate_mesh(m);
  EXPECT_TRUE(r.manifold);
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.boundary_edges, 5);
}

TEST(ValidateMesh, MoebiusStripIsManifoldButNotOriented) {
  const uint32_t n = 16;
  PolygonMesh m;
  for (uint32_t i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n;
    const Vec3 c{3 * std::cos(t), 3 * std::sin(t), 0};
    const Vec3 d =
        std::cos(t / 2) * Vec3{std::cos(t), std::sin(t), 0} + std::sin(t / 2) * Vec3{0, 0, 1};
    m.vertices.push_back(c + d);      // 2i
    m.vertices.push_back(c - 1 * d);  // 2i + 1
  }
  for (uint32_t i = 0; i + 1 < n; ++i) m.add_face({2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1});
  m.add_face({2 * n - 2, 1, 0, 2 * n - 1});  // the half twist: a(n) = b(0), b(n) = a(0)
  const MeshReport r = validate_mesh(m);
  EXPECT_TRUE(r.manifold);
  EXPECT_FALSE(r.oriented);
  EXPECT_EQ(r.boundary_edges, 2 * n);
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.genus, -1);
}

TEST(ValidateMesh, SeparateCubesAreTwoComponents) {
  const MeshReport r = validate_mesh(concat(cube(), cube({3, 0, 0})));
  expect_valid_solid(r, 0);
  EXPECT_EQ(r.components, 2);
  EXPECT_DOUBLE_EQ(r.volume, 2.0);
}

TEST(ValidateMesh, TorusHasGenusOne) {
  const MeshReport r = validate_mesh(torus(24, 12));
  expect_valid_solid(r, 1);
  EXPECT_EQ(r.components, 1);
  EXPECT_FALSE(*r.self_intersecting);
}

TEST(ValidateMesh, FacesWithHolesJoinedByFalseEdges) {
  const MeshReport r = validate_mesh(picture_frame());
  expect_valid_solid(r, 1);
  EXPECT_EQ(r.components, 1);
  EXPECT_DOUBLE_EQ(r.volume, 8.0);
  EXPECT_FALSE(*r.self_intersecting);
}

TEST(ValidateMesh, NonConvexFacesDoNotSelfIntersect) {
  const MeshReport r = validate_mesh(l_prism());
  expect_valid_solid(r, 0);
  EXPECT_DOUBLE_EQ(r.volume, 3.0);
  EXPECT_FALSE(*r.self_intersecting);
}

TEST(ValidateMesh, DegenerateFacesAreCountedExactly) {
  PolygonMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1e-300, 0}, {0, 1, 0}};
  m.add_face({0, 1, 2});     // collinear
  m.add_face({0, 1, 0});     // two distinct vertices
  m.add_face({0, 1, 3});     // not collinear, however thin
  m.add_face({0, 1, 4});     // a plain triangle
  m.add_face({0, 1, 2, 1});  // collinear polygon
  EXPECT_EQ(validate_mesh(m).degenerate_faces, 3);
}

TEST(ValidateMesh, RepeatedIndexIsNotAnEdge) {
  PolygonMesh m = cube();
  // The same top face with its first vertex repeated: edges and topology do not change.
  std::vector<uint32_t> top(m.face(1).begin(), m.face(1).end());
  top.insert(top.begin(), top.front());
  PolygonMesh n;
  n.vertices = m.vertices;
  for (size_t f = 0; f < m.face_count(); ++f)
    n.add_face(f == 1 ? std::span<const uint32_t>(top) : m.face(f));
  const MeshReport r = validate_mesh(n);
  expect_valid_solid(r, 0);
  EXPECT_FALSE(*r.self_intersecting);
}

TEST(ValidateMesh, EmptyMesh) {
  const MeshReport r = validate_mesh(PolygonMesh{});
  EXPECT_EQ(r.components, 0);
  EXPECT_EQ(r.boundary_edges, 0);
  EXPECT_FALSE(r.outward);
  EXPECT_FALSE(*r.self_intersecting);
}

TEST(SelfIntersects, VertexInTheMiddleOfAStraightSideIsNotAContact) {
  // Top and front faces of a cube share the edge 4-5 split at its midpoint 8 (libcgal-demo's
  // mpi.off has such faces). A fan from vertex 4 would drop 8 from the top face's tiles.
  PolygonMesh m = cube();
  m.vertices.push_back({0.5, 0, 1});
  PolygonMesh split;
  split.vertices = m.vertices;
  split.add_face({0, 2, 3, 1});
  split.add_face({4, 8, 5, 7, 6});
  split.add_face({0, 1, 5, 8, 4});
  split.add_face({2, 6, 7, 3});
  split.add_face({0, 4, 6, 2});
  split.add_face({1, 3, 7, 5});
  const MeshReport r = validate_mesh(split);
  expect_valid_solid(r, 0);
  EXPECT_FALSE(*r.self_intersecting);
}

TEST(ValidateMesh, CubesTouchingAtDistinctVerticesOfEqualCoordinatesTouchWithoutIntersecting) {
  // Two cubes sharing an edge or a corner, each with its own vertices: the faces meet only where
  // distinct vertices have equal coordinates (the evaluated union of such cubes is this mesh).
  for (const Vec3 offset : {Vec3{1, 1, 0}, Vec3{1, 1, 1}}) {
    const PolygonMesh m = concat(cube(), cube(offset));
    ASSERT_TRUE(self_intersects(m));
    const MeshReport r = validate_mesh(m);
    ASSERT_TRUE(r.self_intersecting.has_value());
    EXPECT_FALSE(*r.self_intersecting) << offset.z;
    EXPECT_TRUE(*r.self_touching) << offset.z;
  }
}

TEST(ValidateMesh, CrossingCubesWithATouchingVertexStillIntersect) {
  // A touching corner does not hide a crossing elsewhere.
  const PolygonMesh m = concat(concat(cube(), cube({1, 1, 1})), cube({0.5, 0.5, -0.5}));
  const MeshReport r = validate_mesh(m);
  EXPECT_TRUE(*r.self_intersecting);
  EXPECT_FALSE(*r.self_touching);
  const MeshReport clean = validate_mesh(cube());
  EXPECT_FALSE(*clean.self_intersecting);
  EXPECT_FALSE(*clean.self_touching);
}

TEST(SelfIntersects, InterpenetratingCubes) {
  EXPECT_TRUE(self_intersects(concat(cube(), cube({0.5, 0.5, 0.5}))));
}

// bunny00 (75k triangles) goes through the parallel slab path; a small cube through the surface
// at the largest x (the last slab) or at the smallest x (the first) is found.
TEST(SelfIntersects, LargeMeshSlabs) {
  const PolygonMesh bunny = read_mesh(test::cgal_mesh("bunny00.off"));
  EXPECT_FALSE(self_intersects(bunny));
  auto extreme = [&](bool largest) {
    Vec3 best = bunny.vertices[0];
    for (const Vec3& v : bunny.vertices)
      if (largest ? v.x > best.x : v.x < best.x) best = v;
    return best;
  };
  for (bool largest : {true, false}) {
    const Vec3 p = extreme(largest);
    const double s = 0.01 * (extreme(true).x - extreme(false).x);
    EXPECT_TRUE(self_intersects(concat(bunny, cube({p.x - s / 2, p.y - s / 2, p.z - s / 2}, s))))
        << (largest ? "largest x" : "smallest x");
  }
}

TEST(SelfIntersects, ContainedCubeDoesNotIntersect) {
  EXPECT_FALSE(self_intersects(concat(cube({}, 3), cube({1, 1, 1}))));
}

TEST(SelfIntersects, TouchingAtAnUnsharedVertexIntersects) {
  // Same contact point as CubesSharingOnlyAVertexArePinched, but two distinct indices.
  EXPECT_TRUE(self_intersects(concat(cube(), cube({1, 1, 1}))));
}

TEST(SelfIntersects, CoplanarOverlapAcrossASharedEdge) {
  PolygonMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.3, 0.3, 0}};
  m.add_face({0, 1, 2});
  m.add_face({1, 3, 2});  // opposite side of edge 1-2: fine
  EXPECT_FALSE(self_intersects(m));
  m.add_face({2, 1, 4});  // same side of edge 1-2 as vertex 0 and in the same plane
  EXPECT_TRUE(self_intersects(m));
}

TEST(SelfIntersects, FoldAtASharedVertex) {
  PolygonMesh m;
  m.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 1, -1}, {0.2, 0.2, 1}};
  m.add_face({0, 1, 2});
  m.add_face({0, 3, 4});  // shares vertex 0; its edge 3-4 pierces triangle 0-1-2
  EXPECT_TRUE(self_intersects(m));
}

TEST(SelfIntersects, SelfCrossingFace) {
  PolygonMesh m;
  m.vertices = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}};
  m.add_face({0, 1, 2, 3});  // a bow tie
  EXPECT_TRUE(self_intersects(m));
}

TEST(SelfIntersects, DegenerateTrianglesAreIgnored) {
  PolygonMesh m = cube();
  m.vertices.push_back({0.5, 0.5, -1});
  m.vertices.push_back({0.5, 0.5, 2});
  m.add_face({8, 9, 8});  // a needle through the cube, but with no area
  EXPECT_FALSE(self_intersects(m));
}

struct RealMesh {
  std::string name;
  int64_t genus;
  friend std::ostream& operator<<(std::ostream& os, const RealMesh& m) { return os << m.name; }
};

class CleanCgalMesh : public testing::TestWithParam<RealMesh> {};

TEST_P(CleanCgalMesh, IsAValidSolid) {
  const PolygonMesh m = read_mesh(test::cgal_mesh(GetParam().name));
  const MeshReport r = validate_mesh(m);
  expect_valid_solid(r, GetParam().genus);
  EXPECT_EQ(r.components, 1);
  EXPECT_GT(r.volume, 0);
  ASSERT_TRUE(r.self_intersecting.has_value());
  EXPECT_FALSE(*r.self_intersecting);
}

INSTANTIATE_TEST_SUITE_P(Meshes, CleanCgalMesh,
                         testing::Values(RealMesh{"elephant.off", 3},  // V − E + F = −4
                                         RealMesh{"knot1.off", 1}, RealMesh{"armadillo.off", 0},
                                         RealMesh{"bunny00.off", 0}, RealMesh{"fandisk.off", 0}),
                         [](const auto& p) {
                           return p.param.name.substr(0, p.param.name.find('.'));
                         });

class SelfIntersectingCgalMesh : public testing::TestWithParam<std::string> {};

TEST_P(SelfIntersectingCgalMesh, IsReported) {
  EXPECT_TRUE(self_intersects(read_mesh(test::cgal_mesh(GetParam()))));
}

INSTANTIATE_TEST_SUITE_P(Meshes, SelfIntersectingCgalMesh,
                         testing::Values("cow.off", "camel.off", "bull.off", "man.off"),
                         [](const auto& p) { return p.param.substr(0, p.param.find('.')); });

}  // namespace
}  // namespace cover
