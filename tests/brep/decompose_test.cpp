// brep::decompose ([Erleben2006 §7 Fig. 20]): the plane patcher report's cases (torus, knot, box
// with holes, box with rings), a box with a cylindrical hole (evaluated scene), mechanical parts
// from libcgal-demo; every piece exactly convex (is_convex_exact, itself checked to fail on a
// non-convex mesh), closed and outward (kernel validity and CGAL is_closed / is_outward_oriented),
// volumes summing to the input's to 1e-9, convex as written (OFF round trip); separate solids
// (apart, touching along an edge or at a vertex) and cavities; scenes that need the exact Nef
// fallback; the same pieces for any thread count; random points in exactly one piece (exact
// classification); the three-point clip; errors; and the `cover decompose` CLI (outputs, JSON keys,
// open mesh and .stl pieces → exit 2).
#include "cover/brep/decompose.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>

#include "cover/brep/clip.h"
#include "cover/brep/detail/convex_hull.h"
#include "cover/brep/detail/nef_parts.h"
#include "cover/brep/halfedge.h"
#include "cover/io/mesh_io.h"
#include "cover/model/model.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"
#include "cover/solid/transform.h"
#include "helpers.h"

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
  return tube(
      [](double t) {
        return Vec3{2 * std::cos(t), 2 * std::sin(t), 0};
      },
      segments, sides, 0.6);
}

/// (2, 3) torus knot tube (the report's knot).
PolygonMesh knot(int segments, int sides) {
  return tube(
      [](double t) {
        const double r = 2 + std::cos(3 * t);
        return Vec3{r * std::cos(2 * t), r * std::sin(2 * t), -std::sin(3 * t)};
      },
      segments, sides, 0.4);
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

/// The box [lo, hi] as 12 outward triangles over 8 vertices appended to m.
void add_box(PolygonMesh& m, Vec3 lo, Vec3 hi) {
  const auto b = static_cast<uint32_t>(m.vertices.size());
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
  const uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                            {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) {
    m.add_face({b + f[0], b + f[1], b + f[2]});
    m.add_face({b + f[0], b + f[2], b + f[3]});
  }
}

/// The same mesh with each position used once (coincident vertices merged).
PolygonMesh merged(const PolygonMesh& m) {
  PolygonMesh out;
  std::vector<uint32_t> id(m.vertices.size());
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    size_t j = 0;
    while (j < out.vertices.size() && !(out.vertices[j] == m.vertices[i])) ++j;
    if (j == out.vertices.size()) out.vertices.push_back(m.vertices[i]);
    id[i] = static_cast<uint32_t>(j);
  }
  for (size_t f = 0; f < m.face_count(); ++f) {
    std::vector<uint32_t> loop;
    for (uint32_t v : m.face(f)) loop.push_back(id[v]);
    out.add_face(loop);
  }
  return out;
}

/// p strictly inside the convex piece (exact orient3d against every triangle).
bool strictly_inside(const PolygonMesh& piece, const Vec3& p) {
  for (size_t f = 0; f < piece.face_count(); ++f) {
    const auto v = piece.face(f);
    for (size_t k = 1; k + 1 < v.size(); ++k)
      if (orient3d(piece.vertices[v[0]], piece.vertices[v[k]], piece.vertices[v[k + 1]], p) >= 0)
        return false;
  }
  return true;
}

/// Each piece written as OFF and read back is exactly convex (the doubles as written).
void expect_convex_as_written(const brep::DecomposeResult& r, const std::string& what) {
  const auto dir = temp_dir("decompose_written");
  for (size_t i = 0; i < r.pieces.size(); ++i) {
    write_mesh(dir / "p.off", r.pieces[i]);
    EXPECT_TRUE(brep::is_convex_exact(read_mesh(dir / "p.off"))) << what << " piece " << i;
  }
  std::filesystem::remove_all(dir);
}

TEST(IsConvexExact, AcceptsABoxAndRejectsAFrame) {
  EXPECT_TRUE(brep::is_convex_exact(unit_tetrahedron()));
  EXPECT_FALSE(brep::is_convex_exact(read_mesh(source_dir() / "models" / "frame.off")));
}

