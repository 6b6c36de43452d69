// The user-level operators built from the minimal DLFL operators: their V, E, F, genus and
// component changes, their geometry, and their argument checks.
#include "cover/modeler/operators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cover/solid/errors.h"
#include "dlfl_checks.h"

namespace cover::modeler {
namespace {

using test::cube;
using test::totals;
using test::Totals;

/// The face of the unit cube whose vertices all have coordinate `axis` equal to `value`.
FaceId cube_face(const DlflMesh& mesh, int axis, double value) {
  for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
    if (!mesh.face_alive(f) || mesh.face_degree(f) != 4) continue;
    bool all = true;
    for (VertexId v : mesh.face_vertices(f)) all = all && mesh.position(v)[axis] == value;
    if (all) return f;
  }
  ADD_FAILURE() << "no face at axis " << axis << " = " << value;
  return kNone;
}

TEST(RemoveEdge, MergesFacesAndDropsPointSpheres) {
  DlflMesh mesh = cube();
  remove_edge(mesh, 0);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{8, 11, 5, 1, 0}));
  // A dangling edge to a new vertex: removing it removes the vertex too.
  const VertexId p = mesh.create_vertex({0.5, 0.5, 2});
  const HalfedgeId h =
      mesh.insert_edge(Corner::at(mesh.face_halfedge(2)), Corner::point_sphere_of(p));
  remove_edge(mesh, DlflMesh::edge(h));
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{8, 11, 5, 1, 0}));
  EXPECT_FALSE(mesh.vertex_alive(p));
  // An isolated edge: both ends go.
  DlflMesh pair;
  const VertexId a = pair.create_vertex({0, 0, 0}), b = pair.create_vertex({1, 0, 0});
  const HalfedgeId e = pair.insert_edge(Corner::point_sphere_of(a), Corner::point_sphere_of(b));
  remove_edge(pair, DlflMesh::edge(e));
  EXPECT_EQ(totals(pair), Totals{});
  EXPECT_THROW(remove_edge(pair, 0), PreconditionError);
}

TEST(SubdivideEdge, AddsVerticesOnTheEdgeAndKeepsTheFaces) {
  DlflMesh mesh = cube();
  const HalfedgeId h = mesh.face_halfedge(3);
  const FaceId left = mesh.face(h), right = mesh.face(DlflMesh::twin(h));
  const Vec3 p = mesh.position(mesh.tail(h)), q = mesh.position(mesh.head(h));
  const Totals start = totals(mesh);
  const std::vector<VertexId> added = subdivide_edge(mesh, h, 3);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{11, 15, 6, 1, 0}));
  EXPECT_EQ(start.faces, 6u);
  ASSERT_EQ(added.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const Vec3 expected = p + ((i + 1) / 4.0) * (q - p);
    const Vec3 d = mesh.position(added[i]) - expected;
    EXPECT_LT(dot(d, d), 1e-24);
    EXPECT_EQ(mesh.rotation(added[i]).size(), 2u);
  }
  EXPECT_EQ(mesh.face_degree(left), 7u);
  EXPECT_EQ(mesh.face_degree(right), 7u);
  // The new vertices run from tail to head along `left`, and from head to tail along `right`.
  auto order = [&](FaceId f) {
    std::vector<VertexId> loop = mesh.face_vertices(f), on;
    for (VertexId v : loop)
      if (std::find(added.begin(), added.end(), v) != added.end()) on.push_back(v);
    return on;
  };
  std::vector<VertexId> along = order(left), back = order(right);
  std::rotate(along.begin(), std::find(along.begin(), along.end(), added[0]), along.end());
  std::rotate(back.begin(), std::find(back.begin(), back.end(), added[2]), back.end());
  EXPECT_EQ(along, added);
  EXPECT_EQ(back, (std::vector<VertexId>{added[2], added[1], added[0]}));
  EXPECT_FALSE(mesh.halfedge_alive(h));  // the edge was replaced by the chain
  EXPECT_TRUE(subdivide_edge(mesh, mesh.face_halfedge(0), 0).empty());
  EXPECT_EQ(totals(mesh), (Totals{11, 15, 6, 1, 0}));
  EXPECT_THROW(subdivide_edge(mesh, mesh.face_halfedge(0), -1), InputError);
}

