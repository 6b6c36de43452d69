// cover::Model (model/model.h) against the free-function kernels it wraps and against analytic
// answers: operators build the same solid as solid/solid.h's concatenation; every query equals
// the free function on the same solid; the BVH is built once and shared by copies and threads;
// errors are the documented types with one-line messages.
#include "cover/model/model.h"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <thread>

#include "cover/covering/bounds.h"
#include "cover/covering/classify.h"
#include "cover/covering/prepared.h"
#include "cover/covering/ray.h"
#include "cover/model/info.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "helpers.h"

namespace cover {
namespace {

std::vector<Vec3> random_points(size_t n, double lo, double hi, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Vec3> points(n);
  for (Vec3& p : points) p = {u(rng), u(rng), u(rng)};
  return points;
}

/// (box − sphere) ∪ bar: the consumer example's part.
Model part() {
  return (box({0, 0, 0}, {2, 2, 2}) - sphere({2, 2, 2}, 1, 32)) | box({1.5, 0.5, 0.5}, {3.5, 1, 1});
}

TEST(Model, OperatorsBuildTheConcatenatedSolid) {
  const Model a = box({0, 0, 0}, {2, 2, 2}), b = sphere({2, 2, 2}, 1, 16);
  const Solid sa = make_leaf(make_box({0, 0, 0}, {2, 2, 2}), "box");
  const Solid sb = make_leaf(make_sphere({2, 2, 2}, 1, 16), "sphere");
  const std::vector<Vec3> points = random_points(5000, -0.5, 3.5, 1);
  const std::pair<Model, Solid> cases[] = {{a | b, unite({sa, sb})},
                                           {a & b, intersect({sa, sb})},
                                           {a - b, subtract({sa, sb})},
                                           {~(~a), complement(complement(sa))}};
  for (const auto& [model, solid] : cases) {
    EXPECT_EQ(model.leaf_count(), solid.leaves.size());
    EXPECT_EQ(model.classify(points), classify(solid, points));
  }
  // The operands are unchanged (value semantics).
  EXPECT_EQ(a.leaf_count(), 1u);
  EXPECT_EQ(a.solid().tree.nodes.size(), 1u);
}

// The lazy tree against the eager concatenation: 300 seeded random expressions (unions,
// intersections, differences, complements over boxes and spheres, chains included) classify a
// point set exactly as the solid built operator by operator with solid/solid.h, and as it does
// on its leaves' memberships (brute force).
TEST(Model, LazyTreesEqualTheEagerSolidOnRandomExpressions) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(0, 3);
  std::uniform_int_distribution<int> pick(0, 9);
  const std::vector<Vec3> points = random_points(400, -0.5, 4, 7);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<std::pair<Model, Solid>> pool;
    auto leaf = [&] {
      const Vec3 c{u(rng), u(rng), u(rng)};
      if (pick(rng) < 5) {
        const Vec3 lo = c - Vec3{0.6, 0.5, 0.4}, hi = c + Vec3{0.5, 0.6, 0.7};
        return std::pair{box(lo, hi), make_leaf(make_box(lo, hi), "box")};
      }
      return std::pair{sphere(c, 0.8, 8), make_leaf(make_sphere(c, 0.8, 8), "sphere")};
    };
    for (int i = 0; i < 4; ++i) pool.push_back(leaf());
    const int steps = 2 + trial % 12;
    for (int step = 0; step < steps; ++step) {
      // Mostly chains onto the last result (the loop a CAD script writes), sometimes any two.
      const size_t a = pick(rng) < 7 ? pool.size() - 1 : rng() % pool.size();
      const auto [bm, bs] = pick(rng) < 6 ? leaf() : pool[rng() % pool.size()];
      const auto& [am, as] = pool[a];
      switch (pick(rng) % 5) {
        case 0:
        case 1:
          pool.emplace_back(am | bm, unite({as, bs}));
          break;
        case 2:
          pool.emplace_back(am & bm, intersect({as, bs}));
          break;
        case 3:
          pool.emplace_back(am - bm, subtract({as, bs}));
          break;
        default:
          pool.emplace_back(~am, complement(as));
          break;
      }
    }
    const auto& [model, solid] = pool.back();
    ASSERT_EQ(model.leaf_count(), solid.leaves.size()) << "trial " << trial;
    const std::vector<PointClass> got = model.classify(points);
    ASSERT_EQ(got, classify(solid, points)) << "trial " << trial;
    ASSERT_EQ(got, classify_brute_force(model.solid(), points)) << "trial " << trial;
  }
}

