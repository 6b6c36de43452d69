// Field leaves through the whole library (solid/field_leaf.h, field/field.h): scenes with field
// and blend nodes load; every query answers them against independent paths — classification
// against the exact rational sign of each field (field::sign_exact) and exact box tests combined
// by the tree, points built exactly on a surface are `face`, voxels equal the classification of
// their centres, the bracket volume contains a dense-sampling estimate and shrinks with the
// target, results are identical for 1 and 2 threads — and what does not take them refuses.
#include <CGAL/Gmpq.h>
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "cover/field/field.h"
#include "cover/io/scene.h"
#include "cover/model/info.h"
#include "cover/model/model.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "cover/solid/transform.h"
#include "helpers.h"
#include "model/octree_check.h"

namespace cover {
namespace {

Model scene(const std::string& text) {
  LoadedInput in = parse_scene(text, "fields.json");
  return Model(std::move(in.solid), std::move(in.warnings));
}

/// The issue's two-point blend: centres ±0.35, R = 1, r_T = 0.5, n = 2.
const char* kTwoPoints = R"({"blend": [
  {"field": {"skeleton": {"point": [-0.35, 0, 0]}, "radius": 0.5, "influence": 1}},
  {"field": {"skeleton": {"point": [0.35, 0, 0]}, "radius": 0.5, "influence": 1}}]})";

/// A blend with a segment, a triangle, a polyline and a carving point, minus a box, united with
/// a box: every kind of node at once.
std::string mixed_scene() {
  return R"({"union": [
    {"difference": [
      {"blend": [
        {"field": {"skeleton": {"segment": [[-0.6, 0, 0], [0.6, 0, 0]]},
                   "radius": 0.25, "influence": 0.5, "exponent": 3}},
        {"field": {"skeleton": {"triangle": [[0, 0.2, -0.3], [0.4, 0.6, 0], [-0.3, 0.5, 0.3]]},
                   "radius": 0.25, "influence": 0.5, "exponent": 3}},
        {"field": {"skeleton": {"polyline": [[-0.5, -0.5, 0], [0, -0.7, 0.2], [0.5, -0.5, 0]]},
                   "radius": 0.25, "influence": 0.5, "exponent": 3}},
        {"field": {"skeleton": {"point": [0.1, 0.05, 0]},
                   "radius": 0.25, "influence": 0.5, "exponent": 3, "weight": -1}}]},
      {"box": {"min": [0.3, -2, -2], "max": [2, 2, 0]}}]},
    {"box": {"min": [-1, -1, -0.75], "max": [-0.5, 1, -0.5]}}]})";
}

std::vector<Vec3> random_points(size_t n, Vec3 lo, Vec3 hi, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> out(n);
  for (Vec3& p : out)
    p = {lo.x + u(rng) * (hi.x - lo.x), lo.y + u(rng) * (hi.y - lo.y),
         lo.z + u(rng) * (hi.z - lo.z)};
  return out;
}

/// Exact closed-box membership: inside (interior), on the boundary, outside.
field::Sign box_sign(const Vec3& p, Vec3 lo, Vec3 hi) {
  bool on = false;
  for (int a = 0; a < 3; ++a) {
    if (p[a] < lo[a] || p[a] > hi[a]) return field::Sign::kOutside;
    on |= p[a] == lo[a] || p[a] == hi[a];
  }
  return on ? field::Sign::kOn : field::Sign::kInside;
}

TEST(Fields, TwoPointBlendLoadsWithItsSupportBox) {
  const Model m = scene(kTwoPoints);
  ASSERT_EQ(m.solid().leaves.size(), 1u);
  const Leaf& leaf = m.solid().leaves[0];
  EXPECT_TRUE(leaf.is_field());
  EXPECT_EQ(leaf.face_count, 0u);
  EXPECT_EQ(m.solid().fields[0].primitives.size(), 2u);
  // Support box: centres ± R, rounded outward.
  EXPECT_LE(leaf.bbox.min.x, -1.35);
  EXPECT_GE(leaf.bbox.max.x, 1.35);
  EXPECT_LT(leaf.bbox.max.x, 1.3500001);
}

TEST(Fields, PointOnTheTwoPointBlendIsFace) {
  const Model m = scene(kTwoPoints);
  // f(0.85, 0, 0) = (1 − 1.2²)² ... only the near centre reaches: d = 0.5 → T exactly; the far
  // centre at distance 1.2 > R adds 0. The sign is decided in rationals.
  const std::vector<Vec3> pts{{0.85, 0, 0}, {-0.85, 0, 0}, {0.84, 0, 0}, {0.86, 0, 0}, {0, 0, 0}};
  const std::vector<PointClass> c = m.classify(pts);
  EXPECT_EQ(c[0], PointClass::kFace);
  EXPECT_EQ(c[1], PointClass::kFace);
  EXPECT_EQ(c[2], PointClass::kInside);
  EXPECT_EQ(c[3], PointClass::kOutside);
  EXPECT_EQ(c[4], PointClass::kInside);
}