TEST(SubdivideEdge, WorksOnBridgesAndLoops) {
  DlflMesh mesh;
  const VertexId a = mesh.create_vertex({0, 0, 0}), b = mesh.create_vertex({1, 0, 0});
  const HalfedgeId bridge =
      mesh.insert_edge(Corner::point_sphere_of(a), Corner::point_sphere_of(b));
  subdivide_edge(mesh, bridge, 2);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{4, 3, 1, 1, 0}));
  const HalfedgeId loop = mesh.insert_edge(Corner::at(mesh.vertex_halfedge(a) ^ 1u),
                                           Corner::at(mesh.vertex_halfedge(a) ^ 1u));
  subdivide_edge(mesh, loop, 1);
  subdivide_edge(mesh, DlflMesh::twin(mesh.vertex_halfedge(a)), 1);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{6, 6, 2, 1, 0}));
}

TEST(CreatePipe, BetweenOppositeCubeFacesMakesATorus) {
  for (int segments : {1, 3}) {
    for (int twist : {0, 1}) {
      DlflMesh mesh = cube();
      create_pipe(mesh, cube_face(mesh, 2, 1), cube_face(mesh, 2, 0), {segments, twist});
      check_valid(mesh);
      const auto n = static_cast<size_t>(segments);
      EXPECT_EQ(totals(mesh), (Totals{8 + 4 * (n - 1), 12 + 4 * (2 * n - 1), 4 + 4 * n, 1, 1}));
      for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
        if (!mesh.face_alive(f)) continue;
        EXPECT_EQ(mesh.face_degree(f), 4u);
      }
    }
  }
}

TEST(CreatePipe, PairsTheClosestCornersAndPlacesRingsBetweenThem) {
  DlflMesh mesh = cube();
  const FaceId top = cube_face(mesh, 2, 1), bottom = cube_face(mesh, 2, 0);
  create_pipe(mesh, top, bottom, {2, 0});
  // Without twist every rail runs straight down: each ring vertex sits at z = 0.5 right between
  // a top and a bottom vertex of the same (x, y).
  size_t ring = 0;
  for (VertexId v = 8; v < mesh.vertex_capacity(); ++v) {
    if (!mesh.vertex_alive(v)) continue;
    ++ring;
    const Vec3 p = mesh.position(v);
    EXPECT_EQ(p.z, 0.5);
    EXPECT_TRUE((p.x == 0 || p.x == 1) && (p.y == 0 || p.y == 1));
  }
  EXPECT_EQ(ring, 4u);
}

TEST(CreatePipe, PipesBetweenPairsOfCubeFacesRaiseTheGenus) {
  DlflMesh mesh = cube();
  const FaceId faces[3][2] = {{cube_face(mesh, 2, 1), cube_face(mesh, 2, 0)},
                              {cube_face(mesh, 1, 1), cube_face(mesh, 1, 0)},
                              {cube_face(mesh, 0, 1), cube_face(mesh, 0, 0)}};
  for (int g = 1; g <= 3; ++g) {
    create_pipe(mesh, faces[g - 1][0], faces[g - 1][1], {2, 0});
    check_valid(mesh);
    const std::vector<ComponentInfo> parts = components(mesh);
    ASSERT_EQ(parts.size(), 1u);
    EXPECT_EQ(parts[0].genus, g);
  }
}

TEST(CreatePipe, BetweenTwoComponentsJoinsThem) {
  DlflMesh mesh = cube();
  const DlflMesh other = cube({3, 0, 0}, {4, 1, 1});
  // A second cube, built from the minimal operators: copy by polygon mesh.
  PolygonMesh both = to_polygon_mesh(mesh), second = to_polygon_mesh(other);
  const auto offset = static_cast<uint32_t>(both.vertices.size());
  both.vertices.insert(both.vertices.end(), second.vertices.begin(), second.vertices.end());
  for (size_t f = 0; f < second.face_count(); ++f) {
    std::vector<uint32_t> loop(second.face(f).begin(), second.face(f).end());
    for (uint32_t& v : loop) v += offset;
    both.add_face(loop);
  }
  mesh = from_polygon_mesh(both);
  EXPECT_EQ(components(mesh).size(), 2u);
  FaceId right = kNone, left = kNone;
  for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
    bool at1 = true, at3 = true;
    for (VertexId v : mesh.face_vertices(f)) {
      at1 = at1 && mesh.position(v).x == 1;
      at3 = at3 && mesh.position(v).x == 3;
    }
    if (at1) right = f;
    if (at3) left = f;
  }
  create_pipe(mesh, right, left);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{16, 28, 14, 1, 0}));
}