// A chain of one operator is one n-ary node over its operands, built once; intermediate Models
// of the chain stay usable and answer for their own prefix.
TEST(Model, ChainedOperatorsBuildOneNaryNode) {
  std::vector<Model> spheres;
  std::vector<Solid> solids;
  for (int i = 0; i < 200; ++i) {
    const Vec3 c{0.3 * i, 0.1 * (i % 7), 0};
    spheres.push_back(sphere(c, 0.25, 8));
    solids.push_back(make_leaf(make_sphere(c, 0.25, 8), "sphere"));
  }
  Model m, half;
  for (int i = 0; i < 200; ++i) {
    m = m | spheres[i];
    if (i == 99) half = m;
  }
  EXPECT_EQ(m.leaf_count(), 200u);
  EXPECT_EQ(m.solid().tree.nodes.size(), 201u);  // one union over 200 leaves
  const std::vector<Vec3> points = random_points(3000, -0.5, 60, 8);
  EXPECT_EQ(m.classify(points), classify(unite(solids), points));
  EXPECT_EQ(half.leaf_count(), 100u);
  EXPECT_EQ(half.classify(points),
            classify(unite(std::vector<Solid>(solids.begin(), solids.begin() + 100)), points));
  EXPECT_EQ(union_all(spheres).classify(points), m.classify(points));
  // Differences chain on their left operand: a − s1 − s2 − ... is one difference node.
  Model d = box({-1, -1, -1}, {61, 1, 1});
  for (const Model& s : spheres) d = d - s;
  EXPECT_EQ(d.solid().tree.nodes.size(), 202u);
  std::vector<Solid> minus{make_leaf(make_box({-1, -1, -1}, {61, 1, 1}), "box")};
  minus.insert(minus.end(), solids.begin(), solids.end());
  EXPECT_EQ(d.classify(points), classify(subtract(minus), points));
  EXPECT_EQ(intersection_all(std::vector<Model>{box({0, 0, 0}, {2, 2, 2}), sphere({2, 2, 2}, 1)})
                .leaf_count(),
            2u);
  EXPECT_TRUE(union_all({}).empty());
  EXPECT_THROW(intersection_all({}), PreconditionError);
}

// Long chains neither recurse when built nor when destroyed (20,000 and 100,000 nodes; one leaf
// shared by every node), and a lazy Model
// queried from several threads at once is built once.
TEST(Model, LongChainsAndConcurrentFirstUse) {
  const Model b = box({0, 0, 0}, {1, 1, 1});
  {
    Model m = b;
    for (int i = 0; i < 100000; ++i) m = (i % 2) ? (m | b) : (m & b);
  }  // destroyed without being built
  Model m = b;
  for (int i = 0; i < 20000; ++i) m = m | b;
  EXPECT_EQ(m.leaf_count(), 20001u);
  const Model lazy = m - sphere({0.5, 0.5, 0.5}, 0.25, 8);
  const std::vector<Vec3> points{{0.5, 0.5, 0.5}, {0.9, 0.9, 0.9}, {2, 2, 2}};
  std::vector<std::vector<PointClass>> got(4);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) threads.emplace_back([&, t] { got[t] = lazy.classify(points); });
  for (std::thread& t : threads) t.join();
  const std::vector<PointClass> expected{PointClass::kOutside, PointClass::kInside,
                                         PointClass::kOutside};
  for (const auto& g : got) EXPECT_EQ(g, expected);
}

TEST(Model, ClassifyEqualsBruteForceOnRandomAndLatticePoints) {
  const Model m = part();
  std::vector<Vec3> points = random_points(20000, -0.5, 4, 2);
  for (int i = 0; i <= 8; ++i)  // the boxes' corners, edges and faces lie on this lattice
    for (int j = 0; j <= 8; ++j)
      for (int k = 0; k <= 8; ++k) points.push_back({i * 0.5, j * 0.25, k * 0.25});
  EXPECT_EQ(m.classify(points), classify_brute_force(m.solid(), points));
  EXPECT_EQ(to_string(m.classify(std::vector<Vec3>{{0.5, 0.5, 0.5}})[0]), "inside");
}

TEST(Model, WindingsAreEachLeafsWindingNumber) {
  const Model m = part();
  const std::vector<Vec3> points = random_points(3000, -0.5, 4, 3);
  const LeafWindings w = m.windings(points);
  ASSERT_EQ(w.leaves, 3u);
  ASSERT_EQ(w.winding.size(), points.size() * 3);
  std::vector<int> one;
  std::vector<uint8_t> on;
  size_t inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    leaf_windings(m.solid(), points[i], one, on);
    for (size_t l = 0; l < 3; ++l) {
      EXPECT_EQ(w.on_surface[i * 3 + l], on[l]) << i;
      if (!on[l]) {
        EXPECT_EQ(w.winding[i * 3 + l], one[l]) << i;
      }
      inside += w.winding[i * 3 + l] != 0;
    }
  }
  EXPECT_GT(inside, 0u);
}

/// Σ solid angles / 4π (Van Oosterom–Strackee) over every triangle of `tris`, in long double,
/// from the vertices themselves: the reference for an open leaf's generalized winding number.
long double solid_angle_sum(const std::vector<std::array<Vec3, 3>>& tris, const Vec3& q) {
  using L = long double;
  L sum = 0;
  for (const auto& t : tris) {
    L A[3], B[3], C[3];
    for (int k = 0; k < 3; ++k)
      A[k] = L(t[0][k]) - q[k], B[k] = L(t[1][k]) - q[k], C[k] = L(t[2][k]) - q[k];
    auto dotl = [](const L* x, const L* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    const L la = std::sqrt(dotl(A, A)), lb = std::sqrt(dotl(B, B)), lc = std::sqrt(dotl(C, C));
    const L det = A[0] * (B[1] * C[2] - B[2] * C[1]) - A[1] * (B[0] * C[2] - B[2] * C[0]) +
                  A[2] * (B[0] * C[1] - B[1] * C[0]);
    const L den = la * lb * lc + dotl(A, B) * lc + dotl(A, C) * lb + dotl(B, C) * la;
    sum += 2 * std::atan2(det, den);
  }
  return sum / (4 * std::acos(L(-1)));
}

/// The unit cube without its top face (z = 1), as triangles; `copies` times over, each copy
/// shifted a little (a surface covering most of the cube twice where one covers it once).
PolygonMesh open_cube(int copies, std::vector<std::array<Vec3, 3>>& tris) {
  const PolygonMesh cube = make_box({0, 0, 0}, {1, 1, 1});
  PolygonMesh m;
  for (int c = 0; c < copies; ++c) {
    const uint32_t base = static_cast<uint32_t>(m.vertices.size());
    for (const Vec3& v : cube.vertices) m.vertices.push_back(v + c * Vec3{0.013, 0.007, -0.011});
    for (size_t f = 0; f < cube.face_count(); ++f) {
      const auto face = cube.face(f);
      bool top = true;
      for (uint32_t v : face) top &= cube.vertices[v].z == 1;
      if (top) continue;
      for (size_t i = 1; i + 1 < face.size(); ++i) {
        const std::array<uint32_t, 3> t{base + face[0], base + face[i], base + face[i + 1]};
        m.add_face(t);
        tris.push_back({m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]});
      }
    }
  }
  return m;
}

