// The minimal DLFL operators: their exact effect on V, E, F, components and genus; each
// insert_edge undone by delete_edge; conversion from and to PolygonMesh; a seeded fuzz.
#include "cover/modeler/dlfl.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "cover/io/mesh_io.h"
#include "cover/modeler/operators.h"
#include "cover/solid/errors.h"
#include "dlfl_checks.h"

namespace cover::modeler {
namespace {

using test::cube;
using test::snapshot;
using test::totals;
using test::Totals;

Totals changed(Totals t, long dv, long de, long df, long dc, int dg) {
  t.vertices += dv;
  t.edges += de;
  t.faces += df;
  t.components += dc;
  t.genus += dg;
  return t;
}

/// Inserts c1–c2, checks the totals against `expected`, deletes the edge and checks that every
/// id and link is back.
void insert_then_delete(DlflMesh& mesh, Corner c1, Corner c2, const Totals& expected) {
  const test::Snapshot before = snapshot(mesh);
  const HalfedgeId h = mesh.insert_edge(c1, c2);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), expected);
  EXPECT_EQ(mesh.tail(h), mesh.corner_vertex(c1));
  EXPECT_EQ(mesh.head(h), mesh.corner_vertex(c2));
  mesh.delete_edge(DlflMesh::edge(h));
  check_valid(mesh);
  EXPECT_TRUE(snapshot(mesh) == before);
}

TEST(DlflMesh, CreateAndDeleteVertexMakeAndRemovePointSpheres) {
  DlflMesh mesh;
  const VertexId v = mesh.create_vertex({1, 2, 3});
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{1, 0, 1, 1, 0}));
  EXPECT_TRUE(mesh.is_point_sphere(v));
  const FaceId f = mesh.point_sphere_face(v);
  EXPECT_EQ(mesh.face_corners(f), std::vector<Corner>{Corner::point_sphere_of(v)});
  EXPECT_EQ(mesh.face_vertices(f), std::vector<VertexId>{v});
  EXPECT_EQ(mesh.face_degree(f), 0u);
  EXPECT_TRUE(mesh.rotation(v).empty());
  mesh.delete_vertex(v);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), Totals{});
  EXPECT_THROW(mesh.delete_vertex(v), PreconditionError);
}

TEST(DlflMesh, DeleteVertexRefusesVerticesWithEdges) {
  DlflMesh mesh = cube();
  EXPECT_THROW(mesh.delete_vertex(0), PreconditionError);
}

TEST(DlflMesh, InsertEdgeBetweenPointSpheresJoinsThem) {
  DlflMesh mesh;
  const VertexId u = mesh.create_vertex({0, 0, 0}), w = mesh.create_vertex({1, 0, 0});
  const Totals start = totals(mesh);
  insert_then_delete(mesh, Corner::point_sphere_of(u), Corner::point_sphere_of(w),
                     changed(start, 0, 1, -1, -1, 0));
  const HalfedgeId h = mesh.insert_edge(Corner::point_sphere_of(u), Corner::point_sphere_of(w));
  EXPECT_EQ(mesh.face_degree(mesh.face(h)), 2u);
  EXPECT_EQ(mesh.face(h), mesh.face(DlflMesh::twin(h)));
  EXPECT_EQ(mesh.rotation(u), std::vector<HalfedgeId>{h});
}

TEST(DlflMesh, InsertEdgeInOneFaceSplitsIt) {
  DlflMesh mesh = cube();
  const Totals start = totals(mesh);
  EXPECT_EQ(start, (Totals{8, 12, 6, 1, 0}));
  const std::vector<Corner> corners = mesh.face_corners(0);
  ASSERT_EQ(corners.size(), 4u);
  // A diagonal, an edge between neighbouring corners (a two-sided face), a loop at one corner.
  insert_then_delete(mesh, corners[0], corners[2], changed(start, 0, 1, 1, 0, 0));
  insert_then_delete(mesh, corners[0], corners[1], changed(start, 0, 1, 1, 0, 0));
  insert_then_delete(mesh, corners[1], corners[1], changed(start, 0, 1, 1, 0, 0));
}

TEST(DlflMesh, InsertEdgeBetweenTwoFacesOfOneComponentAddsAHandle) {
  DlflMesh mesh = cube();
  const Totals start = totals(mesh);
  for (FaceId f = 1; f < 6; ++f)
    insert_then_delete(mesh, mesh.face_corners(0)[0], mesh.face_corners(f)[1],
                       changed(start, 0, 1, -1, 0, 1));
  // A loop between two corners of one vertex in different faces is a handle too.
  const std::vector<Corner> at_vertex = mesh.vertex_corners(0);
  ASSERT_EQ(at_vertex.size(), 3u);
  insert_then_delete(mesh, at_vertex[0], at_vertex[1], changed(start, 0, 1, -1, 0, 1));
}

