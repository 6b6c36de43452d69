// Operators that build solids' shapes (pipes, chamfers, wireframes, crusts): their V, E, F,
// genus and component changes, and embedded results (no self-intersections, exact).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "cover/io/mesh_io.h"
#include "cover/mesh/validate.h"
#include "cover/modeler/operators.h"
#include "cover/solid/errors.h"
#include "dlfl_checks.h"

namespace cover::modeler {
namespace {

using test::totals;
using test::Totals;

/// The box [min, max] with each side cut into k × k quads (outward, counter-clockwise).
PolygonMesh grid_box(Vec3 min, Vec3 max, int k) {
  PolygonMesh mesh;
  std::map<std::array<int, 3>, uint32_t> ids;
  auto vertex = [&](std::array<int, 3> g) {
    const auto [it, added] = ids.emplace(g, static_cast<uint32_t>(mesh.vertices.size()));
    if (added) {
      Vec3 p;
      for (int a = 0; a < 3; ++a) {
        const double t = double(g[a]) / k;
        (a == 0 ? p.x : a == 1 ? p.y : p.z) = min[a] + t * (max[a] - min[a]);
      }
      mesh.vertices.push_back(p);
    }
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // u × v = +axis
    for (int side : {0, k}) {
      for (int i = 0; i < k; ++i) {
        for (int j = 0; j < k; ++j) {
          std::array<uint32_t, 4> quad;
          const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
          for (int c = 0; c < 4; ++c) {
            std::array<int, 3> g{};
            g[axis] = side, g[u] = i + di[c], g[v] = j + dj[c];
            quad[c] = vertex(g);
          }
          if (side == 0) std::reverse(quad.begin(), quad.end());
          mesh.add_face(quad);
        }
      }
    }
  }
  return mesh;
}

/// Both meshes in one (the second's indices shifted).
PolygonMesh disjoint_union(PolygonMesh a, const PolygonMesh& b) {
  const auto offset = static_cast<uint32_t>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (size_t f = 0; f < b.face_count(); ++f) {
    std::vector<uint32_t> face;
    for (uint32_t v : b.face(f)) face.push_back(v + offset);
    a.add_face(face);
  }
  return a;
}

/// The quad of `mesh` whose vertices average to `center` (within 1e-12).
FaceId quad_at(const DlflMesh& mesh, Vec3 center) {
  for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
    if (!mesh.face_alive(f) || mesh.face_degree(f) != 4) continue;
    Vec3 sum{0, 0, 0};
    for (VertexId v : mesh.face_vertices(f)) sum = sum + mesh.position(v);
    const Vec3 d = 0.25 * sum - center;
    if (dot(d, d) < 1e-24) return f;
  }
  ADD_FAILURE() << "no quad around (" << center.x << ", " << center.y << ", " << center.z << ")";
  return kNone;
}

// A pipe between whole opposite faces of a cube runs along the cube's other faces (the check
// sees it); the pipes below join the middle quads of 3 × 3 grids, so their walls cross the
// interior.
TEST(CreatePipe, BetweenWholeCubeFacesTouchesTheOtherFaces) {
  DlflMesh mesh = test::cube();
  create_pipe(mesh, quad_at(mesh, {1, 0.5, 0.5}), quad_at(mesh, {0, 0.5, 0.5}));
  check_valid(mesh);
  EXPECT_TRUE(self_intersects(to_polygon_mesh(mesh)));
}

TEST(CreatePipe, ThroughACubeIsEmbeddedAndRaisesTheGenus) {
  for (int segments : {1, 3}) {
    SCOPED_TRACE(segments);
    DlflMesh mesh = from_polygon_mesh(grid_box({0, 0, 0}, {1, 1, 1}, 3));
    const Totals before = totals(mesh);
    create_pipe(mesh, quad_at(mesh, {1, 0.5, 0.5}), quad_at(mesh, {0, 0.5, 0.5}), {segments, 0});
    check_valid(mesh);
    const auto n = static_cast<size_t>(segments);
    EXPECT_EQ(totals(mesh), (Totals{before.vertices + 4 * (n - 1), before.edges + 4 * (2 * n - 1),
                                    before.faces + 4 * n - 2, 1, 1}));
    EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
  }
}

TEST(CreatePipe, BetweenTwoCubesSideBySideIsEmbedded) {
  for (int segments : {1, 3}) {
    SCOPED_TRACE(segments);
    DlflMesh mesh = from_polygon_mesh(
        disjoint_union(grid_box({0, 0, 0}, {1, 1, 1}, 3), grid_box({2, 0, 0}, {3, 1, 1}, 3)));
    const Totals before = totals(mesh);
    ASSERT_EQ(before.components, 2u);
    create_pipe(mesh, quad_at(mesh, {1, 0.5, 0.5}), quad_at(mesh, {2, 0.5, 0.5}), {segments, 0});
    check_valid(mesh);
    const auto n = static_cast<size_t>(segments);
    EXPECT_EQ(totals(mesh), (Totals{before.vertices + 4 * (n - 1), before.edges + 4 * (2 * n - 1),
                                    before.faces + 4 * n - 2, 1, 0}));
    EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
    // A pipe through the first cube of the joined solid makes a handle.
    create_pipe(mesh, quad_at(mesh, {0.5, 1, 0.5}), quad_at(mesh, {0.5, 0, 0.5}), {segments, 0});
    check_valid(mesh);
    EXPECT_EQ(totals(mesh).genus, 1);
    EXPECT_EQ(totals(mesh).components, 1u);
    EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
  }
}

TEST(InsetFace, ShrinksTheFaceInsideARingOfQuads) {
  DlflMesh mesh = test::cube();
  const FaceId f = quad_at(mesh, {1, 0.5, 0.5});
  EXPECT_EQ(inset_face(mesh, f, 0.5), f);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{12, 20, 10, 1, 0}));
  EXPECT_EQ(quad_at(mesh, {1, 0.5, 0.5}), f);
  for (VertexId v : mesh.face_vertices(f)) {
    EXPECT_EQ(mesh.position(v).x, 1);
    EXPECT_EQ(std::abs(mesh.position(v).y - 0.5), 0.25);
  }
  EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
  EXPECT_THROW(inset_face(mesh, f, 1), InputError);
}

