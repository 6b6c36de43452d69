// Plane clip and patch (brep/clip.h) on constructed cases: CGAL's classic clip cases reproduced
// independently (hollow box, nine concentric cubes of alternating orientation, planes through
// vertices and along faces), faces with false edges, and the cap modes.
#include "cover/brep/clip.h"

#include <gtest/gtest.h>

#include <random>

#include "brep_checks.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/predicates.h"
#include "helpers.h"

namespace cover::brep {
namespace {

/// Appends the box [lo, hi]³ to m, outward (or inward when `reversed`).
void add_cube(PolygonMesh& m, double lo, double hi, bool reversed = false) {
  const uint32_t b = static_cast<uint32_t>(m.vertices.size());
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({(i & 1) ? hi : lo, (i & 2) ? hi : lo, (i & 4) ? hi : lo});
  const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    if (reversed)
      m.add_face({b + f[3], b + f[2], b + f[1], b + f[0]});
    else
      m.add_face({b + f[0], b + f[1], b + f[2], b + f[3]});
  }
}

ClipResult clip_and_check(const PolygonMesh& m, const Plane& p, const std::string& what,
                          const ClipOptions& o = {}) {
  ClipResult r;
  try {
    r = clip(m, p, o);
  } catch (const std::exception& e) {
    char plane[160];
    std::snprintf(plane, sizeof plane, "%.17g,%.17g,%.17g,%.17g", p.normal.x, p.normal.y,
                  p.normal.z, p.offset);
    ADD_FAILURE() << what << " plane " << plane << ": " << e.what();
    return r;
  }
  test::expect_valid_clip(r, p, signed_volume(m), -1, what);
  return r;
}

TEST(Clip, CubeThroughTheMiddle) {
  PolygonMesh m;
  add_cube(m, 0, 1);
  const ClipResult r = clip_and_check(m, {{0, 0, 1}, 0.25}, "cube z=0.25");
  EXPECT_NEAR(signed_volume(r.above.mesh), 0.75, 1e-15);
  EXPECT_EQ(r.above.rings, 1);
  EXPECT_EQ(r.below.rings, 1);
  EXPECT_EQ(r.above.cap_faces, 1);  // a square stays one convex face
  for (const Vec3& v : r.below.mesh.vertices) EXPECT_TRUE(v.z == 0 || v.z == 0.25);
}

TEST(Clip, TriangulatedCapsAreTriangles) {
  PolygonMesh m;
  add_cube(m, 0, 1);
  ClipOptions o;
  o.triangulate_caps = true;
  const ClipResult r = clip_and_check(m, {{1, 2, 3}, 2.5}, "cube oblique triangulated", o);
  EXPECT_GE(r.above.cap_faces, 2);
  const ClipResult c = clip_and_check(m, {{1, 2, 3}, 2.5}, "cube oblique convex");
  EXPECT_EQ(c.above.cap_faces, 1);
}

TEST(Clip, HollowBoxThroughBothShells) {
  // CGAL's classic: outer box ±2 outward, inner ±1 reversed (a cavity).
  PolygonMesh m;
  add_cube(m, -2, 2);
  add_cube(m, -1, 1, true);
  const ClipResult r = clip_and_check(m, {{0.3, -0.2, 1}, 0.1}, "hollow box");
  EXPECT_EQ(r.above.rings, 2);
  EXPECT_EQ(r.below.rings, 2);
  EXPECT_NEAR(signed_volume(r.above.mesh) + signed_volume(r.below.mesh), 56, 1e-12);
  // Axis plane: the cap is one square with a square hole, bridged then decomposed.
  const ClipResult a = clip_and_check(m, {{1, 0, 0}, 0}, "hollow box x=0");
  EXPECT_NEAR(signed_volume(a.above.mesh), 28, 1e-12);
}

TEST(Clip, NineConcentricCubesAlternating) {
  PolygonMesh m;
  for (int k = 9; k >= 1; --k) add_cube(m, -k, k, k % 2 == 0);
  const ClipResult r = clip_and_check(m, {{0.1, 0.2, 1}, 0.05}, "nine cubes");
  EXPECT_EQ(r.above.rings, 9);
  EXPECT_EQ(r.below.rings, 9);
  const ClipResult x = clip_and_check(m, {{0, 1, 0}, 0}, "nine cubes y=0");
  EXPECT_EQ(x.above.rings, 9);
}

TEST(Clip, PlaneAlongAFace) {
  PolygonMesh m;
  add_cube(m, 0, 1);
  // z = 0 is the plane of the bottom face (normal −z): the whole cube is above.
  ClipResult r = clip_and_check(m, {{0, 0, 1}, 0}, "cube z=0");
  EXPECT_EQ(r.above.mesh.face_count(), 6u);
  EXPECT_EQ(r.below.mesh.face_count(), 0u);
  // z = 1 is the plane of the top face (normal +z): the whole cube is below.
  r = clip_and_check(m, {{0, 0, 1}, 1}, "cube z=1");
  EXPECT_EQ(r.below.mesh.face_count(), 6u);
  EXPECT_EQ(r.above.mesh.face_count(), 0u);
  // Two stacked boxes sharing no face but touching the plane z = 1 from both sides along faces.
  PolygonMesh hollow;
  add_cube(hollow, -2, 2);
  add_cube(hollow, -1, 1, true);
  r = clip_and_check(hollow, {{0, 0, 1}, 1}, "hollow box along the cavity's top");
  EXPECT_NEAR(signed_volume(r.above.mesh), 4 * 4 * 1, 1e-12);
}

TEST(Clip, PlaneThroughADiagonalOfVertices) {
  PolygonMesh m;
  add_cube(m, 0, 1);
  // x − y = 0 passes through vertices 0, 3, 4, 7 (a diagonal rectangle).
  const ClipResult r = clip_and_check(m, {{1, -1, 0}, 0}, "cube diagonal");
  EXPECT_NEAR(signed_volume(r.above.mesh), 0.5, 1e-15);
  EXPECT_EQ(r.constructed_vertices, 0);
  // x + y + z = 1.5 cuts a regular hexagon.
  const ClipResult h = clip_and_check(m, {{1, 1, 1}, 1.5}, "cube hexagon");
  EXPECT_EQ(h.constructed_vertices, 6);
  EXPECT_NEAR(signed_volume(h.above.mesh), 0.5, 1e-15);
  // x + y + z = 1 passes through three vertices: a triangle cap.
  const ClipResult t = clip_and_check(m, {{1, 1, 1}, 1}, "cube corner");
  EXPECT_NEAR(signed_volume(t.below.mesh), 1.0 / 6, 1e-15);
}

TEST(Clip, FacesWithFalseEdges) {
  const PolygonMesh frame = read_mesh(test::source_dir() / "models/frame.off");
  const double v = signed_volume(frame);
  for (const Plane& p : {Plane{{1, 0, 0}, 2}, Plane{{1, 0, 0}, 0.5}, Plane{{0, 0, 1}, 2},
                         Plane{{1, 0.3, 0.2}, 2.15}, Plane{{0, 0, 1}, 4}}) {
    const ClipResult r = clip(frame, p);
    test::expect_valid_clip(r, p, v, -1, "frame");
  }
}

TEST(Clip, ExactPointsThatRoundToOneDouble) {
  // x + 0.3y + 0.2z = 2.1 misses the vertex (1, 1, 4) by less than half an ulp (0.3, 0.2, 2.1 are
  // not doubles): the point it constructs on the false edge next to it is a different exact
  // point that rounds onto that vertex. The halves stay closed 2-manifolds with the right
  // volumes; the cap ring has two nodes at one double point, which get a zero-area triangle of
  // their own (brep/cap.cpp), not a forced ear.
  const PolygonMesh frame = read_mesh(test::source_dir() / "models/frame.off");
  const Plane p{{1, 0.3, 0.2}, 2.1};
  const ClipResult r = clip(frame, p);
  for (const ClipHalf* h : {&r.above, &r.below}) {
    const BrepReport b = validate(HalfedgeMesh::from_polygon_mesh(h->mesh));
    EXPECT_TRUE(b.consistent && b.closed && b.manifold);
  }
  EXPECT_NEAR(signed_volume(r.above.mesh) + signed_volume(r.below.mesh), signed_volume(frame),
              1e-12);
  EXPECT_EQ(r.forced_ears, 0);
  int64_t zero_area = 0;
  for (const ClipHalf* h : {&r.above, &r.below})
    for (size_t f = 0; f < h->mesh.face_count(); ++f)
      zero_area += all_collinear(h->mesh.vertices, h->mesh.face(f)) ? 1 : 0;
  EXPECT_GT(zero_area, 0);
}

TEST(Clip, RejectsBadPlanesAndOpenMeshes) {
  PolygonMesh m;
  add_cube(m, 0, 1);
  EXPECT_THROW(clip(m, {{0, 0, 0}, 1}), InputError);
  EXPECT_THROW(clip(m, {{0, 0, NAN}, 1}), InputError);
  PolygonMesh open;
  open.vertices = m.vertices;
  for (size_t f = 1; f < m.face_count(); ++f) open.add_face(m.face(f));
  EXPECT_THROW(clip(open, {{0, 0, 1}, 0.5}), InputError);
}

TEST(Clip, AxisPlaneKeepsTheCoordinateExact) {
  const PolygonMesh torus = read_mesh(test::source_dir() / "models/torus.off");
  const double c = 0.123456789;
  const ClipResult r = clip_and_check(torus, {{1, 0, 0}, c}, "torus x=c");
  EXPECT_EQ(r.above.rings, 2);
  size_t on_plane = 0;
  for (const Vec3& v : r.above.mesh.vertices) on_plane += v.x == c;
  EXPECT_EQ(on_plane, static_cast<size_t>(r.constructed_vertices));
}

struct PaperModel {
  const char* file;
  int64_t rings_z0;  ///< rings per half cut by z = 0, from the construction
};

class ClipPaperModel : public ::testing::TestWithParam<PaperModel> {};

// Paper Table 1 / Fig. 19 models (models/make_patcher_models.py): z = 0 gives the constructed
// ring counts; seeded random planes through the box keep both halves valid.
TEST_P(ClipPaperModel, RingsAndValidity) {
  const PaperModel& pm = GetParam();
  const PolygonMesh m = read_mesh(test::source_dir() / "models" / pm.file);
  for (bool triangulate : {false, true}) {
    ClipOptions o;
    o.triangulate_caps = triangulate;
    const ClipResult r = clip_and_check(m, {{0, 0, 1}, 0}, std::string(pm.file) + " z=0", o);
    EXPECT_EQ(r.above.rings, pm.rings_z0) << pm.file;
    EXPECT_EQ(r.below.rings, pm.rings_z0) << pm.file;
  }
  const Bbox b = face_bbox(m);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1), t(0, 1);
  for (int i = 0; i < 10; ++i) {
    const Vec3 n{unit(rng), unit(rng), unit(rng)};
    const Vec3 p{b.min.x + t(rng) * (b.max.x - b.min.x), b.min.y + t(rng) * (b.max.y - b.min.y),
                 b.min.z + t(rng) * (b.max.z - b.min.z)};
    ClipOptions o;
    o.triangulate_caps = i % 2 == 1;
    clip_and_check(m, {n, dot(n, p)}, std::string(pm.file) + " random " + std::to_string(i), o);
  }
}