/// The mixed scene's membership from independent parts: field::sign_exact for the blend, exact
/// box comparisons for the boxes, combined by the set operations; a point on exactly one
/// surface where the result changes across it is face. Returns false for points on two
/// surfaces at once (not compared).
bool reference(const FieldLeaf& blend, const Vec3& p, PointClass& out) {
  const field::Sign f = field::sign_exact(blend, p);
  const field::Sign b1 = box_sign(p, {0.3, -2, -2}, {2, 2, 0});
  const field::Sign b2 = box_sign(p, {-1, -1, -0.75}, {-0.5, 1, -0.5});
  const int on = (f == field::Sign::kOn) + (b1 == field::Sign::kOn) + (b2 == field::Sign::kOn);
  if (on > 1) return false;
  auto eval = [](bool in_f, bool in_b1, bool in_b2) { return (in_f && !in_b1) || in_b2; };
  const bool fi = f == field::Sign::kInside, b1i = b1 == field::Sign::kInside,
             b2i = b2 == field::Sign::kInside;
  if (on == 0) {
    out = eval(fi, b1i, b2i) ? PointClass::kInside : PointClass::kOutside;
    return true;
  }
  // One surface: the result on either side of it.
  bool a, b;
  if (f == field::Sign::kOn) {
    a = eval(true, b1i, b2i), b = eval(false, b1i, b2i);
  } else if (b1 == field::Sign::kOn) {
    a = eval(fi, true, b2i), b = eval(fi, false, b2i);
  } else {
    a = eval(fi, b1i, true), b = eval(fi, b1i, false);
  }
  if (a != b) {
    if (b1 == field::Sign::kOn || b2 == field::Sign::kOn)
      return false;  // box faces: face/edge/vertex
    out = PointClass::kFace;
  } else {
    out = a ? PointClass::kInside : PointClass::kOutside;
  }
  return true;
}

TEST(Fields, MixedSceneAgreesWithExactReferenceOn100kPoints) {
  const Model m = scene(mixed_scene());
  ASSERT_EQ(m.solid().leaves.size(), 3u);
  const FieldLeaf& blend = m.solid().fields[0];
  // Random points, and points on a coarse dyadic lattice (many on the box faces and axes).
  std::vector<Vec3> pts = random_points(100000, {-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, 42);
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> g(-40, 40);
  for (int i = 0; i < 20000; ++i) pts.push_back({g(rng) / 32.0, g(rng) / 32.0, g(rng) / 32.0});
  const Classification c = m.classify_counted(pts);
  EXPECT_EQ(c.uncertain, 0u);
  size_t compared = 0, disagree = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    PointClass want;
    if (!reference(blend, pts[i], want)) continue;
    ++compared;
    if (c.classes[i] != want && ++disagree < 5)
      ADD_FAILURE() << "point " << i << " (" << pts[i].x << ", " << pts[i].y << ", " << pts[i].z
                    << "): " << to_string(c.classes[i]) << ", expected " << to_string(want);
  }
  EXPECT_GT(compared, 110000u);
  EXPECT_EQ(disagree, 0u);
  EXPECT_GT(std::count(c.classes.begin(), c.classes.end(), PointClass::kInside), 5000);
}

TEST(Fields, PointPrimitiveIsTheExactBallAndItsSurfacePointsAreFaces) {
  // r_T = 5/8: (3/8, 1/2, 0) is exactly on the sphere; the ball test is exact in rationals.
  const Model m = scene(R"({"field": {"skeleton": {"point": [0, 0, 0]}, "radius": 0.625,
                             "influence": 1.5, "exponent": 4}})");
  std::vector<Vec3> pts = random_points(50000, {-1, -1, -1}, {1, 1, 1}, 9);
  const std::vector<Vec3> on{{0.375, 0.5, 0}, {0, -0.375, 0.5}, {0.625, 0, 0}, {0, 0, -0.625}};
  pts.insert(pts.end(), on.begin(), on.end());
  const std::vector<PointClass> c = m.classify(pts);
  for (size_t i = 0; i < pts.size(); ++i) {
    const CGAL::Gmpq x(pts[i].x), y(pts[i].y), z(pts[i].z), r(0.625);
    const CGAL::Gmpq d = r * r - (x * x + y * y + z * z);
    const PointClass want =
        d > 0 ? PointClass::kInside : (d < 0 ? PointClass::kOutside : PointClass::kFace);
    ASSERT_EQ(c[i], want) << i;
  }
}