TEST(ChamferEdge, ReplacesACubeEdgeByAQuad) {
  DlflMesh mesh = test::cube();
  for (EdgeId e = 0; e < 12; ++e) {
    SCOPED_TRACE(e);
    DlflMesh chamfered = mesh;
    const FaceId f = chamfer_edge(chamfered, e, 0.25);
    check_valid(chamfered);
    EXPECT_EQ(totals(chamfered), (Totals{10, 15, 7, 1, 0}));
    EXPECT_EQ(chamfered.face_degree(f), 4u);
    EXPECT_FALSE(self_intersects(to_polygon_mesh(chamfered)));
  }
  // A second chamfer on an edge that kept both ends: the first chamfer's far edge.
  const FaceId f = chamfer_edge(mesh, 0, 0.25);
  std::vector<EdgeId> untouched;
  for (EdgeId e = 0; e < mesh.edge_capacity(); ++e) {
    if (!mesh.edge_alive(e)) continue;
    bool far = true;
    for (HalfedgeId h : mesh.face_loop(f))
      far = far && mesh.tail(2 * e) != mesh.tail(h) && mesh.head(2 * e) != mesh.tail(h);
    if (far && mesh.face_degree(mesh.face(2 * e)) == 4 &&
        mesh.face_degree(mesh.face(2 * e + 1)) == 4)
      untouched.push_back(e);
  }
  ASSERT_FALSE(untouched.empty());
  chamfer_edge(mesh, untouched[0], 0.25);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{12, 18, 8, 1, 0}));
  EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
  EXPECT_THROW(chamfer_edge(mesh, static_cast<EdgeId>(mesh.edge_capacity()), 0.25),
               PreconditionError);
  EXPECT_THROW(chamfer_edge(mesh, mesh.edge(mesh.face_halfedge(f)), 0.5), InputError);
}