TEST(CreatePipe, RefusesUnequalOrSameFaces) {
  DlflMesh mesh = cube();
  const FaceId top = cube_face(mesh, 2, 1), bottom = cube_face(mesh, 2, 0);
  EXPECT_THROW(create_pipe(mesh, top, top), InputError);
  EXPECT_THROW(create_pipe(mesh, top, bottom, {0, 0}), InputError);
  subdivide_edge(mesh, mesh.face_halfedge(top), 1);
  EXPECT_THROW(create_pipe(mesh, top, bottom), InputError);
  const VertexId p = mesh.create_vertex({9, 9, 9});
  EXPECT_THROW(create_pipe(mesh, bottom, mesh.point_sphere_face(p)), InputError);
  EXPECT_THROW(create_pipe(mesh, bottom, 999), PreconditionError);
  check_valid(mesh);
}

TEST(ExtrudeFace, MovesACopyOfTheFaceAlongItsNormal) {
  DlflMesh mesh = cube();
  const FaceId top = cube_face(mesh, 2, 1);
  const FaceId result = extrude_face(mesh, top, 0.5);
  check_valid(mesh);
  EXPECT_EQ(result, top);
  EXPECT_EQ(totals(mesh), (Totals{12, 20, 10, 1, 0}));
  ASSERT_EQ(mesh.face_degree(top), 4u);
  for (VertexId v : mesh.face_vertices(top)) {
    EXPECT_GE(v, 8u);
    EXPECT_EQ(mesh.position(v).z, 1.5);
  }
  // Every side is a quad with two old and two new vertices; twice in a row stays valid.
  extrude_face(mesh, top, 1);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{16, 28, 14, 1, 0}));
  for (VertexId v : mesh.face_vertices(top)) EXPECT_EQ(mesh.position(v).z, 2.5);
  const VertexId p = mesh.create_vertex({0, 0, 0});
  EXPECT_THROW(extrude_face(mesh, mesh.point_sphere_face(p), 1), InputError);
}

TEST(ExtrudeFace, ThenPipeBetweenExtrusionsMakesAHandle) {
  DlflMesh mesh = cube({0, 0, 0}, {3, 1, 1});
  const FaceId left = cube_face(mesh, 0, 0), right = cube_face(mesh, 0, 3);
  extrude_face(mesh, left, 1);
  extrude_face(mesh, right, 1);
  create_pipe(mesh, left, right, {3, 0});
  check_valid(mesh);
  const std::vector<ComponentInfo> parts = components(mesh);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].genus, 1);
}

TEST(StellateFace, RaisesAConeOverTheFace) {
  DlflMesh mesh = cube();
  const FaceId top = cube_face(mesh, 2, 1);
  const VertexId apex = stellate_face(mesh, top, 0.5);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{9, 16, 9, 1, 0}));
  const Vec3 p = mesh.position(apex);
  EXPECT_EQ(p.x, 0.5);
  EXPECT_EQ(p.y, 0.5);
  EXPECT_EQ(p.z, 1.5);
  EXPECT_EQ(mesh.rotation(apex).size(), 4u);
  for (Corner c : mesh.vertex_corners(apex)) EXPECT_EQ(mesh.face_degree(mesh.corner_face(c)), 3u);
  const VertexId v = mesh.create_vertex({0, 0, 0});
  EXPECT_THROW(stellate_face(mesh, mesh.point_sphere_face(v), 1), InputError);
}

TEST(TruncateVertex, CutsACornerOffAndTruncatesACube) {
  DlflMesh mesh = cube();
  const FaceId cut = truncate_vertex(mesh, 7, 0.25);  // the corner (1, 1, 1)
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{10, 15, 7, 1, 0}));
  EXPECT_FALSE(mesh.vertex_alive(7));
  ASSERT_EQ(mesh.face_degree(cut), 3u);
  for (VertexId w : mesh.face_vertices(cut)) {
    const Vec3 p = mesh.position(w);
    EXPECT_DOUBLE_EQ(p.x + p.y + p.z, 2.75);
  }
  // Outward: the cut face's normal points away from the cube's centre.
  const std::vector<VertexId> tri = mesh.face_vertices(cut);
  const Vec3 n = cross(mesh.position(tri[1]) - mesh.position(tri[0]),
                       mesh.position(tri[2]) - mesh.position(tri[0]));
  EXPECT_GT(dot(n, Vec3{1, 1, 1}), 0);
  for (VertexId v = 0; v < 7; ++v) truncate_vertex(mesh, v, 0.25);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{24, 36, 14, 1, 0}));  // the truncated cube
  EXPECT_THROW(truncate_vertex(mesh, 999, 0.5), PreconditionError);
  EXPECT_THROW(truncate_vertex(mesh, mesh.tail(mesh.face_halfedge(cut)), 1.5), InputError);
}

