// Certified polygonization (polygonize/polygonize.h) and mixed evaluation (Model::evaluate of
// trees with field, warp and open-mesh leaves), against independent paths: the exact surface of
// single primitives (a point field's sphere, a box's faces), the exact validity check of the
// output (closed, oriented, 2-manifold, no self-intersection), the thread count, and classify()
// of the non-evaluated tree at random points whose surroundings (a box of half-width h·√3 around
// the point) the sound three-valued box test decides: there the polygonized mesh must agree
// (every cell corner within h·√3 of such a point has the point's class).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <tuple>

#include "cover/covering/box_states.h"
#include "cover/io/scene.h"
#include "cover/mesh/validate.h"
#include "cover/model/model.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"
#include "helpers.h"

namespace cover {
namespace {

// Random points per scene and the mixed evaluations' grid (the checked build, about 10 times
// slower: a fifth of the points, half the cells per side).
#ifdef COVER_SANITIZED
constexpr size_t kPoints = 4000;
constexpr int kResolution = 24;  // the mixed evaluations' grid
#else
constexpr size_t kPoints = 20000;
constexpr int kResolution = 48;
#endif

Model scene(const std::string& text) {
  LoadedInput in = parse_scene(text, "polygonize.json");
  return Model(std::move(in.solid), std::move(in.warnings));
}

const char* kBall = R"({"field": {"skeleton": {"point": [0.1, -0.2, 0.3]}, "radius": 0.5,
                                  "influence": 1}})";
const char* kTwoPoints = R"({"blend": [
  {"field": {"skeleton": {"point": [-0.35, 0, 0]}, "radius": 0.5, "influence": 1}},
  {"field": {"skeleton": {"point": [0.35, 0, 0]}, "radius": 0.5, "influence": 1}}]})";

void expect_valid(const PolygonMesh& mesh, const std::string& what) {
  ASSERT_GT(mesh.face_count(), 0u) << what;
  const MeshReport r = validate_mesh(mesh);
  EXPECT_TRUE(r.closed) << what;
  EXPECT_TRUE(r.manifold) << what;
  EXPECT_TRUE(r.oriented) << what;
  EXPECT_TRUE(r.outward) << what;
  EXPECT_EQ(r.degenerate_faces, 0) << what;
  ASSERT_TRUE(r.self_intersecting.has_value());
  EXPECT_FALSE(*r.self_intersecting) << what;
  EXPECT_FALSE(r.self_touching.value_or(false)) << what;
}

TEST(Polygonize, PointFieldGivesItsSphereWithinTheTolerance) {
  const Model m = scene(kBall);
  const Vec3 c{0.1, -0.2, 0.3};
  for (int resolution : {8, 32, 100}) {
    const PolygonizeResult r = m.polygonize({.resolution = resolution});
    const std::string what = "resolution " + std::to_string(resolution);
    expect_valid(r.mesh, what);
    const MeshReport rep = validate_mesh(r.mesh, {.check_self_intersection = false});
    EXPECT_EQ(rep.genus, 0) << what;
    EXPECT_EQ(rep.components, 1) << what;
    EXPECT_GT(r.tolerance, 0);
    EXPECT_LE(r.tolerance, r.cell_size / 1024 * 1.0001) << what;
    EXPECT_EQ(r.uncertain, 0u);
    EXPECT_EQ(r.clipped, 0u);
    // The surface f = T of one point is the sphere |p − c| = r_T exactly.
    double worst = 0;
    for (const Vec3& v : r.mesh.vertices) {
      const Vec3 d = v - c;
      worst = std::max(worst, std::abs(std::sqrt(dot(d, d)) - 0.5));
    }
    EXPECT_LE(worst, r.tolerance * (1 + 1e-9)) << what;
    // Every triangle lies in a tetrahedron the surface crosses: within h·√3 of the sphere.
    for (size_t f = 0; f < r.mesh.face_count(); ++f) {
      const auto t = r.mesh.face(f);
      const Vec3 g =
          (1.0 / 3) * (r.mesh.vertices[t[0]] + r.mesh.vertices[t[1]] + r.mesh.vertices[t[2]]) - c;
      ASSERT_LE(std::abs(std::sqrt(dot(g, g)) - 0.5), r.cell_size * std::sqrt(3.0)) << what;
    }
    const double exact = 4.0 / 3 * M_PI * 0.125;
    EXPECT_NEAR(signed_volume(r.mesh), exact, exact * 12 * r.cell_size) << what;
  }
}