TEST(ChamferEdge, KeepsAnEndOfHigherValence) {
  // A spoke of a square pyramid on a cube: the apex and the cube corner have valence 4, so
  // both stay corners of the new face (a hexagon).
  DlflMesh mesh = test::cube();
  const VertexId apex = stellate_face(mesh, quad_at(mesh, {0.5, 0.5, 1}), 0.5);
  const EdgeId e = DlflMesh::edge(mesh.vertex_halfedge(apex));
  const FaceId f = chamfer_edge(mesh, e, 0.25);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{9 + 4, 16 + 5, 9 + 1, 1, 0}));
  EXPECT_EQ(mesh.face_degree(f), 6u);
  EXPECT_TRUE(mesh.vertex_alive(apex));
  EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
}

TEST(Bevel, GivesTheDooSabinPattern) {
  for (const char* name : {"cube", "torus"}) {
    SCOPED_TRACE(name);
    DlflMesh mesh = std::string(name) == "cube"
                        ? test::cube()
                        : from_polygon_mesh(read_mesh(std::filesystem::path(COVER_SOURCE_DIR) /
                                                      "models/torus.off"));
    const Totals before = totals(mesh);
    const size_t corners = 2 * before.edges;
    bevel(mesh, 0.2);
    check_valid(mesh);
    EXPECT_EQ(totals(mesh),
              (Totals{corners, 2 * corners, before.faces + before.edges + before.vertices, 1,
                      before.genus}));
    EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
  }
  // The cube's corner (0, 0, 0) becomes a triangle at 0.1 along two axes.
  DlflMesh mesh = test::cube();
  bevel(mesh, 0.2);
  size_t triangles = 0;
  for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
    if (!mesh.face_alive(f) || mesh.face_degree(f) != 3) continue;
    ++triangles;
    for (VertexId v : mesh.face_vertices(f)) {
      const Vec3 p = mesh.position(v);
      int on_middle = 0;
      for (int a = 0; a < 3; ++a) on_middle += p[a] == 0.1 || p[a] == 0.9;
      EXPECT_EQ(on_middle, 2);
    }
  }
  EXPECT_EQ(triangles, 8u);
  EXPECT_THROW(bevel(mesh, 1.5), InputError);
}

/// Crust counts for a connected closed mesh with `before` totals, k punched faces of total
/// degree n.
Totals crust_totals(const Totals& before, size_t k, size_t n) {
  return {2 * before.vertices + 2 * n, 2 * before.edges + 5 * n, 2 * before.faces + 3 * n - 2 * k,
          1, 2 * before.genus + static_cast<int>(k) - 1};
}

TEST(Crust, PunchedFacesBecomeTunnelsIntoTheRind) {
  for (size_t k = 1; k <= 6; ++k) {
    SCOPED_TRACE(k);
    DlflMesh mesh = test::cube();
    std::vector<FaceId> punched;
    for (FaceId f = 0; f < k; ++f) punched.push_back(f);
    const Totals before = totals(mesh);
    crust(mesh, punched, {0.1, 0.2});
    check_valid(mesh);
    EXPECT_EQ(totals(mesh), crust_totals(before, k, 4 * k));
    EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
  }
  // No punched face: the two shells.
  DlflMesh shells = test::cube();
  crust(shells, {});
  check_valid(shells);
  EXPECT_EQ(totals(shells), (Totals{16, 24, 12, 2, 0}));
  EXPECT_FALSE(self_intersects(to_polygon_mesh(shells)));
  // The inner shell is the cube shrunk by the thickness on every side.
  for (VertexId v = 8; v < 16; ++v)
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(std::min(shells.position(v)[a], 1 - shells.position(v)[a]), 0.1, 1e-15);
}