Totals changed(Totals t, long dv, long de, long df, long dc, int dg) {
  t.vertices += dv;
  t.edges += de;
  t.faces += df;
  t.components += dc;
  t.genus += dg;
  return t;
}

TEST(Operators, RandomSequencesKeepTheMeshValidAndMatchTheirCounts) {
  std::mt19937_64 rng(7);
  DlflMesh mesh = cube();
  auto random_face = [&] {
    std::uniform_int_distribution<FaceId> pick(0, FaceId(mesh.face_capacity() - 1));
    FaceId f;
    do f = pick(rng);
    while (!mesh.face_alive(f) || mesh.face_halfedge(f) == kNone);
    return f;
  };
  // Runs `op`; false when it refused (a degenerate face or a loop edge), leaving mesh as it was.
  int done[4] = {};
  auto applied = [&](const auto& op) {
    const test::Snapshot before = test::snapshot(mesh);
    try {
      op();
      return true;
    } catch (const InputError&) {
      EXPECT_TRUE(test::snapshot(mesh) == before);
      return false;
    }
  };
  for (int step = 0; step < 400; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    const Totals before = totals(mesh);
    const int op = step % 4;
    if (op == 0) {
      const FaceId f = random_face();
      const long n = long(mesh.face_degree(f));
      if (!applied([&] { extrude_face(mesh, f, 0.1); })) continue;
      ASSERT_EQ(totals(mesh), changed(before, n, 2 * n, n, 0, 0));
    } else if (op == 1) {
      const FaceId f = random_face();
      const long n = long(mesh.face_degree(f));
      if (!applied([&] { stellate_face(mesh, f, 0.1); })) continue;
      ASSERT_EQ(totals(mesh), changed(before, 1, n, n - 1, 0, 0));
    } else if (op == 2) {
      const FaceId f1 = random_face();
      FaceId f2 = kNone;
      for (int tries = 0; tries < 100 && f2 == kNone; ++tries) {
        const FaceId g = random_face();
        if (g != f1 && mesh.face_degree(g) == mesh.face_degree(f1)) f2 = g;
      }
      if (f2 == kNone) continue;
      const long n = long(mesh.face_degree(f1)), segments = 1 + step % 3;
      create_pipe(mesh, f1, f2, {int(segments), step % 2});
      ASSERT_EQ(totals(mesh), changed(before, n * (segments - 1), n * (2 * segments - 1),
                                      n * segments - 2, 0, 1));
    } else {
      std::uniform_int_distribution<VertexId> pick(0, VertexId(mesh.vertex_capacity() - 1));
      VertexId v;
      do v = pick(rng);
      while (!mesh.vertex_alive(v));
      const long d = long(mesh.rotation(v).size());
      if (!applied([&] { truncate_vertex(mesh, v, 0.3); })) continue;
      ASSERT_EQ(totals(mesh), changed(before, d - 1, d, 1, 0, 0));
    }
    check_valid(mesh);
    ++done[op];
    if (mesh.vertex_count() > 600) mesh = cube();
  }
  for (int op = 0; op < 4; ++op) EXPECT_GT(done[op], 50) << "operator " << op;
}

TEST(Operators, LibraryExample) {  // docs/library.md
  DlflMesh mesh = from_polygon_mesh(make_box({0, 0, 0}, {1, 1, 1}));
  create_pipe(mesh, 1, 0, PipeOptions(3));
  const FaceId lid = extrude_face(mesh, 5, 0.5);
  check_valid(mesh);
  EXPECT_EQ(lid, 5u);
  for (VertexId v : mesh.face_vertices(lid)) EXPECT_EQ(mesh.position(v).x, 1.5);
  const std::vector<ComponentInfo> parts = components(mesh);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].genus, 1);
  const PolygonMesh out = to_polygon_mesh(mesh);
  EXPECT_EQ(out.vertices.size(), mesh.vertex_count());
  EXPECT_EQ(out.face_count(), mesh.face_count());
}

}  // namespace
}  // namespace cover::modeler
