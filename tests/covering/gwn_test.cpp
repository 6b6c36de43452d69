// Open leaves by the generalized winding number (covering/gwn.h): classify() and the fast
// evaluation against an independent brute-force solid-angle sum (long double, every triangle)
// on open libcgal-demo and assimp models, closed meshes with holes punched, and triangle soups.
#include "cover/covering/gwn.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "cover/covering/classify.h"
#include "cover/covering/detail/triangles.h"
#include "cover/io/scene.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/primitives.h"
#include "helpers.h"

namespace cover {
namespace {

/// Σ solid angles / 4π over every covering triangle of leaf 0 (Van Oosterom–Strackee, written
/// out here in plain doubles): the reference the fast path is compared with.
double brute_winding(const detail::LeafTriangles& lt, const Vec3& q) {
  using L = double;
  L sum = 0;
  for (const detail::CoverTri& t : lt.tris) {
    const L ax = t.a.x - q.x, ay = t.a.y - q.y, az = t.a.z - q.z;
    const L bx = t.b.x - q.x, by = t.b.y - q.y, bz = t.b.z - q.z;
    const L cx = t.c.x - q.x, cy = t.c.y - q.y, cz = t.c.z - q.z;
    const L la = std::sqrt(ax * ax + ay * ay + az * az),
            lb = std::sqrt(bx * bx + by * by + bz * bz),
            lc = std::sqrt(cx * cx + cy * cy + cz * cz);
    const L det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    const L den = la * lb * lc + (ax * bx + ay * by + az * bz) * lc +
                  (ax * cx + ay * cy + az * cz) * lb + (bx * cx + by * cy + bz * cz) * la;
    sum += 2 * std::atan2(det, den);
  }
  return sum / (4 * std::acos(L(-1)));
}

struct Report {
  int checked = 0, disagreements = 0, value_misses = 0;
};

/// 3000 random points in the leaf's box grown by 10%: classify() (BVH + far field + exact
/// re-decision) against the brute-force sum wherever ||w| − 1/2| > 0.05.
Report check_solid(const Solid& s, int points = 3000, uint64_t seed = 1) {
  EXPECT_EQ(s.leaves.size(), 1u);
  EXPECT_TRUE(s.leaves[0].open());
  const detail::LeafTriangles lt = detail::covering_triangles(s);
  const GwnForest forest = build_gwn(s);
  const Bbox b = s.bbox();
  std::mt19937_64 rng(seed);
  std::vector<Vec3> pts(points);
  for (Vec3& p : pts)
    for (int a = 0; a < 3; ++a) {
      const double pad = 0.1 * (b.max[a] - b.min[a]) + 1e-3;
      std::uniform_real_distribution<double> u(b.min[a] - pad, b.max[a] + pad);
      (a == 0 ? p.x : a == 1 ? p.y : p.z) = u(rng);
    }
  const std::vector<PointClass> c = classify(s, pts);
  Report r;
  for (size_t i = 0; i < pts.size(); ++i) {
    const double w = brute_winding(lt, pts[i]);
    const GwnValue v = generalized_winding(forest.trees[0], pts[i], GwnOptions{}.beta);
    if (std::abs(v.w - w) > v.error + 1e-9) ++r.value_misses;
    if (std::abs(std::abs(w) - 0.5) <= 0.05) continue;
    ++r.checked;
    const bool inside = std::abs(w) > 0.5;
    if (c[i] == PointClass::kFace || c[i] == PointClass::kEdge || c[i] == PointClass::kVertex)
      continue;  // on the surface: not a winding-number question
    if ((c[i] == PointClass::kInside) != inside) ++r.disagreements;
  }
  return r;
}

Solid open_leaf(PolygonMesh m, const std::string& name) {
  std::vector<std::string> warnings;
  return prepare_leaf(std::move(m), name, name, LoadOptions{}, warnings);
}

TEST(Gwn, TriangleSoups) {
  for (uint64_t seed : {1u, 2u, 3u}) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    PolygonMesh m;
    for (int t = 0; t < 300; ++t) {
      const Vec3 c{u(rng), u(rng), u(rng)};
      for (int k = 0; k < 3; ++k) m.vertices.push_back(c + 0.3 * Vec3{u(rng), u(rng), u(rng)});
      m.add_face({3u * t, 3u * t + 1, 3u * t + 2});
    }
    const Report r = check_solid(open_leaf(std::move(m), "soup"), 3000, seed);
    EXPECT_GT(r.checked, 300) << seed;
    EXPECT_EQ(r.disagreements, 0) << seed;
    EXPECT_EQ(r.value_misses, 0) << seed;
  }
}

TEST(Gwn, ClosedMeshesWithHolesPunched) {
  for (const char* name : {"sphere", "elephant"}) {
    PolygonMesh m = std::string(name) == "sphere"
                        ? make_sphere({0, 0, 0}, 1, 48)
                        : leaf_mesh(load_input(test::cgal_mesh("elephant.off")).solid, 0);
    // Drop every 7th face: many small holes, each a membrane where |w| passes 1/2.
    PolygonMesh holed;
    holed.vertices = m.vertices;
    for (size_t f = 0; f < m.face_count(); ++f)
      if (f % 7 != 3) holed.add_face(m.face(f));
    const Report r = check_solid(open_leaf(std::move(holed), name));
    EXPECT_GT(r.checked, 1500) << name;
    EXPECT_EQ(r.disagreements, 0) << name;
    EXPECT_EQ(r.value_misses, 0) << name;
  }
}

TEST(Gwn, GridCellsSettledByConeBound) {
  // A sphere with every 7th face dropped, and a CSG of it with a closed box.
  const PolygonMesh m = make_sphere({0, 0, 0}, 1, 32);
  PolygonMesh holed;
  holed.vertices = m.vertices;
  std::vector<Vec3> hole_centres;
  for (size_t f = 0; f < m.face_count(); ++f) {
    if (f % 7 != 3) {
      holed.add_face(m.face(f));
      continue;
    }
    Vec3 c{0, 0, 0};
    for (uint32_t v : m.face(f)) c = c + m.vertices[v];
    hole_centres.push_back((1.0 / static_cast<double>(m.face(f).size())) * c);
  }
  const Solid s = open_leaf(std::move(holed), "holed sphere");
  const GwnForest forest = build_gwn(s);
  const GwnTree& cone = forest.closures[0].cone;
  ASSERT_FALSE(cone.tris.empty());
  // 1. winding_below against the direct sum of the cones at points of the boxes it settles
  //    (boxes near the holes, limits down to 0.002: a bound 5× too small fails here).
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.3, 1.3), size(0.001, 0.1), f01(0, 1);
  std::normal_distribution<double> off(0, 0.08), far(0, 0.25);
  const double limits[] = {0.002, 0.01, 0.05, 0.2, 0.4};
  int settled = 0, unsettled = 0;
  for (int b = 0; b < 1500; ++b) {
    Bbox box;
    std::normal_distribution<double>& o = b % 2 ? off : far;
    const Vec3 c = hole_centres[b % hole_centres.size()] + Vec3{o(rng), o(rng), o(rng)};
    const double h = size(rng), limit = limits[b % 5];
    box.add(c - Vec3{h, h, h});
    box.add(c + Vec3{h, h, h});
    if (!winding_below(cone, box, limit)) {
      ++unsettled;
      continue;
    }
    ++settled;
    for (int k = 0; k < 8; ++k) {
      const Vec3 q = box.min + Vec3{f01(rng) * 2 * h, f01(rng) * 2 * h, f01(rng) * 2 * h};
      EXPECT_LT(std::abs(generalized_winding_direct(cone, q).w), limit) << b;
    }
  }
  EXPECT_GT(settled, 60) << unsettled;
  EXPECT_GT(unsettled, 100);
  // 2. classify with the grid (cells settled by the bound) = the per-point path, on uniform
  //    points and on points near the holes.
  std::vector<Vec3> pts;
  for (int i = 0; i < 30000; ++i) pts.push_back({u(rng), u(rng), u(rng)});
  std::normal_distribution<double> near(0, 0.05);
  for (int i = 0; i < 30000; ++i)
    pts.push_back(hole_centres[i % hole_centres.size()] + Vec3{near(rng), near(rng), near(rng)});
  for (int variant = 0; variant < 2; ++variant) {
    const Solid solid =
        variant == 0 ? s : subtract({s, make_leaf(make_box({0, 0, 0}, {1.2, 0.5, 0.5}), "box")});
    ClassifyOptions with_grid, per_point;
    with_grid.grid_min_points = 0;
    per_point.grid_min_points = SIZE_MAX;
    const std::vector<PointClass> a = classify(solid, pts, with_grid);
    const std::vector<PointClass> b = classify(solid, pts, per_point);
    int differ = 0, inside = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      differ += a[i] != b[i];
      inside += b[i] == PointClass::kInside;
    }
    EXPECT_EQ(differ, 0) << variant;
    EXPECT_GT(inside, 5000) << variant;
  }
}