TEST(Crust, OfATorusRaisesTheGenus) {
  DlflMesh mesh =
      from_polygon_mesh(read_mesh(std::filesystem::path(COVER_SOURCE_DIR) / "models/torus.off"));
  const Totals before = totals(mesh);
  ASSERT_EQ(before.genus, 1);
  const size_t degrees = mesh.face_degree(0) + mesh.face_degree(5);
  crust(mesh, {0, 5}, {0.02, 0.3});
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), crust_totals(before, 2, degrees));
  EXPECT_EQ(totals(mesh).genus, 3);
  EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
}

TEST(Wireframe, GenusIsTheCycleRankOfTheEdgeGraph) {
  struct Case {
    const char* name;
    DlflMesh mesh;
  };
  DlflMesh pyramid = test::cube();
  stellate_face(pyramid, 0, 0.5);
  for (Case& c : std::vector<Case>{{"cube", test::cube()}, {"stellated cube", pyramid}}) {
    SCOPED_TRACE(c.name);
    const Totals before = totals(c.mesh);
    const size_t corners = 2 * before.edges;
    wireframe(c.mesh, {0.05, 0.25});
    check_valid(c.mesh);
    const int cycle_rank = static_cast<int>(before.edges) - static_cast<int>(before.vertices) + 1;
    EXPECT_EQ(totals(c.mesh), (Totals{2 * before.vertices + 2 * corners,
                                      2 * before.edges + 5 * corners, 3 * corners, 1, cycle_rank}));
    EXPECT_EQ(static_cast<size_t>(cycle_rank), before.faces - 1);
    EXPECT_FALSE(self_intersects(to_polygon_mesh(c.mesh)));
  }
}

TEST(ExtrudeFaceDooSabin, PlacesTheCornerMaskOverTheMovedFace) {
  DlflMesh mesh = test::cube();
  const FaceId f = quad_at(mesh, {0.5, 0.5, 1});
  EXPECT_EQ(extrude_face_doo_sabin(mesh, f, 1.0), f);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh), (Totals{12, 20, 10, 1, 0}));
  // On a square the mask (9, 3, 1, 3)/16 halves the square about its centre.
  for (VertexId v : mesh.face_vertices(f)) {
    EXPECT_NEAR(mesh.position(v).z, 2, 1e-15);
    EXPECT_NEAR(std::abs(mesh.position(v).x - 0.5), 0.25, 1e-15);
    EXPECT_NEAR(std::abs(mesh.position(v).y - 0.5), 0.25, 1e-15);
  }
  EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
  EXPECT_THROW(extrude_face_doo_sabin(mesh, f, 1.0, {0.0, 0.0}), InputError);
}

TEST(ExtrudeFaceDome, StacksRingsUnderALowCone) {
  DlflMesh mesh = test::cube();
  const Totals before = totals(mesh);
  const VertexId apex = extrude_face_dome(mesh, quad_at(mesh, {0.5, 0.5, 1}), 1.0);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh),
            (Totals{before.vertices + 21, before.edges + 44, before.faces + 23, 1, 0}));
  EXPECT_NEAR(mesh.position(apex).z, 1 + 0.3 + 0.18 + 0.1 + 0.05 + 0.025 + 0.01, 1e-12);
  EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
}