TEST(ClipThroughPoints, SameHalvesAsTheRoundedPlaneWhenItIsExact) {
  const PolygonMesh box = read_mesh(source_dir() / "models" / "frame.off");
  const brep::ClipResult a = brep::clip(box, brep::Plane{{0, 0, 1}, 1.0});
  const brep::ClipResult b =
      brep::clip(box, std::array<Vec3, 3>{{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}});
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

TEST(Decompose, DisjointCubesAreSeparatePieces) {
  PolygonMesh m;
  add_box(m, {0, 0, 0}, {1, 1, 1});
  add_box(m, {3, 0, 0}, {4, 1, 1});
  const brep::DecomposeResult r = brep::decompose(m);
  expect_valid_decomposition(r, 2.0, "two cubes");
  ASSERT_EQ(r.pieces.size(), 2u);
  EXPECT_TRUE(strictly_inside(r.pieces[0], {0.5, 0.5, 0.5}));
  EXPECT_TRUE(strictly_inside(r.pieces[1], {3.5, 0.5, 0.5}));
}

// One OFF whose boxes share the vertices of their common edge or corner: two solids, each its
// own pieces (the hull of both would be larger).
TEST(Decompose, BoxesTouchingAlongAnEdgeOrAtAVertexAreNotMerged) {
  PolygonMesh edge, corner;
  add_box(edge, {0, 0, 0}, {1, 1, 1});
  add_box(edge, {1, 1, 0}, {2, 2, 1});
  add_box(corner, {0, 0, 0}, {1, 1, 1});
  add_box(corner, {1, 1, 1}, {2, 2, 2});
  for (const PolygonMesh& m : {merged(edge), merged(corner)}) {
    ASSERT_LT(m.vertices.size(), 16u);
    const brep::DecomposeResult r = brep::decompose(m);
    expect_valid_decomposition(r, 2.0, "touching boxes");
    EXPECT_EQ(r.pieces.size(), 2u);
  }
}

/// The box [0, 3]³ with the cavity [1, 2]³ (an inner, inside-out shell): volume 26.
PolygonMesh box_with_cavity() {
  PolygonMesh m, inner;
  add_box(m, {0, 0, 0}, {3, 3, 3});
  add_box(inner, {1, 1, 1}, {2, 2, 2});
  const auto b = static_cast<uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), inner.vertices.begin(), inner.vertices.end());
  for (size_t f = 0; f < inner.face_count(); ++f) {
    const auto v = inner.face(f);
    m.add_face({b + v[0], b + v[2], b + v[1]});
  }
  return m;
}

// A cavity (an inner, inside-out shell) is cut away from the box around it; a box beside them
// is decomposed on its own.
TEST(Decompose, BoxWithACavity) {
  PolygonMesh m = box_with_cavity();
  add_box(m, {5, 0, 0}, {6, 1, 1});
  const brep::DecomposeResult r = brep::decompose(m);
  expect_valid_decomposition(r, 27.0 - 1.0 + 1.0, "box with a cavity");
  for (const PolygonMesh& p : r.pieces) EXPECT_FALSE(strictly_inside(p, {1.5, 1.5, 1.5}));
}

// An L-shaped block with a spherical cavity away from its notch. With one candidate edge per cut,
// the planes through the notch (the most reflex edge) miss the cavity, which is then a separate
// inward component of one half: it stays with the component around it, so the cut is valid
// and the block does not fall back to the slow whole-shell path.
TEST(Decompose, ACavityStaysWithItsShellWhenACutMissesIt) {
  const Model m =
      (box({0, 0, 0}, {4, 1, 1}) | box({0, 0, 0}, {1, 4, 1})) - sphere({3.25, 0.5, 0.5}, 0.3, 12);
  brep::DecomposeOptions o;
  o.candidates = 1;
  const brep::DecomposeResult r = brep::decompose(m.evaluate().mesh, o);
  expect_valid_decomposition(r, m.evaluate().volume, "L with a cavity");
  EXPECT_GT(r.cuts, r.failed_cuts);  // the block was cut (without the cavity kept: 3 of 3 failed)
}