TEST(Fields, SameResultsWithOneAndTwoThreads) {
  const Model m = scene(mixed_scene());
  const std::vector<Vec3> pts =
      random_points(60000 / test::kCheckedStride, {-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, 5);
  std::vector<PointClass> one, two;
  VoxelizeOptions vo;
  vo.resolution = 40;
  VoxelGrid g1, g2;
  VolumeResult v1, v2;
  {
    ThreadLimit limit(1);
    one = m.classify(pts);
    g1 = m.voxelize(vo);
    v1 = m.volume();
  }
  {
    ThreadLimit limit(2);
    two = m.classify(pts);
    g2 = m.voxelize(vo);
    v2 = m.volume();
  }
  EXPECT_EQ(one, two);
  EXPECT_EQ(g1.bits, g2.bits);
  EXPECT_EQ(v1.volume, v2.volume);
  EXPECT_EQ(v1.error_bound, v2.error_bound);
}

TEST(Fields, VoxelsEqualClassificationOfTheirCentres) {
  const Model m = scene(mixed_scene());
  VoxelizeOptions vo;
  vo.resolution = 48;
  const VoxelGrid g = m.voxelize(vo);
  const VoxelLattice& lat = g.lattice;
  std::vector<Vec3> centres;
  for (int i = 0; i < lat.dims[0]; ++i)
    for (int j = 0; j < lat.dims[1]; ++j)
      for (int k = 0; k < lat.dims[2]; ++k) centres.push_back(lat.centre(i, j, k));
  const std::vector<PointClass> c = m.classify(centres);
  size_t at = 0, set = 0;
  for (int i = 0; i < lat.dims[0]; ++i)
    for (int j = 0; j < lat.dims[1]; ++j)
      for (int k = 0; k < lat.dims[2]; ++k) {
        const bool want = c[at++] != PointClass::kOutside;
        ASSERT_EQ(g.get(i, j, k), want) << i << " " << j << " " << k;
        set += want;
      }
  EXPECT_GT(set, 1000u);
}

TEST(Fields, BracketVolumeContainsTheSampledVolumeAndShrinks) {
  const Model m = scene(mixed_scene());
  VolumeOptions coarse, fine;
  coarse.bracket_relative_error = 0.1;
  fine.bracket_relative_error = 0.05;
  const VolumeResult a = m.volume(coarse), b = m.volume(fine);
  EXPECT_EQ(a.method, "bracket");
  EXPECT_TRUE(a.target_met);
  EXPECT_TRUE(b.target_met);
  EXPECT_LT(b.error_bound, a.error_bound);
  // Both brackets contain each other's truth: they must overlap, and the fine one must contain
  // a dense midpoint-rule estimate up to that estimate's own resolution error.
  EXPECT_LE(std::abs(a.volume - b.volume), a.error_bound + b.error_bound);
  const Bbox box = *m.bounds();
  const int n = 160;
  VoxelizeOptions vo;
  vo.resolution = n;
  const VoxelGrid g = m.voxelize(vo);
  const uint64_t count = g.count();
  const double h = g.lattice.spacing;
  const double estimate = count * h * h * h;
  (void)box;
  EXPECT_NEAR(estimate, b.volume, b.error_bound + 0.02 * b.volume);
}

TEST(Fields, PureBlendVolumeBracketsTheBallVolume) {
  // One point primitive: the ball of radius r_T, volume 4/3·π·r³.
  const Model m = scene(
      R"({"field": {"skeleton": {"point": [0.1, 0.2, 0.3]}, "radius": 0.5, "influence": 1}})");
  VolumeOptions o;
  o.bracket_relative_error = 1e-2;
  const VolumeResult r = m.volume(o);
  const double exact = 4.0 / 3.0 * 3.14159265358979323846 * 0.125;
  EXPECT_LE(std::abs(r.volume - exact), r.error_bound);
  EXPECT_TRUE(r.target_met);
  EXPECT_LE(r.error_bound, 1e-2 * r.volume);
}

TEST(Fields, TransformsMoveAndScaleTheSkeletons) {
  const Model m =
      scene(R"({"field": {"skeleton": {"segment": [[0, 0, 0], [1, 0, 0]]}, "radius": 0.25,
                  "influence": 0.5}, "transform": {"scale": 2, "translate": [0, 0, 1]}})");
  const FieldPrimitive& p = m.solid().fields[0].primitives[0];
  EXPECT_EQ(p.points[1].x, 2);
  EXPECT_EQ(p.points[1].z, 1);
  EXPECT_EQ(p.radius, 0.5);
  EXPECT_EQ(p.influence, 1);
  const std::vector<PointClass> c = m.classify(std::vector<Vec3>{{1, 0.5, 1}, {1, 0, 1.6}});
  EXPECT_EQ(c[0], PointClass::kFace);
  EXPECT_EQ(c[1], PointClass::kOutside);
  EXPECT_THROW(scene(R"({"field": {"skeleton": {"point": [0, 0, 0]}, "radius": 0.5, "influence": 1},
                         "transform": {"scale": [1, 2, 1]}})"),
               InputError);
}

