// brep::decompose (paper Fig. 20): the plane patcher report's cases (torus, knot, box with holes,
// box with rings), a box with a cylindrical hole (evaluated scene), mechanical parts from
// libcgal-demo; every piece exactly convex (is_convex_exact, itself checked to fail on a
// non-convex mesh), closed and outward (kernel validity and CGAL is_closed /
// is_outward_oriented), volumes summing to the input's to 1e-9; the three-point clip; errors;
// and the `cover decompose` CLI (outputs, JSON keys, open mesh → exit 2 naming the file).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "brep/clip.h"
#include "brep/decompose.h"
#include "brep/halfedge.h"
#include "helpers.h"
#include "model/model.h"
#include "solid/errors.h"
#include "solid/measure.h"
#include "solid/mesh_io.h"

namespace cover::test {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;

/// A tube of `sides` around the closed curve c(t), t in [0, 2π), `segments` rings: quads split
/// into triangles. Outward for a curve whose frame (tangent, normal, binormal) is right-handed.
template <typename Curve>
PolygonMesh tube(Curve c, int segments, int sides, double radius) {
  PolygonMesh m;
  const double tau = 2 * std::numbers::pi;
  for (int i = 0; i < segments; ++i) {
    const double t = tau * i / segments;
    const Vec3 p = c(t), dp = c(t + 1e-5) - c(t - 1e-5);
    const Vec3 tangent = (1 / std::sqrt(dot(dp, dp))) * dp;
    Vec3 n = cross(tangent, Vec3{0, 0, 1});
    n = (1 / std::sqrt(dot(n, n))) * n;
    const Vec3 b = cross(tangent, n);
    for (int j = 0; j < sides; ++j) {
      const double a = tau * j / sides;
      m.vertices.push_back(p + radius * (std::cos(a) * n + std::sin(a) * b));
    }
  }
  auto id = [&](int i, int j) { return static_cast<uint32_t>((i % segments) * sides + j % sides); };
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < sides; ++j) {
      m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  if (signed_volume(m) < 0) {  // orientation of the frame: flip
    PolygonMesh f;
    f.vertices = m.vertices;
    for (size_t k = 0; k < m.face_count(); ++k) {
      const auto v = m.face(k);
      f.add_face({v[0], v[2], v[1]});
    }
    return f;
  }
  return m;
}

PolygonMesh torus(int segments, int sides) {
  return tube([](double t) { return Vec3{2 * std::cos(t), 2 * std::sin(t), 0}; }, segments, sides, 0.6);
}

/// (2, 3) torus knot tube (the report's knot).
PolygonMesh knot(int segments, int sides) {
  return tube([](double t) {
    const double r = 2 + std::cos(3 * t);
    return Vec3{r * std::cos(2 * t), r * std::sin(2 * t), -std::sin(3 * t)};
  }, segments, sides, 0.4);
}

Mesh to_cgal(const PolygonMesh& m) {
  Mesh out;
  std::vector<Mesh::Vertex_index> vs;
  for (const Vec3& p : m.vertices) vs.push_back(out.add_vertex(K::Point_3(p.x, p.y, p.z)));
  for (size_t f = 0; f < m.face_count(); ++f) {
    std::vector<Mesh::Vertex_index> loop;
    for (uint32_t v : m.face(f)) loop.push_back(vs[v]);
    out.add_face(loop);
  }
  return out;
}

/// Every piece valid and exactly convex; the volumes add up to the input's.
void expect_valid_decomposition(const brep::DecomposeResult& r, double volume,
                                const std::string& what) {
  ASSERT_FALSE(r.pieces.empty()) << what;
  double sum = 0;
  for (size_t i = 0; i < r.pieces.size(); ++i) {
    const PolygonMesh& p = r.pieces[i];
    const brep::BrepReport v = brep::validate(brep::HalfedgeMesh::from_polygon_mesh(p));
    EXPECT_TRUE(v.closed && v.manifold) << what << " piece " << i;
    EXPECT_EQ(v.components, 1) << what << " piece " << i;
    EXPECT_TRUE(brep::is_convex_exact(p)) << what << " piece " << i;
    const Mesh m = to_cgal(p);
    EXPECT_TRUE(CGAL::is_closed(m)) << what << " piece " << i;
    EXPECT_TRUE(CGAL::Polygon_mesh_processing::is_outward_oriented(m)) << what << " piece " << i;
    const double vol = signed_volume(p);
    EXPECT_GT(vol, 0) << what << " piece " << i;
    sum += vol;
  }
  EXPECT_NEAR(sum, volume, 1e-9 * volume) << what;
  EXPECT_NEAR(r.volume, volume, 1e-9 * volume) << what;
  EXPECT_NEAR(r.input_volume, volume, 1e-12 * volume) << what;
}

TEST(IsConvexExact, AcceptsABoxAndRejectsAFrame) {
  EXPECT_TRUE(brep::is_convex_exact(unit_tetrahedron()));
  EXPECT_FALSE(brep::is_convex_exact(read_mesh(source_dir() / "models" / "frame.off")));
}

TEST(ClipThroughPoints, SameHalvesAsTheRoundedPlaneWhenItIsExact) {
  const PolygonMesh box = read_mesh(source_dir() / "models" / "frame.off");
  const brep::ClipResult a = brep::clip(box, brep::Plane{{0, 0, 1}, 1.0});
  const brep::ClipResult b = brep::clip(box, std::array<Vec3, 3>{{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}});
  EXPECT_DOUBLE_EQ(signed_volume(a.above.mesh), signed_volume(b.above.mesh));
  EXPECT_DOUBLE_EQ(signed_volume(a.below.mesh), signed_volume(b.below.mesh));
  EXPECT_EQ(b.above.face_source.size(), b.above.mesh.face_count());
  EXPECT_THROW(brep::clip(box, std::array<Vec3, 3>{{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}}), InputError);
}

// The report's cases (Table 1), generated small enough for the checked build.
TEST(Decompose, ReportCases) {
  const PolygonMesh cases[] = {torus(16, 8), knot(48, 6),
                               read_mesh(source_dir() / "models" / "box_with_holes.off"),
                               read_mesh(source_dir() / "models" / "box_with_rings.off"),
                               read_mesh(source_dir() / "models" / "frame.off")};
  const char* names[] = {"torus", "knot", "box_with_holes", "box_with_rings", "frame"};
  for (size_t i = 0; i < std::size(cases); ++i) {
    const brep::DecomposeResult r = brep::decompose(cases[i]);
    expect_valid_decomposition(r, signed_volume(cases[i]), names[i]);
    EXPECT_GT(r.reflex_edges, 0) << names[i];
    EXPECT_EQ(r.uncut_pieces, 0) << names[i];
  }
}

TEST(Decompose, ConvexInputIsOnePiece) {
  const brep::DecomposeResult r = brep::decompose(unit_tetrahedron());
  ASSERT_EQ(r.pieces.size(), 1u);
  EXPECT_EQ(r.reflex_edges, 0);
  EXPECT_EQ(r.cuts, 0);
  EXPECT_DOUBLE_EQ(signed_volume(r.pieces[0]), 1.0 / 6);
}

TEST(Decompose, BoxWithACylindricalHole) {
  const Model m = box({0, 0, 0}, {4, 4, 2}) - cylinder({2, 2, -1}, {2, 2, 3}, 1, 24);
  const brep::DecomposeResult r = m.decompose();
  expect_valid_decomposition(r, m.evaluate().volume, "box minus cylinder");
  EXPECT_GE(r.pieces.size(), 4u);  // a hole needs at least four convex pieces around it
}

TEST(Decompose, HalfAnglePlanesOnly) {
  brep::DecomposeOptions o;
  o.face_planes = false;
  const PolygonMesh m = read_mesh(source_dir() / "models" / "box_with_rings.off");
  expect_valid_decomposition(brep::decompose(m, o), signed_volume(m), "half-angle only");
}

// Mechanical parts from libcgal-demo (closed, no self-intersections); the checked build runs
// the two smallest.
TEST(Decompose, MechanicalParts) {
#ifdef COVER_SANITIZED
  const char* names[] = {"cross.off", "joint.off"};
#else
  const char* names[] = {"cross.off", "joint.off", "part.off", "anchor.off"};
#endif
  for (const char* name : names) {
    const PolygonMesh m = read_mesh(cgal_mesh(name));
    const brep::DecomposeResult r = brep::decompose(m);
    expect_valid_decomposition(r, signed_volume(m), name);
    EXPECT_GT(r.reflex_edges, 0) << name;
  }
}

TEST(Decompose, RefusesOpenAndInsideOutMeshes) {
  PolygonMesh open = unit_tetrahedron();
  open.face_start.pop_back();
  open.face_vertices.resize(open.face_start.back());
  EXPECT_THROW(brep::decompose(open), InputError);
  PolygonMesh flipped;
  const PolygonMesh t = unit_tetrahedron();
  flipped.vertices = t.vertices;
  for (size_t f = 0; f < t.face_count(); ++f) {
    const auto v = t.face(f);
    flipped.add_face({v[0], v[2], v[1]});
  }
  EXPECT_THROW(brep::decompose(flipped), InputError);
}

TEST(DecomposeCli, WritesPiecesAndJson) {
  const auto dir = temp_dir("decompose");
  const RunResult r = run_cover("decompose '" + (source_dir() / "models" / "box_with_rings.off").string() +
                                "' -o '" + (dir / "out").string() + "' --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  for (const char* key : {"pieces", "reflex_edges", "volume", "seconds", "seconds_detail"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_NEAR(j["volume"].get<double>(), 1952, 1952 * 1e-9);
  const nlohmann::json list = nlohmann::json::parse(read_file(dir / "out" / "pieces.json"));
  ASSERT_EQ(list["pieces"].size(), j["pieces"].get<size_t>());
  double sum = 0;
  for (const auto& p : list["pieces"]) {
    const PolygonMesh piece = read_mesh(dir / "out" / p["file"].get<std::string>());
    EXPECT_TRUE(brep::is_convex_exact(piece)) << p["file"];
    sum += signed_volume(piece);
  }
  EXPECT_NEAR(sum, 1952, 1952 * 1e-9);
  const RunResult ply = run_cover("decompose '" + (source_dir() / "models" / "frame.off").string() +
                                  "' -o '" + (dir / "ply").string() + "' --ext .ply");
  EXPECT_EQ(ply.status, 0) << ply.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "ply" / "piece_0000.ply"));
  std::filesystem::remove_all(dir);
}

TEST(DecomposeCli, OpenMeshIsExitTwoNamingTheFile) {
  const auto dir = temp_dir("decompose_open");
  const auto path = dir / "open.off";
  write_file(path, "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n");
  const RunResult r = run_cover("decompose '" + path.string() + "' -o '" + (dir / "out").string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("open.off"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "piece_0000.off"));
  const RunResult ext = run_cover("decompose '" + path.string() + "' -o '" + (dir / "o").string() +
                                  "' --ext .png");
  EXPECT_EQ(ext.status, 2);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover::test