TEST(ExtrudeFaceDodecahedral, RaisesARingOfPentagons) {
  for (int sides : {4, 5}) {
    SCOPED_TRACE(sides);
    DlflMesh mesh = test::cube();
    FaceId f = quad_at(mesh, {0.5, 0.5, 1});
    if (sides == 5) {  // a pentagon: cut one corner of the top face off
      const HalfedgeId h = mesh.face_halfedge(f);
      subdivide_edge(mesh, h, 1);
    }
    const Totals before = totals(mesh);
    const auto n = static_cast<size_t>(sides);
    const FaceId top = extrude_face_dodecahedral(mesh, f, 0.6);
    check_valid(mesh);
    EXPECT_EQ(totals(mesh),
              (Totals{before.vertices + 3 * n, before.edges + 5 * n, before.faces + 2 * n, 1, 0}));
    EXPECT_EQ(mesh.face_degree(top), n);
    size_t pentagons = 0;
    for (FaceId g = 0; g < mesh.face_capacity(); ++g)
      pentagons += mesh.face_alive(g) && mesh.face_degree(g) == 5 && g != top;
    EXPECT_GE(pentagons, 2 * n);
    for (VertexId v : mesh.face_vertices(top)) EXPECT_NEAR(mesh.position(v).z, 1.6, 1e-12);
    EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
  }
  DlflMesh mesh = test::cube();
  EXPECT_THROW(extrude_face_dodecahedral(mesh, 99, 1.0), PreconditionError);
  EXPECT_THROW(extrude_face_dodecahedral(mesh, 0, 1.0, 0.0), InputError);
  EXPECT_THROW(extrude_face_dome(mesh, 99, 1.0), PreconditionError);
  const VertexId p = mesh.create_vertex({5, 5, 5});
  EXPECT_THROW(extrude_face_dodecahedral(mesh, mesh.point_sphere_face(p), 1.0), InputError);
  EXPECT_EQ(totals(mesh), (Totals{9, 12, 7, 2, 0}));
}

TEST(Crust, RefusesBadArguments) {
  DlflMesh mesh = test::cube();
  EXPECT_THROW(crust(mesh, {99}), PreconditionError);
  EXPECT_THROW(crust(mesh, {0, 0}), InputError);
  EXPECT_THROW(crust(mesh, {0}, {0.0, 0.2}), InputError);
  EXPECT_THROW(crust(mesh, {0}, {0.1, 1.0}), InputError);
  EXPECT_EQ(totals(mesh), (Totals{8, 12, 6, 1, 0}));
}

/// The Hermite centre curve of a curved pipe between faces with centroids c1, c2 and outward
/// normals n1, n2, weights 1, no path points (written out here independently of pipe_path.cpp).
Vec3 hermite(Vec3 c1, Vec3 n1, Vec3 c2, Vec3 n2, double t, Vec3* tangent) {
  const double l = std::sqrt(dot(c2 - c1, c2 - c1));
  const Vec3 m0 = l * n1, m1 = -l * n2;
  const double t2 = t * t, t3 = t2 * t;
  *tangent = (6 * t2 - 6 * t) * c1 + (3 * t2 - 4 * t + 1) * m0 + (6 * t - 6 * t2) * c2 +
             (3 * t2 - 2 * t) * m1;
  return (2 * t3 - 3 * t2 + 1) * c1 + (t3 - 2 * t2 + t) * m0 + (3 * t2 - 2 * t3) * c2 +
         (t3 - t2) * m1;
}

/// The new vertices (ids from `first`) within `radius` of `centre` in the plane through it
/// across `tangent`.
std::vector<Vec3> ring_near(const DlflMesh& mesh, VertexId first, Vec3 centre, Vec3 tangent,
                            double radius) {
  const Vec3 u = (1 / std::sqrt(dot(tangent, tangent))) * tangent;
  std::vector<Vec3> ring;
  for (VertexId v = first; v < mesh.vertex_capacity(); ++v) {
    if (!mesh.vertex_alive(v)) continue;
    const Vec3 d = mesh.position(v) - centre;
    if (dot(d, d) <= radius * radius && std::abs(dot(d, u)) < 1e-9)
      ring.push_back(mesh.position(v));
  }
  return ring;
}