TEST(Polygonize, ToleranceAndCellSizeAreHonoured) {
  const Model m = scene(kBall);
  const PolygonizeResult r = m.polygonize({.cell_size = 0.05, .tolerance = 1e-9});
  EXPECT_EQ(r.cell_size, 0.03125);  // the largest power of two ≤ 0.05
  EXPECT_LE(r.tolerance, 1e-9);
  expect_valid(r.mesh, "cell 0.05");
  EXPECT_THROW(m.polygonize({.resolution = 1}), InputError);
  EXPECT_THROW(m.polygonize({.tolerance = -1}), InputError);
  EXPECT_THROW(m.polygonize({.resolution = 4096, .max_memory_bytes = 1 << 20}), InputError);
  EXPECT_THROW((~m).polygonize(), NotComputable);
  EXPECT_EQ(Model().polygonize().mesh.face_count(), 0u);
}

TEST(Polygonize, SameMeshForAnyThreadCount) {
  const Model m = scene(kTwoPoints);
  PolygonizeResult one, two;
  {
    ThreadLimit limit(1);
    one = m.polygonize({.resolution = 48});
  }
  {
    ThreadLimit limit(2);
    two = m.polygonize({.resolution = 48});
  }
  EXPECT_EQ(one.mesh.vertices, two.mesh.vertices);
  EXPECT_EQ(one.mesh.face_vertices, two.mesh.face_vertices);
  EXPECT_EQ(one.tolerance, two.tolerance);
}

TEST(Polygonize, MeshLeafVerticesLieOnItsFaces) {
  const Model m = box({0.1, 0.2, 0.3}, {0.9, 0.7, 1.3}) - sphere({0.9, 0.7, 1.3}, 0.3, 12);
  const PolygonizeResult r = m.polygonize({.resolution = 40});
  expect_valid(r.mesh, "box - sphere");
  // Every vertex is within the tolerance of a boundary point: check by classify() of the two
  // points the tolerance away along each axis direction giving a class change.
  std::vector<Vec3> probes;
  for (const Vec3& v : r.mesh.vertices)
    for (int a = 0; a < 3; ++a)
      for (double s : {-1.0, 1.0}) {
        Vec3 step{0, 0, 0};
        (a == 0 ? step.x : a == 1 ? step.y : step.z) = s * r.tolerance * 2;
        probes.push_back(v + step);
      }
  probes.insert(probes.end(), r.mesh.vertices.begin(), r.mesh.vertices.end());
  const std::vector<PointClass> cls = m.classify(probes);
  size_t changed = 0;
  for (size_t v = 0; v < r.mesh.vertices.size(); ++v) {
    bool in = false, out = false;
    for (size_t k = 0; k < 6; ++k) (cls[6 * v + k] == PointClass::kOutside ? out : in) = true;
    const PointClass self = cls[6 * r.mesh.vertices.size() + v];
    changed += (in && out) || (self != PointClass::kInside && self != PointClass::kOutside);
  }
  // Every vertex of a box face or a sphere facet is within 2·tolerance of a class change along
  // an axis except where the facet is oblique: most are, all are near.
  EXPECT_GT(changed, r.mesh.vertices.size() * 9 / 10);
}