TEST(Fields, BadNodesAreOneLineErrorsNamingThePath) {
  auto message = [](const std::string& text) {
    try {
      scene(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(R"({"field": {"skeleton": {"point": [0, 0, 0]}, "radius": 1, "influence": 1}})")
                .find("fields.json: /field: "),
            std::string::npos);
  const std::string mismatch = message(R"({"blend": [
    {"field": {"skeleton": {"point": [0, 0, 0]}, "radius": 0.5, "influence": 1}},
    {"field": {"skeleton": {"point": [1, 0, 0]}, "radius": 0.4, "influence": 1}}]})");
  EXPECT_NE(mismatch.find("/blend/1/field"), std::string::npos) << mismatch;
  EXPECT_NE(message(R"({"blend": [{"box": {"min": [0,0,0], "max": [1,1,1]}}]})").find("/blend/0"),
            std::string::npos);
  EXPECT_NE(
      message(R"({"field": {"skeleton": {"cube": [0, 0, 0]}, "radius": 0.5, "influence": 1}})")
          .find("unknown skeleton"),
      std::string::npos);
  EXPECT_NE(
      message(R"({"field": {"skeleton": {"point": [0, 0, 0]}, "radius": 0.5}})").find("influence"),
      std::string::npos);
  for (const std::string& m : {mismatch}) EXPECT_EQ(m.find('\n'), std::string::npos);
}

TEST(Fields, ExactVolumeOfACurvedTreeIsItsBracket) {
  // No exact volume of a curved solid in doubles: exact asks for the same certified bracket.
  const Model m = scene(mixed_scene());
  VolumeOptions exact, plain;
  exact.exact = true;
  // The checked build asks a looser bracket (same comparison, a quarter of the samples).
  exact.bracket_relative_error = plain.bracket_relative_error = 0.05 * test::kCheckedStride;
  const VolumeResult e = m.volume(exact), p = m.volume(plain);
  EXPECT_EQ(e.method, "bracket");
  EXPECT_EQ(e.volume, p.volume);
  EXPECT_EQ(e.error_bound, p.error_bound);
  EXPECT_GT(e.error_bound, 0);
}

TEST(Fields, RaysCrossTheTwoPointBlendWhereItsSurfaceIs) {
  const Model m = scene(kTwoPoints);
  // Along the x axis the surface is at x = ±0.85 exactly; the crossings are within 2^-20 of the
  // run through the support box (2.7 long) of them.
  const std::vector<RayResult> r = m.cast(std::vector<Ray>{{{-3, 0, 0}, {1, 0, 0}}});
  ASSERT_EQ(r[0].spans.size(), 1u);
  EXPECT_NEAR(r[0].spans[0].t0, 3 - 0.85, 3e-6);
  EXPECT_NEAR(r[0].spans[0].t1, 3 + 0.85, 3e-6);
  EXPECT_EQ(r[0].uncertain, 0u);
  const std::vector<FirstHit> h = m.first_hits(std::vector<Ray>{{{-3, 0, 0}, {1, 0, 0}}});
  ASSERT_TRUE(h[0].hit);
  EXPECT_LT(h[0].normal.x, 0);  // outward at the left end: −x
}