class OpenModels : public ::testing::TestWithParam<std::string> {};

TEST_P(OpenModels, ClassifyAgreesWithBruteForceSum) {
  const std::filesystem::path path = GetParam();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not installed";
  const Solid s = load_input(path).solid;
  const Report r = check_solid(s);
  EXPECT_GT(r.checked, 100) << path;
  EXPECT_EQ(r.disagreements, 0) << path;
  EXPECT_EQ(r.value_misses, 0) << path;
}

std::vector<std::string> open_models() {
  std::vector<std::string> out;
  for (const char* m : {"elephant-with-holes.off", "mushroom.off", "cube-ouvert.off", "head.off",
                        "nefertiti.off", "mesh_with_border.off", "patch-01.off"})
    out.push_back(test::cgal_mesh(m).string());
  const std::string a = "/usr/share/assimp/models/";
  for (const char* m :
       {"OBJ/WusonOBJ.obj", "OBJ/concave_polygon.obj", "OBJ/multiple_spaces.obj", "OBJ/regr01.obj",
        "OBJ/space_in_material_name.obj", "OBJ/spider.obj", "OFF/Wuson.off", "PLY/float-color.ply",
        "STL/Spider_ascii.stl", "STL/Spider_binary.stl", "STL/Wuson.stl", "STL/sphereWithHole.stl",
        "STL/triangle.stl", "STL/triangle_with_empty_solid.stl",
        "STL/triangle_with_two_solids.stl"})
    out.push_back(a + m);
  return out;
}