/// Mixed evaluation of `m`: valid, and equal to classify() of the non-evaluated tree at 20,000
/// seeded random points of the box whose surroundings the box test decides.
/// `decided` says how a point's class is known: by the sound box test (fields, warps and meshes),
/// or, for open leaves (whose box test never decides), by classify() of the non-evaluated tree
/// agreeing at the point and at the 26 points of the band's box around it.
void expect_mixed_matches(const Model& m, const std::string& what, bool certified = true) {
  const EvaluateResult e = m.evaluate({.mesh_resolution = kResolution});
  expect_valid(e.mesh, what);
  ASSERT_GE(e.meshed.size(), 1u) << what;
  double h = 0;
  for (const MeshedLeaf& l : e.meshed) {
    h = std::max(h, l.cell_size);
    EXPECT_LE(l.tolerance, l.cell_size / 1024 * 1.0001) << what;
  }
  EXPECT_GT(e.tolerance, 0) << what;
  const Model evaluated = mesh(
      e.mesh.vertices,
      [&] {
        std::vector<std::array<uint32_t, 3>> t(e.mesh.face_count());
        for (size_t f = 0; f < t.size(); ++f)
          t[f] = {e.mesh.face(f)[0], e.mesh.face(f)[1], e.mesh.face(f)[2]};
        return t;
      }(),
      "evaluated");
  const Bbox b = *m.bounds();
  std::mt19937_64 rng(20261207);
  std::uniform_real_distribution<double> u(0, 1);
  const double band = h * std::sqrt(3.0) * (1 + 1e-6);
  std::vector<Vec3> random(kPoints);
  for (Vec3& p : random)
    p = {b.min.x + (b.max.x - b.min.x) * u(rng), b.min.y + (b.max.y - b.min.y) * u(rng),
         b.min.z + (b.max.z - b.min.z) * u(rng)};
  std::vector<Vec3> points;
  std::vector<uint8_t> expected;
  if (certified) {
    for (const Vec3& p : random) {
      Bbox around;
      around.add(p - Vec3{band, band, band});
      around.add(p + Vec3{band, band, band});
      const uint8_t s = box_state(m.prepared(), around);
      if (s == kBoxUndecided) continue;
      points.push_back(p);
      expected.push_back(s);
    }
  } else {
    std::vector<Vec3> probe;
    for (const Vec3& p : random)
      for (int k = 0; k < 27; ++k)
        probe.push_back(p + band * Vec3{k % 3 - 1.0, k / 3 % 3 - 1.0, k / 9 - 1.0});
    const std::vector<PointClass> c = m.classify(probe);
    for (size_t i = 0; i < random.size(); ++i) {
      const auto first = c.begin() + 27 * i, last = first + 27;
      if (std::any_of(first, last, [&](PointClass x) { return x != *first; })) continue;
      if (*first != PointClass::kInside && *first != PointClass::kOutside) continue;
      points.push_back(random[i]);
      expected.push_back(*first == PointClass::kInside ? kBoxInside : kBoxOutside);
    }
  }
  EXPECT_GT(points.size(), kPoints / 4) << what;
  const std::vector<PointClass> got = evaluated.classify(points);
  size_t disagree = 0;
  for (size_t i = 0; i < points.size(); ++i)
    disagree += (got[i] == PointClass::kInside) != (expected[i] == kBoxInside);
  EXPECT_EQ(disagree, 0u) << what << ": " << points.size() << " points";
}

TEST(MixedEvaluation, FieldsAndMeshesAgreeWithClassifyOffTheBand) {
  expect_mixed_matches(scene(kTwoPoints), "two-point blend");
  expect_mixed_matches(scene(std::string(R"({"difference": [)") + kTwoPoints +
                             R"(, {"box": {"min": [-0.2, -1, -1], "max": [0.2, 1, 1]}}]})"),
                       "blend minus a slab");
  expect_mixed_matches(scene(std::string(R"({"union": [)") + kBall +
                             R"(, {"box": {"min": [0, -0.3, 0.2], "max": [1, 0.3, 0.4]}}]})"),
                       "ball and box");
  expect_mixed_matches(scene(std::string(R"({"intersection": [{"complement": )") + kBall +
                             R"(}, {"box": {"min": [-1, -1, -1], "max": [1, 1, 1]}}]})"),
                       "box minus a ball by complement");
}

TEST(MixedEvaluation, MeshSkeletonsStayExactOutsideTheOverlaps) {
  const std::string torus = std::string(COVER_SOURCE_DIR) + "/models/torus.off";
  const std::string skeleton =
      R"({"field": {"skeleton": {"mesh": ")" + torus + R"("}, "radius": 0.1, "influence": 0.3}})";
  // Alone: the mesh itself, exactly (no polygonization: Q is empty).
  const Model mesh = load(torus);
  const EvaluateResult alone = scene(skeleton).evaluate({.mesh_resolution = kResolution});
  ASSERT_EQ(alone.meshed.size(), 1u);
  EXPECT_EQ(alone.tolerance, 0);
  std::vector<Vec3> a = alone.mesh.vertices, b = mesh.evaluate().mesh.vertices;
  auto order = [](const Vec3& p, const Vec3& q) {
    return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
  };
  std::sort(a.begin(), a.end(), order);
  std::sort(b.begin(), b.end(), order);
  EXPECT_EQ(a, b);
  // Blended with a point and cut by a box: valid, agrees with classify off the band, and every
  // torus vertex outside the point's support box and the cut is an output vertex, exactly.
  const Model blend = scene(R"({"difference": [{"blend": [)" + skeleton +
                            R"(, {"field": {"skeleton": {"point": [1.2, 0, 0.3]}, "radius": 0.1,
                                  "influence": 0.3}}]},
                              {"box": {"min": [-3, -3, -1], "max": [0, 0, 1]}}]})");
  expect_mixed_matches(blend, "torus skeleton blend minus a box");
  const EvaluateResult e = blend.evaluate({.mesh_resolution = kResolution});
  const std::set<std::tuple<double, double, double>> out = [&] {
    std::set<std::tuple<double, double, double>> s;
    for (const Vec3& p : e.mesh.vertices) s.insert({p.x, p.y, p.z});
    return s;
  }();
  size_t kept = 0;
  for (const Vec3& p : mesh.solid().vertices) {
    const bool near_point = std::abs(p.x - 1.2) <= 0.31 && std::abs(p.y) <= 0.31;
    const bool cut = p.x <= 0 && p.y <= 0;
    if (near_point || cut) continue;
    EXPECT_TRUE(out.count({p.x, p.y, p.z})) << p.x << " " << p.y << " " << p.z;
    ++kept;
  }
  EXPECT_GT(kept, mesh.solid().vertices.size() / 2);
}