TEST(Model, WindingOfAnOpenLeafIsItsRoundedGeneralizedWindingNumber) {
  for (int copies : {1, 2}) {
    std::vector<std::array<Vec3, 3>> tris;
    const Model open = mesh(open_cube(copies, tris), "open cube");
    ASSERT_TRUE(open.solid().leaves[0].open());
    // With a closed box as a second leaf: its column stays the exact crossing count.
    const Model m = open | box({0.25, 0.25, 0.25}, {0.75, 0.75, 2});
    std::vector<Vec3> points;  // 2,500: a 50 × 50 lattice in the plane x = 0.3 + noise
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
    for (int j = 0; j < 50; ++j)
      for (int k = 0; k < 50; ++k)
        points.push_back({0.3 + jitter(rng), -0.5 + 2.0 * (j + 0.5) / 50 + jitter(rng),
                          -0.5 + 2.0 * (k + 0.5) / 50 + jitter(rng)});
    const LeafWindings w = m.windings(points);
    const LeafWindings alone = open.windings(points);
    const std::vector<PointClass> c = open.classify(points);
    std::vector<int> crossing;
    std::vector<uint8_t> on;
    int checked = 0, wrong_value = 0, wrong_membership = 0, above_one = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      ASSERT_FALSE(w.on_surface[2 * i]) << i;
      EXPECT_EQ(w.winding[2 * i], alone.winding[i]) << i;
      // Membership: nonzero exactly where classify() counts the leaf inside.
      if ((w.winding[2 * i] != 0) != (c[i] == PointClass::kInside)) ++wrong_membership;
      // Value: the nearest integer to the brute-force sum, away from half-integers.
      const long double ref = solid_angle_sum(tris, points[i]);
      if (std::abs(ref - std::round(ref)) > 0.49L) continue;
      ++checked;
      if (w.winding[2 * i] != static_cast<int>(std::lround(ref))) ++wrong_value;
      above_one += std::abs(w.winding[2 * i]) > 1;
      // The closed box's column: its exact winding number.
      leaf_windings(m.solid(), points[i], crossing, on);
      if (!on[1]) {
        EXPECT_EQ(w.winding[2 * i + 1], crossing[1]) << i;
      }
    }
    EXPECT_GT(checked, 2000) << copies;
    EXPECT_EQ(wrong_membership, 0) << copies;
    EXPECT_EQ(wrong_value, 0) << copies;
    if (copies == 2) {
      EXPECT_GT(above_one, 100);
    }
  }
}