TEST(DlflMesh, InsertEdgeBetweenComponentsJoinsThem) {
  DlflMesh mesh = cube();
  const VertexId p = mesh.create_vertex({5, 5, 5});
  const Totals start = totals(mesh);
  EXPECT_EQ(start.components, 2u);
  insert_then_delete(mesh, mesh.face_corners(2)[3], Corner::point_sphere_of(p),
                     changed(start, 0, 1, -1, -1, 0));
  insert_then_delete(mesh, Corner::point_sphere_of(p), mesh.face_corners(2)[3],
                     changed(start, 0, 1, -1, -1, 0));
}

TEST(DlflMesh, LoopAtAPointSphereMakesASphereOfTwoFaces) {
  DlflMesh mesh;
  const VertexId v = mesh.create_vertex({0, 0, 0});
  const Corner c = Corner::point_sphere_of(v);
  insert_then_delete(mesh, c, c, Totals{1, 1, 2, 1, 0});
}

TEST(DlflMesh, DeleteEdgeOfTwoFacesMergesThem) {
  DlflMesh mesh = cube();
  const Totals start = totals(mesh);
  mesh.delete_edge(0);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), changed(start, 0, -1, -1, 0, 0));
  EXPECT_THROW(mesh.delete_edge(0), PreconditionError);
}

TEST(DlflMesh, DeleteEdgeSplitsAComponentOrLowersTheGenus) {
  // Two cubes joined by a bridge edge: deleting the bridge splits the component.
  DlflMesh mesh = cube();
  const VertexId p = mesh.create_vertex({3, 0, 0});
  mesh.insert_edge(Corner::point_sphere_of(p), Corner::at(mesh.face_halfedge(1)));
  const Totals joined = totals(mesh);
  const HalfedgeId bridge = mesh.vertex_halfedge(p);
  mesh.delete_edge(DlflMesh::edge(bridge));
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), changed(joined, 0, -1, 1, 1, 0));
  EXPECT_TRUE(mesh.is_point_sphere(p));
  // A handle edge: deleting it splits its face and lowers the genus.
  const HalfedgeId handle =
      mesh.insert_edge(Corner::at(mesh.face_halfedge(0)), Corner::at(mesh.face_halfedge(1)));
  const Totals torus = totals(mesh);
  EXPECT_EQ(torus.genus, 1);
  mesh.delete_edge(DlflMesh::edge(handle));
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), changed(torus, 0, -1, 1, 0, -1));
}

TEST(DlflMesh, RotationIsClockwiseSeenFromOutside) {
  const DlflMesh mesh = cube();
  for (VertexId v = 0; v < 8; ++v) {
    const std::vector<HalfedgeId> rotation = mesh.rotation(v);
    ASSERT_EQ(rotation.size(), 3u);
    Vec3 d[3];
    for (int i = 0; i < 3; ++i) d[i] = mesh.position(mesh.head(rotation[i])) - mesh.position(v);
    const Vec3 outward = mesh.position(v) - Vec3{0.5, 0.5, 0.5};
    EXPECT_LT(dot(cross(d[0], d[1]), outward), 0);
    EXPECT_EQ(mesh.vertex_corners(v).size(), 3u);
    for (Corner c : mesh.vertex_corners(v)) EXPECT_EQ(mesh.corner_vertex(c), v);
  }
}

TEST(DlflConvert, KeepsVerticesFacesAndLoopsOfTheCgalMeshes) {
  size_t converted = 0, refused = 0;
  for (const auto& entry : std::filesystem::directory_iterator(COVER_CGAL_MESHES)) {
    if (entry.path().extension() != ".off" || entry.file_size() > 8'000'000) continue;
    PolygonMesh input;
    try {
      input = read_mesh(entry.path());
    } catch (const InputError&) {
      continue;
    }
    DlflMesh mesh;
    try {
      mesh = from_polygon_mesh(input);
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
      ++refused;
      continue;
    }
    SCOPED_TRACE(entry.path().filename().string());
    ++converted;
    check_valid(mesh);
    const PolygonMesh output = to_polygon_mesh(mesh);
    EXPECT_EQ(output.vertices, input.vertices);
    EXPECT_EQ(output.face_start, input.face_start);
    EXPECT_EQ(output.face_vertices, input.face_vertices);
  }
  RecordProperty("converted", std::to_string(converted));
  RecordProperty("refused", std::to_string(refused));
  EXPECT_GE(converted, 20u);
  EXPECT_GE(refused, 1u);  // open meshes (a boundary) are refused
}