TEST(MixedEvaluation, WarpsAndModelsFromFiles) {
  const Model warped = load(std::filesystem::path(COVER_SOURCE_DIR) / "models/warped_part.json");
  expect_mixed_matches(warped, "warped_part.json");
  const Model snake = load(std::filesystem::path(COVER_SOURCE_DIR) / "models/snake.json");
  const EvaluateResult e = snake.evaluate({.mesh_resolution = kResolution});
  expect_valid(e.mesh, "snake.json");
  EXPECT_EQ(e.meshed.size(), 2u);  // the blend and the circle field; the slab stays exact
}

TEST(MixedEvaluation, OpenMeshesEvaluate) {
  const Model open = load(test::cgal_mesh("cube-ouvert.off"));
  ASSERT_TRUE(open.solid().has_open_leaf());
  const Bbox b = *open.bounds();
  const Vec3 mid = 0.5 * (b.min + b.max);
  expect_mixed_matches(open - box(mid, b.max + Vec3{1, 1, 1}), "open cube minus a box", false);
  const Model elephant = load(test::cgal_mesh("elephant-with-holes.off"));
  const EvaluateResult e = elephant.evaluate({.mesh_resolution = 20});
  expect_valid(e.mesh, "elephant-with-holes.off");
}

TEST(MixedEvaluation, OpenLeafBoxStatesAreSound) {
  // An open leaf's box state away from its triangles (its closure's winding number where the
  // cones subtend |w_C| < 0.4): every point of a settled box has that class.
  const Model open = load(test::cgal_mesh("cube-ouvert.off"));
  const Model m = open | scene(kBall);
  const Bbox b = *m.bounds();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  size_t settled[2] = {0, 0};
  std::vector<Vec3> probes;
  std::vector<uint8_t> state;
  for (int i = 0; i < 3000; ++i) {
    const double half = 0.3 * u(rng) * u(rng);
    const Vec3 c{b.min.x + (b.max.x - b.min.x) * u(rng), b.min.y + (b.max.y - b.min.y) * u(rng),
                 b.min.z + (b.max.z - b.min.z) * u(rng)};
    Bbox box;
    box.add(c - Vec3{half, half, half});
    box.add(c + Vec3{half, half, half});
    const uint8_t s = box_state(m.prepared(), box);
    if (s == kBoxUndecided) continue;
    ++settled[s];
    for (int k = 0; k < 27; ++k) {
      probes.push_back(c + half * Vec3{k % 3 - 1.0, k / 3 % 3 - 1.0, k / 9 - 1.0});
      state.push_back(s);
    }
  }
  EXPECT_GT(settled[kBoxInside], 20u);
  EXPECT_GT(settled[kBoxOutside], 100u);
  const std::vector<PointClass> cls = m.classify(probes);
  size_t wrong = 0;
  for (size_t i = 0; i < probes.size(); ++i)
    wrong += (cls[i] == PointClass::kOutside) != (state[i] == kBoxOutside);
  EXPECT_EQ(wrong, 0u);
  // The bracket and the octree take the open leaf beside the field.
  const VolumeResult v = m.volume();
  EXPECT_EQ(v.method, "bracket");
  EXPECT_GT(v.volume - v.error_bound, 0);
  EXPECT_GT(m.octree({.depth = 3}).nodes.size(), 1u);
}