// The free kernels on a Prepared (and their one-shot forms on a Solid) answer as the facade
// does, open leaves included: the winding-number rule lives in the kernels, not in Model.
TEST(Model, FreeKernelsAnswerAsTheFacadeOnOpenLeaves) {
  std::vector<std::array<Vec3, 3>> tris;
  const Model m = mesh(open_cube(1, tris), "open cube") | box({0.25, 0.25, 0.25}, {0.75, 0.75, 2});
  ASSERT_TRUE(m.solid().has_open_leaf());
  const Prepared prepared(m.solid());
  const std::vector<Vec3> points = random_points(3000, -0.5, 1.5, 17);
  EXPECT_EQ(classify(prepared, points), m.classify(points));
  EXPECT_EQ(classify(m.solid(), points), m.classify(points));
  const LeafWindings free_w = leaf_windings(prepared, points), model_w = m.windings(points);
  EXPECT_EQ(free_w.winding, model_w.winding);
  EXPECT_EQ(free_w.on_surface, model_w.on_surface);
  std::vector<Ray> rays;
  for (const Vec3& o : random_points(200, -1, 2, 18)) rays.push_back({o, {1, 0.3, 0.2}});
  const std::vector<RayResult> free_r = cast(prepared, rays), model_r = m.cast(rays);
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(free_r[i].spans.size(), model_r[i].spans.size()) << i;
    for (size_t s = 0; s < free_r[i].spans.size(); ++s) {
      EXPECT_EQ(free_r[i].spans[s].t0, model_r[i].spans[s].t0);
      EXPECT_EQ(free_r[i].spans[s].t1, model_r[i].spans[s].t1);
    }
  }
  // Volume: the winding method in both, the same estimate and bound.
  const VolumeResult fv = volume(m.solid(), {.rays = 32}), mv = m.volume({.rays = 32});
  EXPECT_EQ(fv.method, "winding");
  EXPECT_EQ(fv.volume, mv.volume);
  EXPECT_EQ(fv.error_bound, mv.error_bound);
  EXPECT_THROW(volume(prepared, {.exact = true}), InputError);
  // Voxels: each centre classified, whole grid and brick alike, against classify() itself.
  VoxelizeOptions vo;
  vo.resolution = 12;
  const VoxelGrid fg = voxelize(m.solid(), vo), mg = m.voxelize(vo);
  EXPECT_EQ(fg.bits, mg.bits);
  const VoxelLattice lattice = m.voxel_lattice(vo);
  std::vector<Vec3> centres;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      for (int k = 0; k < 12; ++k) centres.push_back(lattice.centre(i, j, k));
  const std::vector<PointClass> c = m.classify(centres);
  size_t at = 0, differ = 0;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      for (int k = 0; k < 12; ++k) differ += fg.get(i, j, k) != (c[at++] != PointClass::kOutside);
  EXPECT_EQ(differ, 0u);
  const IndexBox brick{{2, 3, 4}, {9, 8, 12}};
  VoxelGrid fb;
  voxelize_brick(prepared, lattice, brick, fb);
  EXPECT_EQ(fb.bits, m.voxelize_brick(lattice, brick).bits);
  // Octree and render through the same Prepared.
  const VoxelBounds cube = m.voxel_bounds(8);
  const Octree ft = build_octree(prepared, cube, {.depth = 3}), mt = m.octree({.depth = 3}, cube);
  ASSERT_EQ(ft.nodes.size(), mt.nodes.size());
  for (size_t i = 0; i < ft.nodes.size(); ++i) EXPECT_EQ(ft.nodes[i].state, mt.nodes[i].state);
  CameraOptions co;
  co.width = 40;
  co.height = 30;
  EXPECT_EQ(render(prepared, m.camera(co)).rgb, m.render(co).rgb);
}

// The evaluated B-rep is built once: evaluate() again, clip() and evaluate_cells() cut the same
// mesh as the free evaluate() of the solid; options that change the result evaluate again, and
// EvaluateOptions::phases times the steps without changing the result.
TEST(Model, EvaluatedBrepIsKeptAndMatchesTheFreeEvaluate) {
  const Model m = box({0, 0, 0}, {2, 2, 2}) - sphere({2, 2, 2}, 1.2, 24);
  const EvaluateResult free_e = evaluate(m.solid());
  const EvaluateResult a = m.evaluate(), b = m.evaluate({.grain = 7});
  EXPECT_EQ(a.mesh.vertices, free_e.mesh.vertices);
  EXPECT_EQ(a.mesh.face_vertices, free_e.mesh.face_vertices);
  EXPECT_EQ(b.mesh.face_vertices, a.mesh.face_vertices);
  EvaluatePhases phases;
  const EvaluateResult timed = m.evaluate({.phases = &phases});
  EXPECT_EQ(timed.mesh.face_vertices, a.mesh.face_vertices);
  EXPECT_GT(phases.triangulate + phases.intersect + phases.select + phases.assemble, 0.0);
  EXPECT_EQ(m.evaluate_cells(2).evaluated.mesh.face_vertices, a.mesh.face_vertices);
  const Model copy = m;  // copies share the kept B-rep
  EXPECT_EQ(copy.evaluate().mesh.vertices, a.mesh.vertices);
  const brep::ClipResult cut = m.clip(brep::Plane{{0, 0, 1}, 1});
  const brep::ClipResult direct = brep::clip(free_e.mesh, brep::Plane{{0, 0, 1}, 1});
  EXPECT_EQ(cut.below.mesh.vertices, direct.below.mesh.vertices);
}

TEST(Model, VolumeExactCoveringRaysAndBrep) {
  // Disjoint boxes: the covering is exact.
  const Model two = box({0, 0, 0}, {1, 1, 1}) | box({2, 0, 0}, {3, 2, 1});
  const VolumeResult v = two.volume();
  EXPECT_EQ(v.method, "covering");
  EXPECT_DOUBLE_EQ(v.volume, 3.0);
  EXPECT_EQ(v.error_bound, 0);
  // Overlapping: rays within their bound of the exact B-rep volume, and --exact gives the B-rep.
  const Model m = part();
  const double exact = m.evaluate().volume;
  VolumeOptions rays;
  rays.rays = 64;
  const VolumeResult r = m.volume(rays);
  EXPECT_EQ(r.method, "rays");
  EXPECT_LE(std::abs(r.volume - exact), r.error_bound + 1e-12 * exact);
  VolumeOptions exact_options;
  exact_options.exact = true;
  const VolumeResult e = m.volume(exact_options);
  EXPECT_EQ(e.method, "brep");
  // The exact result's volume (rationals), against the rounded mesh's volume summed in doubles.
  EXPECT_NEAR(e.volume, exact, 1e-12 * exact);
  EXPECT_EQ(e.error_bound, 0);
  ASSERT_TRUE(e.area.has_value());
  // Unbounded.
  EXPECT_THROW((~m).volume(), NotComputable);
}