TEST(Fields, RaySpansAgreeWithClassificationAlongEachRay) {
  const Model m = scene(mixed_scene());
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Ray> rays(1000);
  for (Ray& r : rays) r = {{3 * u(rng), 3 * u(rng), 3 * u(rng)}, {u(rng), u(rng), u(rng)}};
  const std::vector<RayResult> res = m.cast(rays);
  // Points along each ray away from every hit (further than the crossings' tolerance): inside a
  // span exactly where classify says not outside.
  std::vector<Vec3> pts;
  std::vector<uint8_t> in_span;
  for (size_t i = 0; i < rays.size(); ++i) {
    const double len = std::sqrt(dot(rays[i].dir, rays[i].dir));
    for (int k = 1; k <= 200; ++k) {
      const double t = k * 0.03 / len;
      bool near = false;
      for (const RayHit& h : res[i].hits) near |= std::abs(h.t - t) * len < 1e-4;
      if (near) continue;
      bool inside = false;
      for (const Span& s : res[i].spans) inside |= s.t0 < t && t < s.t1;
      pts.push_back(rays[i].origin + t * rays[i].dir);
      in_span.push_back(inside);
    }
  }
  const std::vector<PointClass> c = m.classify(pts);
  size_t disagree = 0, inside = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    disagree += (c[i] != PointClass::kOutside) != (in_span[i] != 0);
    inside += in_span[i];
  }
  EXPECT_EQ(disagree, 0u);
  EXPECT_GT(inside, 500u);
}

TEST(Fields, RenderShowsTheBlend) {
  const Model m = scene(kTwoPoints);
  CameraOptions co;
  co.width = co.height = 64;
  const Image img = m.render(co);
  // The centre pixel sees the blend; a corner sees the background.
  EXPECT_NE(img.ids[32 * 64 + 32], Image::kBackgroundId);
  EXPECT_EQ(img.ids[0], Image::kBackgroundId);
}

TEST(Fields, OctreeClaimsFullAndEmptyOnlyWhereDenseSamplingAgrees) {
  const Model m = scene(mixed_scene());
  OctreeOptions o;
  o.depth = 5;
  const Octree t = m.octree(o);
  const std::array<uint64_t, 3> counts = t.leaf_counts();
  EXPECT_GT(counts[0], 100u);
  EXPECT_GT(counts[1], 10u);
  EXPECT_GT(counts[2], 100u);
  EXPECT_EQ(test::certified_cells_wrong(m, t, 4), 0u);
  // Thread-count independent, and the occupancy of the root is close to the volume's share.
  Octree t1;
  {
    ThreadLimit limit(1);
    t1 = m.octree(o);
  }
  ASSERT_EQ(t1.nodes.size(), t.nodes.size());
  for (size_t i = 0; i < t.nodes.size(); ++i) {
    ASSERT_EQ(t1.nodes[i].state, t.nodes[i].state);
    ASSERT_EQ(t1.nodes[i].occupancy, t.nodes[i].occupancy);
  }
  const VolumeResult v = m.volume();
  const double cube = t.bounds.size * t.bounds.size * t.bounds.size;
  EXPECT_NEAR(t.nodes[0].occupancy * cube, v.volume, v.error_bound + 0.05 * v.volume);
}

TEST(Fields, BytesRoundTripKeepsTheFields) {
  const Model m = scene(mixed_scene()).transformed(Transform::rotation({1, 2, 3}, 30));
  const Model back = Model::from_bytes(m.to_bytes());
  ASSERT_EQ(back.solid().fields.size(), 1u);
  EXPECT_EQ(back.solid().leaves[0].bbox.min, m.solid().leaves[0].bbox.min);
  const std::vector<Vec3> pts = random_points(20000, {-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}, 8);
  EXPECT_EQ(back.classify(pts), m.classify(pts));
  // A damaged field section is refused in one line.
  std::string bytes = m.to_bytes();
  bytes.resize(bytes.size() - 3);
  EXPECT_THROW(Model::from_bytes(bytes), InputError);
}

TEST(Fields, FieldQueryAndInfo) {
  const Model m = scene(kTwoPoints);
  const Model::FieldValues f = m.field(std::vector<Vec3>{{0.85, 0, 0}, {0, 0, 0}});
  ASSERT_EQ(f.leaves.size(), 1u);
  // At (0.85, 0, 0): the near centre at d = 0.5 gives (1 − 0.25)² = 0.5625 = T; ∇f points to −x.
  EXPECT_DOUBLE_EQ(f.values[0].value, 0.5625);
  EXPECT_DOUBLE_EQ(field::threshold(m.solid().fields[0]), 0.5625);
  EXPECT_LT(f.values[0].gradient.x, 0);
  EXPECT_EQ(f.values[1].gradient.x, 0);  // symmetric
  const ModelInfo info = cover::info(m);
  ASSERT_EQ(info.leaves.size(), 1u);
  ASSERT_TRUE(info.leaves[0].field.has_value());
  EXPECT_EQ(info.leaves[0].field->primitives.size(), 2u);
  EXPECT_DOUBLE_EQ(info.leaves[0].threshold, 0.5625);
  EXPECT_THROW(box({0, 0, 0}, {1, 1, 1}).field(std::vector<Vec3>{{0, 0, 0}}), InputError);
}

}  // namespace
}  // namespace cover