INSTANTIATE_TEST_SUITE_P(Models, ClipPaperModel,
                         ::testing::Values(PaperModel{"knot.off", 6},
                                           PaperModel{"torus1536.off", 2},
                                           PaperModel{"box_with_holes.off", 9},
                                           PaperModel{"box_with_rings.off", 8},
                                           PaperModel{"pinch.off", 2}),
                         [](const auto& info) {
                           std::string s = info.param.file;
                           return s.substr(0, s.find('.'));
                         });

TEST(Clip, PinchedVertexIsDuplicated) {
  // Two towers touching at (0, 0, 0), cut at their base: the above half is two solids sharing
  // one point; the vertex is duplicated (one per fan) so both halves are 2-manifolds.
  const PolygonMesh m = read_mesh(test::source_dir() / "models/pinch.off");
  const Plane p{{0, 0, 1}, 0};
  const ClipResult r = clip(m, p);
  const test::HalfCheck above = test::check_half(r.above.mesh, p, -1);
  EXPECT_TRUE(above.report.closed && above.report.manifold);
  EXPECT_EQ(above.pinched, 1);
  EXPECT_EQ(above.report.components, 2);
  EXPECT_FALSE(above.self_intersecting);
  const test::HalfCheck below = test::check_half(r.below.mesh, p, -1);
  EXPECT_TRUE(below.report.closed && below.report.manifold);
  EXPECT_EQ(below.pinched, 0);
  EXPECT_NEAR(above.volume + below.volume, signed_volume(m), 1e-12);
  // A plane through the pinch point but tilted: rings still touch there.
  clip_and_check(m, {{0.3, -0.2, 1}, 0}, "pinch tilted");
}

}  // namespace
}  // namespace cover::brep