TEST(Model, TransformedEqualsTransformingEveryLeaf) {
  const Transform t = Transform::trs({2, 2, 2}, {0, 0, 1}, 90, {1, -3, 0.5});
  const Model m = part().transformed(t);
  PolygonMesh b = make_box({0, 0, 0}, {2, 2, 2}), s = make_sphere({2, 2, 2}, 1, 32),
              bar = make_box({1.5, 0.5, 0.5}, {3.5, 1, 1});
  for (PolygonMesh* mesh : {&b, &s, &bar}) apply_transform(t, *mesh);
  const Solid expected =
      unite({subtract({make_leaf(b, "box"), make_leaf(s, "sphere")}), make_leaf(bar, "box")});
  const std::vector<Vec3> points = random_points(5000, -8, 8, 4);
  EXPECT_EQ(m.classify(points), classify(expected, points));
  // A mirror keeps the solid solid (faces re-oriented): the volume keeps its sign.
  Transform mirror;
  mirror.rows[0][0] = -1;
  EXPECT_DOUBLE_EQ(box({0, 0, 0}, {1, 2, 3}).transformed(mirror).volume().volume, 6.0);
  std::array<double, 16> bad{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1};
  EXPECT_THROW((void)Transform::from_matrix(bad), InputError);
  Transform zero;
  for (auto& row : zero.rows) row = {0, 0, 0, 0};
  EXPECT_THROW(part().transformed(zero), InputError);
}

// translated / scaled / rotated / mirrored are transformed() by the matching matrices.
TEST(Model, TranslateScaleRotateMirror) {
  const Model m = part();
  const std::vector<Vec3> points = random_points(3000, -8, 8, 9);
  auto same = [&](const Model& a, const Transform& t) {
    EXPECT_EQ(a.classify(points), m.transformed(t).classify(points));
  };
  same(m.translated({1, -2, 0.5}), Transform::trs({1, 1, 1}, {0, 0, 1}, 0, {1, -2, 0.5}));
  same(m.scaled({2, 0.5, -1}), Transform::trs({2, 0.5, -1}, {0, 0, 1}, 0, {0, 0, 0}));
  same(m.scaled(1.5), Transform::trs({1.5, 1.5, 1.5}, {0, 0, 1}, 0, {0, 0, 0}));
  same(m.rotated({1, 1, 0}, 30), Transform::trs({1, 1, 1}, {1, 1, 0}, 30, {0, 0, 0}));
  Transform flip;
  flip.rows[1][1] = -1;
  same(m.mirrored({0, 3, 0}), flip);
  // A mirror keeps the solid solid.
  EXPECT_DOUBLE_EQ(
      box({0, 0, 0}, {1, 2, 3}).mirrored({1, 1, 1}).volume(VolumeOptions{.exact = true}).volume,
      6.0);
  EXPECT_THROW(m.scaled({1, 0, 1}), InputError);
  EXPECT_THROW(m.rotated({0, 0, 0}, 10), InputError);
  EXPECT_THROW(m.mirrored({0, 0, 0}), InputError);
  EXPECT_THROW(m.translated({NAN, 0, 0}), InputError);
}

TEST(Model, CastAndFirstHitsEqualTheKernel) {
  const Model m = part();
  std::vector<Ray> rays;
  for (const Vec3& o : random_points(500, -1, 4, 5)) rays.push_back({o, {1, 0.25, 0.125}});
  const std::vector<RayResult> all = m.cast(rays);
  const Prepared prepared(m.solid());
  const Bvh& bvh = prepared.bvh();
  const std::vector<RayResult> direct = cast(prepared, rays);
  const std::vector<FirstHit> first = m.first_hits(rays);
  ASSERT_EQ(all.size(), rays.size());
  size_t hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(all[i].spans.size(), direct[i].spans.size());
    for (size_t k = 0; k < all[i].spans.size(); ++k)
      EXPECT_EQ(all[i].spans[k].t0, direct[i].spans[k].t0);
    const FirstHit expected = first_hit(bvh, direct[i]);
    EXPECT_EQ(first[i].hit, expected.hit);
    EXPECT_EQ(first[i].t, expected.t);
    hits += first[i].hit;
  }
  EXPECT_GT(hits, 0u);
  std::vector<Ray> zero{{{0, 0, 0}, {0, 0, 0}}};
  EXPECT_THROW(m.cast(zero), InputError);
}

TEST(Model, VoxelizeOctreeRenderAndClipEqualTheKernels) {
  const Model m = part();
  VoxelizeOptions vo;
  vo.resolution = 32;
  const VoxelGrid grid = m.voxelize(vo);
  vo.bounds = m.voxel_bounds(32);
  const VoxelGrid direct = voxelize(m.solid(), vo);
  EXPECT_EQ(grid.bits, direct.bits);
  EXPECT_GT(grid.count(), 0u);

  OctreeOptions oo;
  oo.depth = 4;
  const Octree tree = m.octree(oo);
  const Octree direct_tree = build_octree(m.solid(), m.voxel_bounds(16), oo);
  ASSERT_EQ(tree.nodes.size(), direct_tree.nodes.size());
  EXPECT_EQ(tree.leaf_counts(), direct_tree.leaf_counts());

  CameraOptions co;
  co.width = 64;
  co.height = 48;
  const Image image = m.render(co);
  const Image direct_image = render(Prepared(m.solid()), m.camera(co), {});
  EXPECT_EQ(image.rgb, direct_image.rgb);
  co.width = 0;
  EXPECT_THROW(m.render(co), InputError);

  const brep::ClipResult clipped = m.clip({{0, 0, 1}, 0.75});
  const double exact = m.evaluate().volume;
  const double halves = signed_volume(clipped.above.mesh) + signed_volume(clipped.below.mesh);
  EXPECT_NEAR(halves, exact, 1e-12 * exact);
}