INSTANTIATE_TEST_SUITE_P(Real, OpenModels, ::testing::ValuesIn(open_models()),
                         [](const auto& info) {
                           std::string n = std::filesystem::path(info.param).filename().string();
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

TEST(Gwn, RepairOnLoad) {
  // Wuson.off: seam vertices duplicated; welded it has the STL version's 412 boundary edges.
  const std::filesystem::path wuson = "/usr/share/assimp/models/OFF/Wuson.off";
  const std::filesystem::path cube = "/usr/share/assimp/models/PLY/cube_uv.ply";
  if (!std::filesystem::exists(wuson) || !std::filesystem::exists(cube))
    GTEST_SKIP() << "assimp-testmodels not installed";
  const LoadedInput w = load_input(wuson);
  EXPECT_EQ(w.solid.leaves[0].boundary_edges, 412);
  // cube_uv.ply is closed once welded: the exact path, volume of its box.
  const LoadedInput c = load_input(cube);
  EXPECT_FALSE(c.solid.leaves[0].open());
  bool welded = false;
  for (const std::string& s : c.warnings) welded |= s.find("duplicate vertices welded") != s.npos;
  EXPECT_TRUE(welded);
  EXPECT_NEAR(signed_volume(leaf_mesh(c.solid, 0)), 8.0, 1e-5);  // a 2-cube (one vertex at −1−1e-6)
  LoadOptions closed_only;
  closed_only.require_closed = true;
  EXPECT_THROW(load_input(wuson, closed_only), InputError);
}

}  // namespace
}  // namespace cover