TEST(DlflConvert, KnownGenusOfCgalMeshes) {
  const DlflMesh torus = from_polygon_mesh(read_mesh(cover::test::cgal_mesh("3torus.off")));
  const std::vector<ComponentInfo> parts = components(torus);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].genus, 3);
}

TEST(DlflConvert, RefusesInvalidMeshesWithOneLine) {
  PolygonMesh open = cover::test::unit_tetrahedron();
  open.face_start.pop_back();
  open.face_vertices.resize(open.face_start.back());
  PolygonMesh flipped = cover::test::unit_tetrahedron();
  std::swap(flipped.face_vertices[0], flipped.face_vertices[1]);
  PolygonMesh pinched = cover::test::unit_tetrahedron();  // two tetrahedra sharing vertex 0
  pinched.vertices.insert(pinched.vertices.end(), {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}});
  for (auto face : {std::vector<uint32_t>{0, 4, 5}, {0, 6, 4}, {0, 5, 6}, {4, 6, 5}})
    pinched.add_face(face);
  PolygonMesh repeated = cover::test::unit_tetrahedron();
  repeated.face_vertices[1] = repeated.face_vertices[0];
  PolygonMesh out_of_range = cover::test::unit_tetrahedron();
  out_of_range.face_vertices[2] = 9;
  for (const PolygonMesh& bad : {open, flipped, pinched, repeated, out_of_range}) {
    try {
      from_polygon_mesh(bad);
      ADD_FAILURE() << "accepted an invalid mesh";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
}

TEST(DlflConvert, UnusedVerticesBecomePointSpheres) {
  PolygonMesh input = cover::test::unit_tetrahedron();
  input.vertices.push_back({7, 7, 7});
  const DlflMesh mesh = from_polygon_mesh(input);
  check_valid(mesh);
  EXPECT_TRUE(mesh.is_point_sphere(4));
  EXPECT_EQ(totals(mesh), (Totals{5, 6, 5, 2, 0}));
  const PolygonMesh output = to_polygon_mesh(mesh);
  EXPECT_EQ(output.vertices, input.vertices);
  EXPECT_EQ(output.face_vertices, input.face_vertices);
}

// ---- the seeded fuzz ----

/// A random live corner: of a random live vertex.
Corner random_corner(const DlflMesh& mesh, std::mt19937_64& rng) {
  std::uniform_int_distribution<VertexId> pick(0, VertexId(mesh.vertex_capacity() - 1));
  VertexId v;
  do v = pick(rng);
  while (!mesh.vertex_alive(v));
  const std::vector<Corner> corners = mesh.vertex_corners(v);
  return corners[std::uniform_int_distribution<size_t>(0, corners.size() - 1)(rng)];
}

EdgeId random_edge(const DlflMesh& mesh, std::mt19937_64& rng) {
  std::uniform_int_distribution<EdgeId> pick(0, EdgeId(mesh.edge_capacity() - 1));
  EdgeId e;
  do e = pick(rng);
  while (!mesh.edge_alive(e));
  return e;
}

/// Both corners in one face, two faces of one component, or two components: forced by `kind`.
std::pair<Corner, Corner> random_corner_pair(const DlflMesh& mesh, int kind, std::mt19937_64& rng) {
  const std::vector<uint32_t> component = vertex_components(mesh);
  for (int tries = 0; tries < 50; ++tries) {
    const Corner c1 = random_corner(mesh, rng);
    if (kind == 0) {
      const std::vector<Corner> same = mesh.face_corners(mesh.corner_face(c1));
      return {c1, same[std::uniform_int_distribution<size_t>(0, same.size() - 1)(rng)]};
    }
    const Corner c2 = random_corner(mesh, rng);
    const bool one_component =
        component[mesh.corner_vertex(c1)] == component[mesh.corner_vertex(c2)];
    if (mesh.corner_face(c1) != mesh.corner_face(c2) && one_component == (kind == 1))
      return {c1, c2};
  }
  return {random_corner(mesh, rng), random_corner(mesh, rng)};
}

TEST(DlflFuzz, RandomOperatorsKeepTheMeshValid) {
#ifdef COVER_SANITIZED
  constexpr int kSteps = 10'000;
#else
  constexpr int kSteps = 100'000;
#endif
  std::mt19937_64 rng(20240607);
  PolygonMesh start = make_box({0, 0, 0}, {1, 1, 1});
  for (int i = 0; i < 4; ++i) start.vertices.push_back(Vec3{2.0 + i % 2, double(i / 2), 0});
  start.add_face({8, 10, 9});
  start.add_face({8, 9, 11});
  start.add_face({8, 11, 10});
  start.add_face({9, 10, 11});
  DlflMesh mesh = from_polygon_mesh(start);
  mesh.create_vertex({-1, 0, 0});
  mesh.create_vertex({-2, 0, 0});
  int counts[7] = {};
  for (int step = 0; step < kSteps; ++step) {
    const Totals before = totals(mesh);
    const bool large = mesh.edge_count() > 80 || mesh.vertex_count() > 60;
    int op = std::uniform_int_distribution<int>(0, 99)(rng);
    if (large) op = op % 2 == 0 ? 6 + op % 4 : 45 + op % 43;  // shrink: delete or remove
    if (mesh.edge_count() == 0 && op >= 45) op = 10;
    if (mesh.vertex_count() == 0) op = 0;
    SCOPED_TRACE("step " + std::to_string(step) + " op " + std::to_string(op));
    if (op < 6) {  // create_vertex
      mesh.create_vertex({double(step % 7), double(step % 5), double(step % 3)});
      ASSERT_EQ(totals(mesh), changed(before, 1, 0, 1, 1, 0));
      ++counts[0];
    } else if (op < 10) {  // delete_vertex of a point-sphere, if one is picked
      const Corner c = random_corner(mesh, rng);
      if (c.is_point_sphere()) {
        mesh.delete_vertex(c.vertex);
        ASSERT_EQ(totals(mesh), changed(before, -1, 0, -1, -1, 0));
        ++counts[1];
      }
    } else if (op < 45) {  // insert_edge, each case in turn
      const int kind = step % 3;
      const std::vector<uint32_t> component = vertex_components(mesh);
      const auto [c1, c2] = random_corner_pair(mesh, kind, rng);
      const bool same_face = mesh.corner_face(c1) == mesh.corner_face(c2);
      const bool one_component =
          component[mesh.corner_vertex(c1)] == component[mesh.corner_vertex(c2)];
      const test::Snapshot snap = step % 16 == 0 ? snapshot(mesh) : test::Snapshot{};
      const HalfedgeId h = mesh.insert_edge(c1, c2);
      const Totals expected = same_face       ? changed(before, 0, 1, 1, 0, 0)
                              : one_component ? changed(before, 0, 1, -1, 0, 1)
                                              : changed(before, 0, 1, -1, -1, 0);
      ASSERT_EQ(totals(mesh), expected);
      if (step % 16 == 0) {
        check_valid(mesh);
        mesh.delete_edge(DlflMesh::edge(h));
        ASSERT_TRUE(snapshot(mesh) == snap);
        mesh.insert_edge(c1, c2);
      }
      ++counts[2];
    } else if (op < 80) {  // delete_edge
      const EdgeId e = random_edge(mesh, rng);
      const bool same_face = mesh.face(2 * e) == mesh.face(2 * e + 1);
      mesh.delete_edge(e);
      const Totals after = totals(mesh);
      if (!same_face) {
        ASSERT_EQ(after, changed(before, 0, -1, -1, 0, 0));
      } else {  // the face splits: a component splits in two, or a genus drops
        ASSERT_TRUE(after == changed(before, 0, -1, 1, 1, 0) ||
                    after == changed(before, 0, -1, 1, 0, -1))
            << after;
      }
      ++counts[3];
    } else if (op < 88) {  // remove_edge
      const EdgeId e = random_edge(mesh, rng);
      const bool same_face = mesh.face(2 * e) == mesh.face(2 * e + 1);
      remove_edge(mesh, e);
      const Totals after = totals(mesh);
      // Ends left as point-spheres are removed with their faces and components.
      const long removed = long(before.vertices) - long(after.vertices);
      ASSERT_EQ(after.edges, before.edges - 1);
      ASSERT_TRUE(removed == 0 || removed == 1 || removed == 2);
      if (!same_face) {
        ASSERT_EQ(after, changed(before, -removed, -1, -1 - removed, -removed, 0));
      }
      ASSERT_LE(after.genus, before.genus);
      ++counts[4];
    } else {  // subdivide_edge
      const HalfedgeId h = 2 * random_edge(mesh, rng) + step % 2;
      const int k = 1 + step % 2;
      subdivide_edge(mesh, h, k);
      ASSERT_EQ(totals(mesh), changed(before, k, k, 0, 0, 0));
      ++counts[5];
    }
    check_valid(mesh);
  }
  for (int i = 0; i < 6; ++i) EXPECT_GT(counts[i], 0) << "operation " << i << " never ran";
}

}  // namespace
}  // namespace cover::modeler