TEST(Model, BvhBuiltOnceSharedByCopiesAndThreads) {
  const Model m = part();
  const Model copy = m;  // NOLINT(performance-unnecessary-copy-initialization): shares the state
  const std::vector<Vec3> points = random_points(20000, -0.5, 4, 6);
  const std::vector<PointClass> expected = classify_brute_force(m.solid(), points);
  std::vector<std::vector<PointClass>> results(4);
  std::vector<const Bvh*> bvhs(4);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      const Model& which = t % 2 ? copy : m;
      results[t] = which.classify(points);
      bvhs[t] = &which.bvh();
    });
  for (std::thread& t : threads) t.join();
  for (int t = 0; t < 4; ++t) {
    EXPECT_EQ(results[t], expected);
    EXPECT_EQ(bvhs[t], bvhs[0]);
  }
}

TEST(Model, BytesRoundTripAnswersTheSame) {
  const Model m = part().transformed(Transform::trs({1, 2, 1}, {1, 1, 0}, 33, {0.5, 0, 0}));
  const Model back = Model::from_bytes(m.to_bytes());
  const std::vector<Vec3> points = random_points(5000, -2, 6, 9);
  EXPECT_EQ(back.classify(points), m.classify(points));
  EXPECT_EQ(back.evaluate().volume, m.evaluate().volume);
  EXPECT_TRUE(Model::from_bytes(Model().to_bytes()).empty());
  EXPECT_THROW(Model::from_bytes("not a solid"), InputError);
}

TEST(Model, FromBytesRefusesDamageOrReadsASolidEveryKernelAnswers) {
  // Closed, open and mirrored leaves under every operation; seeded random byte flips and
  // truncations: InputError, or a solid on which classify (against brute force), windings,
  // volume and voxelize run. Before reading validated the leaves, a closed leaf flagged open
  // crashed classify / volume / voxelize, and one flagged closed with a face missing answered.
  std::vector<std::array<Vec3, 3>> tris;
  const Model open = mesh(open_cube(1, tris), "open");
  const Model scene =
      (box({0, 0, 0}, {1, 1, 1}) -
       open.transformed(Transform::trs({0.5, 0.5, 0.5}, {0, 0, 1}, 0, {0.25, 0.25, 0.25}))) |
      (sphere({1, 1, 1}, 0.5, 6) &
       ~box({0.5, 0, 0}, {2, 1, 1})
            .transformed(Transform::trs({-1, 1, 1}, {0, 0, 1}, 0, {2.5, 0, 0})));
  const std::string bytes = scene.to_bytes();
  const std::vector<Vec3> points = random_points(64, -0.5, 1.5, 12);
  std::mt19937_64 rng(40);
#ifdef COVER_SANITIZED
  const int trials = 300;
#else
  const int trials = 3000;
#endif
  int refused = 0, read = 0;
  for (int trial = 0; trial < trials; ++trial) {
    std::string damaged = bytes;
    const int flips = 1 + static_cast<int>(rng() % 3);
    for (int f = 0; f < flips; ++f) {
      const size_t at = rng() % damaged.size();
      // Half the flips one bit (a sign, a flag, an index off by a power of two).
      damaged[at] ^= static_cast<char>(rng() % 2 ? 1 << (rng() % 8) : 1 + rng() % 255);
    }
    if (rng() % 8 == 0) damaged.resize(rng() % damaged.size());
    Model m;
    try {
      m = Model::from_bytes(damaged);
    } catch (const InputError&) {
      ++refused;
      continue;
    }
    ++read;
    EXPECT_EQ(m.to_bytes(), damaged) << trial;
    EXPECT_EQ(m.classify(points), classify_brute_force(m.solid(), points)) << trial;
    (void)m.windings(points);
    if (!m.bounded()) continue;
    VolumeOptions vo;
    vo.rays = 8;
    (void)m.volume(vo);
    VoxelizeOptions xo;
    xo.resolution = 8;
    (void)m.voxelize(xo);
  }
  EXPECT_GT(refused, trials / 4);
  EXPECT_GT(read, 0);  // e.g. a changed name or a moved vertex
}

TEST(Model, UnboundedResultIsNotComputableForEveryBrepKernel) {
  // evaluate, evaluate_cells, decompose and clip of a complement root: one exception type.
  const Model m = ~box({0, 0, 0}, {1, 1, 1});
  EXPECT_THROW(m.evaluate(), NotComputable);
  EXPECT_THROW(m.evaluate_cells(2, VoxelBounds{{0, 0, 0}, 1}), NotComputable);
  EXPECT_THROW(m.decompose(), NotComputable);
  EXPECT_THROW(m.clip(brep::Plane{{0, 0, 1}, 0.5}), NotComputable);
  EXPECT_THROW(m.volume(), NotComputable);
}