// The exact fallback's Nef polyhedra of a shell with a cavity: CGAL's Nef constructor marks the
// inside of every closed surface whatever its orientation, so one mesh holding both would come
// out filled (27, not 26), and every fallback of such a shell would miss the cavity's volume.
TEST(DecomposeFallback, NefOfAShellWithACavityLeavesTheCavityOut) {
  PolygonMesh m = box_with_cavity();
  auto volume = [](const std::vector<std::vector<Vec3>>& parts) {
    double sum = 0;
    for (const std::vector<Vec3>& part : parts)
      sum += signed_volume(brep::detail::convex_hull(std::span<const Vec3>(part)));
    return sum;
  };
  EXPECT_DOUBLE_EQ(volume(brep::detail::nef_convex_parts(m)), 26.0);
  const brep::detail::ShellRegions regions(m);
  const auto whole = regions.convex_parts({}, Bbox{{-1, -1, -1}, {4, 4, 4}});
  ASSERT_TRUE(whole.has_value());
  EXPECT_DOUBLE_EQ(volume(*whole), 26.0);
  // Above the plane z = 1.5 (through the cavity): 3 × 3 × 1.5 − 0.5.
  const brep::detail::HalfSpace top{{Vec3{0, 0, 1.5}, Vec3{1, 0, 1.5}, Vec3{0, 1, 1.5}}, true};
  const auto upper = regions.convex_parts(std::span(&top, 1), Bbox{{-1, -1, -1}, {4, 4, 4}});
  ASSERT_TRUE(upper.has_value());
  EXPECT_DOUBLE_EQ(volume(*upper), 13.0);
}

// Pieces as written (shortest round-trip doubles) are exactly convex, on a part whose cuts
// round many points.
TEST(Decompose, PiecesAreConvexAsWritten) {
#ifdef COVER_SANITIZED
  const char* names[] = {"joint.off"};
#else
  const char* names[] = {"joint.off", "rotor.off"};
#endif
  for (const char* name : names) {
    const PolygonMesh m = read_mesh(cgal_mesh(name));
    const brep::DecomposeResult r = brep::decompose(m);
    expect_valid_decomposition(r, signed_volume(m), name);
    expect_convex_as_written(r, name);
  }
}

// A box minus a cylinder united with a torus (its evaluated result stresses the cap).
TEST(Decompose, BoxMinusCylinderUnionTorus) {
  const Model torus = load(source_dir() / "models" / "torus.off");
  const Model m = (box({-3, -3, -1}, {3, 3, 1}) - cylinder({0, 0, -2}, {0, 0, 2}, 1, 32)) | torus;
  expect_valid_decomposition(m.decompose(), m.evaluate().volume, "box - cylinder | torus");
}

// The README's part: rounding leaves a piece non-convex, which the exact fallback redoes rather
// than refusing. Slow (Nef polyhedra): not in the checked build.
TEST(Decompose, ReadmePartUsesTheExactFallback) {
#ifdef COVER_SANITIZED
  GTEST_SKIP() << "slow under sanitizers";
#else
  const Model part = (box({0, 0, 0}, {2, 2, 2}) - sphere({2, 2, 2}, 1.2)) |
                     cylinder({0, 0, 0}, {0, 0, 3}, 0.5)
                         .transformed(Transform::trs({1, 1, 1}, {1, 0, 0}, 10, {0, 0, 0}));
  const brep::DecomposeResult r = part.decompose();
  expect_valid_decomposition(r, part.evaluate().volume, "part");
  EXPECT_GE(r.fallback_nodes, 1);
  expect_convex_as_written(r, "part");
#endif
}

// Two rotated couplingdown.off intersected (a random-CSG stress scene): a few pieces that no
// plane could cut are not convex; each is redone by the exact fallback on its own (milliseconds)
// instead of the whole shell (6,471 pieces, about two minutes). 2.5 s in Release: not in the
// checked build.
TEST(Decompose, ANonConvexPieceIsRedoneAloneNotWithItsShell) {
#ifdef COVER_SANITIZED
  GTEST_SKIP() << "slow under sanitizers";
#else
  const Model c = load(cgal_mesh("couplingdown.off"));
  const Transform a = Transform::from_matrix(std::array<double, 16>{
      0.80601186454012641, 1.2174827190834066, -0.18185958227939872, 0.094012323870378611,
      -1.1284324294652501, 0.64388837712216351, -0.69068097892670643, -0.03242253176177945,
      -0.49191191392841482, 0.51781829945771007, 1.2864210362066621, 0.35642708359188047, 0, 0, 0,
      1});
  const Transform b = Transform::from_matrix(std::array<double, 16>{
      0.78842507075773149, 1.1861733593896737, 1.0910138560638083, 0.35468440002866919,
      -1.6385487887558328, 0.28602865859990773, 0.80965210627314133, 0.36227396930485423,
      0.37767562034391466, -1.2352846664674109, 1.2351122928133886, -0.26375990912892844, 0, 0, 0,
      1});
  const Model m = c.transformed(a) & c.transformed(b);
  const brep::DecomposeResult r = m.decompose();
  expect_valid_decomposition(r, m.evaluate().volume, "couplingdown & couplingdown");
  EXPECT_GE(r.uncut_pieces, 1);
  EXPECT_GE(r.fallback_nodes, 1);
  EXPECT_LT(r.pieces.size(), 2000u);  // the cut pieces, not the shell's Nef parts
#endif
}

