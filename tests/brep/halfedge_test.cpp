// HalfedgeMesh operators and validate() (brep/halfedge.h).
#include "cover/brep/halfedge.h"

#include <gtest/gtest.h>

#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "helpers.h"

namespace cover::brep {
namespace {

PolygonMesh cube() {
  PolygonMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({double(i & 1), double((i >> 1) & 1), double(i >> 2)});
  m.add_face({0, 2, 3, 1});
  m.add_face({4, 5, 7, 6});
  m.add_face({0, 1, 5, 4});
  m.add_face({2, 6, 7, 3});
  m.add_face({0, 4, 6, 2});
  m.add_face({1, 3, 7, 5});
  return m;
}

TEST(Halfedge, CubeIsClosedGenusZero) {
  const BrepReport r = validate(HalfedgeMesh::from_polygon_mesh(cube()));
  EXPECT_TRUE(r.consistent);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.manifold);
  EXPECT_EQ(r.vertices, 8);
  EXPECT_EQ(r.edges, 12);
  EXPECT_EQ(r.faces, 6);
  EXPECT_EQ(r.euler, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.components, 1);
}

TEST(Halfedge, TorusHasEulerZero) {
  const BrepReport r =
      validate(HalfedgeMesh::from_polygon_mesh(read_mesh(test::source_dir() / "models/torus.off")));
  EXPECT_TRUE(r.closed && r.manifold);
  EXPECT_EQ(r.euler, 0);
  EXPECT_EQ(r.genus, 1);
}

TEST(Halfedge, FalseEdgeFaceCountsAsAnnulus) {
  // frame.off: top and bottom faces hold a hole joined by a false edge; genus 1.
  const BrepReport r =
      validate(HalfedgeMesh::from_polygon_mesh(read_mesh(test::source_dir() / "models/frame.off")));
  EXPECT_TRUE(r.consistent && r.closed && r.manifold);
  EXPECT_EQ(r.genus, 1);
}

TEST(Halfedge, OpenMeshCountsBoundaryLoops) {
  PolygonMesh m = cube();
  PolygonMesh open;
  open.vertices = m.vertices;
  for (size_t f = 1; f < m.face_count(); ++f) open.add_face(m.face(f));
  const BrepReport r = validate(HalfedgeMesh::from_polygon_mesh(open));
  EXPECT_TRUE(r.consistent);
  EXPECT_FALSE(r.closed);
  EXPECT_EQ(r.boundary_loops, 1);
  EXPECT_EQ(r.euler, 1);
  EXPECT_EQ(r.genus, 0);
}

TEST(Halfedge, RejectsEdgeUsedTwiceInOneDirection) {
  PolygonMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.add_face({0, 1, 2});
  m.add_face({0, 1, 3});
  EXPECT_THROW(HalfedgeMesh::from_polygon_mesh(m), InputError);
}

TEST(Halfedge, MinimalOperatorsBuildATetrahedron) {
  HalfedgeMesh m;
  const uint32_t a = m.add_vertex({0, 0, 0}), b = m.add_vertex({1, 0, 0}),
                 c = m.add_vertex({0, 1, 0}), d = m.add_vertex({0, 0, 1});
  const uint32_t ab = m.insert_edge(a, b), bc = m.insert_edge(b, c), ca = m.insert_edge(c, a);
  const uint32_t ad = m.insert_edge(a, d), bd = m.insert_edge(b, d), cd = m.insert_edge(c, d);
  // Faces counter-clockwise from outside: acb (bottom), abd, bcd, cad.
  const uint32_t f0[] = {ca ^ 1, bc ^ 1, ab ^ 1};
  const uint32_t f1[] = {ab, bd, ad ^ 1};
  const uint32_t f2[] = {bc, cd, bd ^ 1};
  const uint32_t f3[] = {ca, ad, cd ^ 1};
  EXPECT_FALSE(validate(m).closed);
  m.make_face(f0);
  m.make_face(f1);
  m.make_face(f2);
  m.make_face(f3);
  const BrepReport r = validate(m);
  EXPECT_TRUE(r.consistent && r.closed && r.manifold);
  EXPECT_EQ(r.euler, 2);
  EXPECT_GT(signed_volume(m.to_polygon_mesh()), 0);
}

TEST(Halfedge, SplitEdgeAndSplitFaceKeepEuler) {
  HalfedgeMesh m = HalfedgeMesh::from_polygon_mesh(cube());
  // Split the edge 0–1 and then the bottom face between the new vertex and vertex 3.
  uint32_t h01 = kNone;
  for (uint32_t h = 0; h < m.halfedge_slots(); ++h)
    if (m.origin(h) == 0 && m.head(h) == 1) h01 = h;
  ASSERT_NE(h01, kNone);
  const uint32_t v = m.split_edge(h01, {0.5, 0, 0});
  EXPECT_EQ(validate(m).euler, 2);
  EXPECT_EQ(m.face_degree(m.face(h01)), 5u);
  uint32_t from_v = kNone, from_3 = kNone;
  const uint32_t f = m.face(h01 ^ 1);  // the bottom face 0,2,3,1 now holds 0,2,3,1,v
  uint32_t h = m.face_halfedge(f);
  do {
    if (m.origin(h) == v) from_v = h;
    if (m.origin(h) == 3) from_3 = h;
    h = m.next(h);
  } while (h != m.face_halfedge(f));
  ASSERT_NE(from_v, kNone);
  ASSERT_NE(from_3, kNone);
  const uint32_t x = m.split_face(from_v, from_3);
  const BrepReport r = validate(m);
  EXPECT_TRUE(r.consistent && r.closed && r.manifold);
  EXPECT_EQ(r.faces, 7);
  EXPECT_EQ(r.euler, 2);
  EXPECT_NEAR(signed_volume(m.to_polygon_mesh()), 1.0, 1e-15);
  // delete_edge is split_face's inverse.
  m.delete_edge(x);
  const BrepReport back = validate(m);
  EXPECT_TRUE(back.consistent && back.closed);
  EXPECT_EQ(back.faces, 6);
}

TEST(Halfedge, DetachAndSplitNonmanifoldVertices) {
  // Detaching all four side-face edges at the top ring of a cube leaves the top face and the
  // rest as two open pieces that share vertices: splitting fans duplicates those 4 vertices.
  HalfedgeMesh m = HalfedgeMesh::from_polygon_mesh(cube());
  const uint32_t slots = m.halfedge_slots();
  for (uint32_t h = 0; h < slots; h += 2)
    if (m.position(m.origin(h)).z == 1 && m.position(m.head(h)).z == 1) m.detach_edge(h);
  BrepReport r = validate(m);
  EXPECT_TRUE(r.consistent);
  EXPECT_FALSE(r.manifold);
  EXPECT_EQ(m.split_nonmanifold_vertices(), 4u);
  r = validate(m);
  EXPECT_TRUE(r.consistent && r.manifold);
  EXPECT_EQ(r.components, 2);
  EXPECT_EQ(r.boundary_loops, 2);
  // An isolated vertex can be deleted; an inserted, faceless edge too.
  const uint32_t a = m.add_vertex({5, 5, 5}), b = m.add_vertex({6, 5, 5});
  const uint32_t e = m.insert_edge(a, b);
  m.delete_edge(e);
  m.delete_vertex(a);
  m.delete_vertex(b);
  EXPECT_TRUE(validate(m).consistent);
  EXPECT_EQ(m.to_polygon_mesh().vertices.size(), 12u);
}

}  // namespace
}  // namespace cover::brep