TEST(Model, EvaluateCellsRefusesNOverTheMemoryLimitBeforeEvaluating) {
  const Model m = part();
  try {
    (void)m.evaluate_cells(2000);  // 8e9 cells: refused at once, nothing evaluated
    ADD_FAILURE() << "not refused";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "evaluate cells: n = 2000: cutting into cells needs 23437500 MiB, over max_memory "
              "4096 MiB");
  }
  brep::CellsOptions small;
  small.max_memory_bytes = 4 << 20;  // 4 MiB: 10³ cells need 3000 KiB, 12³ 5184 KiB
  EXPECT_NO_THROW((void)m.evaluate_cells(10, std::nullopt, small));
  EXPECT_THROW((void)m.evaluate_cells(12, std::nullopt, small), InputError);
  EXPECT_EQ(brep::cells_memory_bytes(80), 80.0 * 80 * 80 * 3072);
}

TEST(Model, TransformWithADeterminantBeyondTheDoublesSaysSo) {
  const Model b = box({0, 0, 0}, {1, 1, 1});
  auto message = [&](const Transform& m) {
    try {
      (void)b.transformed(m);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message(Transform::trs({1e-200, 1e-200, 1e-200}, {0, 0, 1}, 0, {0, 0, 0})),
            "transform: the determinant, about 1e-600, is beyond the range of normal doubles: "
            "volumes would underflow");
  EXPECT_EQ(message(Transform::trs({1e200, 1e200, 1e-10}, {0, 0, 1}, 0, {0, 0, 0})),
            "transform: the determinant, about 1e390, is beyond the range of normal doubles: "
            "volumes would overflow");
  EXPECT_EQ(message(Transform::trs({1, 0, 1}, {0, 0, 1}, 0, {0, 0, 0})),
            "transform: singular matrix (it flattens the solid)");
  // Small but representable: accepted, and the volume is exact.
  EXPECT_EQ(b.transformed(Transform::trs({1e-100, 1e-100, 1e-100}, {0, 0, 1}, 0, {0, 0, 0}))
                .volume()
                .volume,
            1e-100 * 1e-100 * 1e-100);
}

TEST(Model, EmptyModelIsTheEmptySet) {
  const Model empty;
  const Model b = box({0, 0, 0}, {1, 1, 1});
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ((empty | b).leaf_count(), 1u);
  EXPECT_TRUE((empty & b).empty());
  EXPECT_TRUE((empty - b).empty());
  EXPECT_EQ((b - empty).leaf_count(), 1u);
  EXPECT_EQ(empty.volume().volume, 0);
  EXPECT_EQ(empty.classify(std::vector<Vec3>{{0, 0, 0}})[0], PointClass::kOutside);
  EXPECT_EQ(empty.evaluate().mesh.face_count(), 0u);
  EXPECT_EQ(empty.voxelize({.resolution = 4}).count(), 0u);
  // The octree of the empty set: every node empty, as a cube far from a box gives.
  const Octree none = empty.octree({.depth = 3}, VoxelBounds{{5, 5, 5}, 1});
  const Octree far = b.octree({.depth = 3}, VoxelBounds{{5, 5, 5}, 1});
  ASSERT_FALSE(none.nodes.empty());
  EXPECT_EQ(none.nodes.size(), far.nodes.size());
  for (const Octree::Node& node : none.nodes) EXPECT_EQ(node.state, CellState::kEmpty);
  EXPECT_EQ(empty.octree({.depth = 2}).nodes.size(), 1u);
  EXPECT_THROW(~empty, PreconditionError);
}

TEST(Model, LoadAndMeshFromArrays) {
  const Model frame = load(test::source_dir() / "models" / "frame.off");
  EXPECT_EQ(frame.leaf_count(), 1u);
  EXPECT_THROW(load(test::source_dir() / "models" / "missing.off"), InputError);
  try {
    load(test::source_dir() / "models" / "missing.off");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.off"), std::string::npos);
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
  // A tetrahedron from arrays, given inside-out: reversed on load (a warning), volume 1/6.
  const std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const std::vector<std::array<uint32_t, 3>> inside_out = {
      {0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  const Model tet = mesh(v, inside_out, "tet");
  EXPECT_DOUBLE_EQ(tet.volume().volume, 1.0 / 6.0);
  EXPECT_EQ(tet.warnings().size(), 1u);
  const std::vector<std::array<uint32_t, 3>> bad_index = {{0, 1, 7}};
  EXPECT_THROW(mesh(v, bad_index, "tet"), InputError);
  const std::vector<std::array<uint32_t, 3>> open = {{0, 2, 1}, {0, 1, 3}};
  LoadOptions closed_only;
  closed_only.require_closed = true;
  EXPECT_THROW(mesh(v, open, "tet", closed_only), InputError);
  // Accepted: the winding-number rule. The warning names the option that refuses it, as each
  // front end spells it.
  const Model open_tet = mesh(v, open, "tet");
  EXPECT_TRUE(open_tet.solid().leaves[0].open());
  ASSERT_EQ(open_tet.warnings().size(), 1u);
  EXPECT_NE(open_tet.warnings()[0].find("(require_closed refuses)"), std::string::npos)
      << open_tet.warnings()[0];
  const auto flag = [](std::string_view name) { return "--" + std::string(name); };
  EXPECT_NE(open_tet.warnings(flag)[0].find("(--require_closed refuses)"), std::string::npos);
  EXPECT_THROW(box({0, 0, 0}, {0, 1, 1}), InputError);
  EXPECT_THROW(sphere({0, 0, 0}, -1), InputError);
  EXPECT_THROW(cylinder({0, 0, 0}, {0, 0, 0}, 1), InputError);
  const std::vector<Vec3> nan_point = {{std::nan(""), 0, 0}};
  EXPECT_THROW(tet.classify(nan_point), InputError);
}

// A parameter is named as the C++ API spells it, marked so that each front end shows its own
// name: the CLI its flag, Python its keyword (cli/main.cpp flag_of, python/module.cpp keyword).
TEST(Model, ParameterErrorsNameTheOptionsField) {
  const Model m = part();
  const auto flag = [](std::string_view name) {
    return name == "resolution" ? std::string("--res") : "--" + std::string(name);
  };
  try {
    (void)m.voxelize({.resolution = 5000});
    ADD_FAILURE() << "not refused";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "resolution: expected a whole number from 1 to 4096, got 5000");
    EXPECT_EQ(e.text(flag), "--res: expected a whole number from 1 to 4096, got 5000");
    EXPECT_EQ(e.prefixed("in.off: ").text(flag),
              "in.off: --res: expected a whole number from 1 to 4096, got 5000");
  }
  try {
    (void)m.octree({.depth = 17});
    ADD_FAILURE() << "not refused";
  } catch (const InputError& e) {
    EXPECT_TRUE(std::string_view(e.what()).starts_with("depth: expected a whole number"))
        << e.what();
    EXPECT_TRUE(e.text(flag).starts_with("--depth: expected a whole number")) << e.text(flag);
  }
  // Text without marks is shown as written, whatever the renderer.
  EXPECT_EQ(InputError("a.off:3: bad face").text(flag), "a.off:3: bad face");
  EXPECT_EQ(InputError(parameter("x") + " and " + parameter("y_z") + ": both").text(flag),
            "--x and --y_z: both");
}

// The free functions answer a Solid with no leaf (the empty set) as the Model does, without
// reading its empty CSG tree.
TEST(FreeFunctions, SolidWithNoLeafIsTheEmptySet) {
  const Solid none;
  const std::vector<Vec3> points = {{0, 0, 0}, {1, 2, 3}};
  EXPECT_EQ(classify(none, points),
            (std::vector<PointClass>{PointClass::kOutside, PointClass::kOutside}));
  EXPECT_EQ(classify_brute_force(none, points), classify(none, points));
  EXPECT_EQ(covering_volume(none), 0.0);
  EXPECT_EQ(covering_inexact_reason(none), std::nullopt);
  const std::vector<Ray> rays = {{{-1, 0.5, 0.5}, {1, 0, 0}}};
  const std::vector<RayResult> hits = cast(Prepared(none), rays);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_TRUE(hits[0].hits.empty());
  EXPECT_TRUE(hits[0].spans.empty());
  EXPECT_EQ(leaf_windings(Prepared(none), points).leaves, 0u);
  EXPECT_EQ(volume(none).volume, 0.0);
  EXPECT_TRUE(is_bounded(none));
  VoxelizeOptions vo;
  vo.resolution = 4;
  vo.bounds = VoxelBounds{{0, 0, 0}, 1};
  EXPECT_EQ(voxelize(none, vo).count(), 0u);
  EXPECT_EQ(evaluate(none).mesh.face_count(), 0u);
  CameraOptions co;
  co.width = 8;
  co.height = 6;
  const Camera cam = frame_camera(Bbox{{0, 0, 0}, {1, 1, 1}}, co);
  const Image img = render(Prepared(none), cam, {});
  for (uint16_t id : img.ids) EXPECT_EQ(id, Image::kBackgroundId);
}

// cover::info (what `cover info` and Model.info print) against the kernels it summarises,
// leaf by leaf: validate_mesh, the half-edge kernel and the exact covering volume.
TEST(Info, EachLeafAgreesWithValidateAndTheHalfEdgeKernel) {
  const Model m = part();  // (box − sphere) ∪ bar: three closed leaves
  const ModelInfo facts = info(m);
  const Solid& s = m.solid();
  ASSERT_EQ(facts.leaves.size(), s.leaves.size());
  EXPECT_EQ(facts.vertices, s.vertices.size());
  EXPECT_EQ(facts.faces, s.face_count());
  for (uint32_t l = 0; l < s.leaves.size(); ++l) {
    const LeafInfo& leaf = facts.leaves[l];
    const PolygonMesh mesh = leaf_mesh(s, l);
    const MeshReport r = validate_mesh(mesh);
    EXPECT_EQ(leaf.name, s.leaves[l].name);
    EXPECT_TRUE(leaf.report.closed && leaf.report.manifold && leaf.report.outward);
    EXPECT_EQ(leaf.report.genus, r.genus);
    EXPECT_EQ(leaf.report.volume, r.volume);
    EXPECT_EQ(leaf.report.self_intersecting, std::optional<bool>(false));
    ASSERT_TRUE(leaf.brep.has_value());
    EXPECT_EQ(leaf.brep->euler, 2);  // box, sphere, bar: genus 0
    EXPECT_EQ(leaf.brep->genus, 0);
    EXPECT_FALSE(leaf.repair.open());
  }
  EXPECT_EQ(info(m, {.check_self_intersection = false}).leaves[0].report.self_intersecting,
            std::nullopt);
  EXPECT_TRUE(info(Model()).leaves.empty());
}

}  // namespace
}  // namespace cover