// libcgal-demo meshes that stress the rounded cap triangulation (cheese) and the internal
// invariants (fandisk). Minutes each in Release (cheese: 9,750 pieces, 146 s on 2 cores),
// so outside the suite: run it with --gtest_also_run_disabled_tests (ctest lists it as
// disabled).
TEST(Decompose, DISABLED_CheeseAndFandisk) {
#ifdef COVER_SANITIZED
  GTEST_SKIP() << "slow under sanitizers";
#else
  for (const char* name : {"cheese.off", "fandisk.off"}) {
    const PolygonMesh m = read_mesh(cgal_mesh(name));
    const brep::DecomposeResult r = brep::decompose(m);
    expect_valid_decomposition(r, signed_volume(m), name);
  }
#endif
}

// The same pieces (points and volumes) for any thread count; the triangulation of a hull facet
// with four or more coplanar points may still differ.
TEST(Decompose, SamePiecesForEveryThreadCount) {
  const PolygonMesh m = read_mesh(cgal_mesh("joint.off"));
  brep::DecomposeResult one, two;
  {
    const ThreadLimit limit(1);
    one = brep::decompose(m);
  }
  {
    const ThreadLimit limit(2);
    two = brep::decompose(m);
  }
  ASSERT_EQ(one.pieces.size(), two.pieces.size());
  for (size_t i = 0; i < one.pieces.size(); ++i) {
    EXPECT_EQ(one.pieces[i].vertices, two.pieces[i].vertices) << i;
    EXPECT_NEAR(signed_volume(one.pieces[i]), signed_volume(two.pieces[i]),
                1e-14 * signed_volume(one.pieces[i]))
        << i;
  }
}

// Random points of the box with holes: one inside the input lies strictly inside exactly one
// piece (up to points on piece boundaries), one outside in none (exact classification).
TEST(Decompose, InsidePointsLieInExactlyOnePiece) {
  const PolygonMesh m = read_mesh(source_dir() / "models" / "box_with_holes.off");
  const brep::DecomposeResult r = brep::decompose(m);
  const Model model = mesh(m);
  Vec3 lo = m.vertices[0], hi = m.vertices[0];
  for (const Vec3& p : m.vertices) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> points(2000);
  for (Vec3& p : points)
    p = {lo.x + u(rng) * (hi.x - lo.x), lo.y + u(rng) * (hi.y - lo.y),
         lo.z + u(rng) * (hi.z - lo.z)};
  const std::vector<PointClass> c = model.classify(points);
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    int in = 0;
    for (const PolygonMesh& p : r.pieces) in += strictly_inside(p, points[i]);
    if (c[i] == PointClass::kInside) {
      ++inside;
      EXPECT_LE(in, 1) << i;
    } else if (c[i] == PointClass::kOutside) {
      EXPECT_EQ(in, 0) << i;
    }
  }
  EXPECT_GT(inside, 100);
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
  const RunResult r =
      run_cover("decompose '" + (source_dir() / "models" / "box_with_rings.off").string() +
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
  const RunResult r = run_cover("decompose --closed-only '" + path.string() + "' -o '" +
                                (dir / "out").string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("open.off"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "piece_0000.off"));
  const RunResult ext =
      run_cover("decompose '" + path.string() + "' -o '" + (dir / "o").string() + "' --ext .png");
  EXPECT_EQ(ext.status, 2);
  std::filesystem::remove_all(dir);
}

TEST(DecomposeCli, RefusesStlPieces) {
  const auto dir = temp_dir("decompose_stl");
  const RunResult r = run_cover("decompose '" + (source_dir() / "models" / "frame.off").string() +
                                "' -o '" + (dir / "out").string() + "' --ext .stl");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("float32"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "piece_0000.stl"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cover::test