// A curved handle between two quads on the top of a bar arches over it: every inner ring is
// planar across the Hermite curve and centred on it, the genus rises by one, and the result is
// embedded.
TEST(CreatePipe, CurvedHandleFollowsTheHermiteCurveAndIsEmbedded) {
  for (int segments : {2, 5, 16}) {
    SCOPED_TRACE(segments);
    DlflMesh mesh = from_polygon_mesh(grid_box({0, 0, 0}, {5, 1, 1}, 5));
    const Totals before = totals(mesh);
    const FaceId f1 = quad_at(mesh, {0.5, 0.5, 1}), f2 = quad_at(mesh, {4.5, 0.5, 1});
    const Vec3 c1{0.5, 0.5, 1}, c2{4.5, 0.5, 1}, up{0, 0, 1};
    PipeOptions options(segments);
    options.curved = true;
    create_pipe(mesh, f1, f2, options);
    check_valid(mesh);
    const auto n = static_cast<size_t>(segments);
    EXPECT_EQ(totals(mesh), (Totals{before.vertices + 4 * (n - 1), before.edges + 4 * (2 * n - 1),
                                    before.faces + 4 * n - 2, 1, 1}));
    EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
    for (int j = 1; j < segments; ++j) {
      Vec3 tangent;
      const Vec3 centre = hermite(c1, up, c2, up, double(j) / segments, &tangent);
      const std::vector<Vec3> ring =
          ring_near(mesh, static_cast<VertexId>(before.vertices), centre, tangent, 0.6);
      ASSERT_EQ(ring.size(), 4u) << "ring " << j;
      Vec3 mean{0, 0, 0};
      for (const Vec3& p : ring) mean = mean + 0.25 * p;
      EXPECT_LT(std::sqrt(dot(mean - centre, mean - centre)), 1e-12) << "ring " << j;
    }
  }
}

// Through a path point: the centre passes through it (the middle ring of an even count is
// centred there), and the handle stays embedded.
TEST(CreatePipe, CurvedHandleThroughAPathPoint) {
  DlflMesh mesh = from_polygon_mesh(grid_box({0, 0, 0}, {5, 1, 1}, 5));
  const Totals before = totals(mesh);
  PipeOptions options(12);
  options.path = {{2.5, 0.5, 3}};
  options.weight1 = options.weight2 = 0.5;
  create_pipe(mesh, quad_at(mesh, {0.5, 0.5, 1}), quad_at(mesh, {4.5, 0.5, 1}), options);
  check_valid(mesh);
  EXPECT_EQ(totals(mesh).genus, 1);
  EXPECT_FALSE(self_intersects(to_polygon_mesh(mesh)));
  // At the path point the curve's tangent is the Catmull–Rom one, (c2 − c1)/2: along x.
  const std::vector<Vec3> ring =
      ring_near(mesh, static_cast<VertexId>(before.vertices), {2.5, 0.5, 3}, {1, 0, 0}, 0.6);
  ASSERT_EQ(ring.size(), 4u);
  Vec3 mean{0, 0, 0};
  for (const Vec3& p : ring) mean = mean + 0.25 * p;
  EXPECT_LT(std::sqrt(dot(mean - Vec3{2.5, 0.5, 3}, mean - Vec3{2.5, 0.5, 3})), 1e-12);
  // The first and last rings stay near their faces: the pipe leaves and enters vertically.
  for (VertexId v = static_cast<VertexId>(before.vertices); v < mesh.vertex_capacity(); ++v) {
    if (mesh.vertex_alive(v)) {
      EXPECT_GT(mesh.position(v).z, 1.0);
    }
  }
}

TEST(CreatePipe, CurvedRefusesBadWeights) {
  for (double w : {0.0, -1.0, std::nan("")}) {
    DlflMesh mesh = from_polygon_mesh(grid_box({0, 0, 0}, {5, 1, 1}, 5));
    PipeOptions options(4);
    options.curved = true;
    options.weight2 = w;
    EXPECT_THROW(
        create_pipe(mesh, quad_at(mesh, {0.5, 0.5, 1}), quad_at(mesh, {4.5, 0.5, 1}), options),
        InputError);
    check_valid(mesh);  // nothing changed
    EXPECT_EQ(totals(mesh).genus, 0);
  }
}

}  // namespace
}  // namespace cover::modeler