TEST(MixedEvaluation, ClipCellsAndDecomposeTakeEveryLeaf) {
  const Model m = scene(std::string(R"({"difference": [)") + kTwoPoints +
                        R"(, {"box": {"min": [-0.2, -1, -1], "max": [0.2, 1, 1]}}]})");
  const brep::ClipResult c = m.clip({{0, 0, 1}, 0.1});
  expect_valid(c.above.mesh, "clip above");
  const double whole = m.evaluate().volume;
  EXPECT_NEAR(signed_volume(c.above.mesh) + signed_volume(c.below.mesh), whole, 1e-9 * whole);
  const CellsEvaluation cells = m.evaluate_cells(2);
  EXPECT_NEAR(signed_volume(cells.cells.glued), whole, 1e-9 * whole);
  // Model::decompose cuts the default evaluation (about 160,000 curved triangles: minutes); the
  // same route on a coarse one.
  const EvaluateResult coarse = m.evaluate({.mesh_resolution = 6});
  const brep::DecomposeResult d = brep::decompose(coarse.mesh);
  double sum = 0;
  for (const auto& piece : d.pieces) sum += signed_volume(piece);
  EXPECT_NEAR(sum, coarse.volume, 1e-9 * coarse.volume);
}

TEST(MixedEvaluation, ClipAndCellsTakeMeshSkeletons) {
  const std::string torus = std::string(COVER_SOURCE_DIR) + "/models/torus.off";
  const Model m = scene(R"({"difference": [{"blend": [{"field": {"skeleton": {"mesh": ")" + torus +
                        R"("}, "radius": 0.1, "influence": 0.3}}, {"field": {"skeleton":
                        {"point": [1.2, 0, 0.3]}, "radius": 0.1, "influence": 0.3}}]},
                        {"box": {"min": [-3, -3, -1], "max": [0.05, 0.05, 1]}}]})");
  const double whole = m.evaluate().volume;
  const brep::ClipResult c = m.clip({{0, 0, 1}, 0.1});
  expect_valid(c.above.mesh, "clip above");
  expect_valid(c.below.mesh, "clip below");
  EXPECT_NEAR(signed_volume(c.above.mesh) + signed_volume(c.below.mesh), whole, 1e-9 * whole);
  const CellsEvaluation cells = m.evaluate_cells(3);
  EXPECT_NEAR(signed_volume(cells.cells.glued), whole, 1e-9 * whole);
}

TEST(Distance, BallFieldAndBox) {
  // A point field's surface is the sphere |p − c| = 0.5: the signed distance through the mixed
  // evaluation's mesh is within h·√3 of |p − c| − 0.5 (the mesh lies within h·√3 of the
  // surface, and a sphere's mesh at this grid misses nothing).
  const Model ball = scene(kBall);
  const Vec3 c{0.1, -0.2, 0.3};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> q(3000);
  for (Vec3& p : q) p = c + Vec3{u(rng), u(rng), u(rng)};
  const Model::Distances d = ball.distance(q);
  ASSERT_EQ(d.meshed.size(), 1u);
  const double h = d.meshed[0].cell_size;
  for (size_t i = 0; i < q.size(); ++i) {
    const Vec3 v = q[i] - c;
    const double exact = std::sqrt(dot(v, v)) - 0.5;
    ASSERT_NEAR(d.distance[i], exact, h * std::sqrt(3.0)) << i;
    if (std::abs(exact) > 1e-9) ASSERT_EQ(d.distance[i] < 0, exact < 0) << i;
  }
  // A box: exactly its signed distance function (up to rounding), 0 exactly on a face.
  const Model b = box({0, 0, 0}, {1, 2, 3});
  const Model::Distances e = b.distance(std::vector<Vec3>{{0.5, 1, 3}, {2, 1, 1}, {0.5, 0.5, 0.5}});
  EXPECT_EQ(e.distance[0], 0);
  EXPECT_DOUBLE_EQ(e.distance[1], 1);
  EXPECT_DOUBLE_EQ(e.distance[2], -0.5);
  EXPECT_TRUE(e.meshed.empty());
  EXPECT_THROW((~b).distance(q), NotComputable);
}

TEST(MixedEvaluation, ClosedMeshTreesAreUnchanged) {
  const Model m = box({0, 0, 0}, {1, 1, 1}) - sphere({1, 1, 1}, 0.5, 16);
  const EvaluateResult a = m.evaluate(), b = evaluate(m.solid());
  EXPECT_TRUE(a.meshed.empty());
  EXPECT_EQ(a.tolerance, 0);
  EXPECT_EQ(a.mesh.vertices, b.mesh.vertices);
  EXPECT_EQ(a.mesh.face_vertices, b.mesh.face_vertices);
}

}  // namespace
}  // namespace cover
