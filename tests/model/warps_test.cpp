// Warp leaves through the whole library (solid/warp_leaf.h, field/warp.h): twist, taper and
// bend nodes over meshes, fields and subtrees load from scenes; every query answers them against
// independent paths — classification against the child's classification at the inverse-mapped
// points and against exact rational references (a tapered box), special cases (a capsule
// twisted about its own axis is the capsule), voxels equal the classification of their centres,
// octree full / empty cells agree with dense sampling, ray spans agree with classification along
// each ray, the bracket volume contains the known volume, the bytes round trip, results are
// identical for 1 and 2 threads — and bad nodes are one-line errors naming their JSON path.
#include <CGAL/Gmpq.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <span>
#include <string>

#include "cover/field/warp.h"
#include "cover/io/scene.h"
#include "cover/model/info.h"
#include "cover/model/model.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "cover/solid/transform.h"
#include "model/octree_check.h"

namespace cover {
namespace {

Model scene(const std::string& text) {
  LoadedInput in = parse_scene(text, "warps.json");
  return Model(std::move(in.solid), std::move(in.warnings));
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

/// A bar with a hole, twisted about a tilted axis: a warp of a mesh subtree.
const char* kTwistedBar = R"({"twist": {
  "axis": {"point": [0, 0, 0], "direction": [0, 0, 1]}, "degrees_per_unit": 60,
  "child": {"difference": [
    {"box": {"min": [-0.5, -0.2, -1], "max": [0.5, 0.2, 1]}},
    {"cylinder": {"base": [0, -1, 0.3], "top": [0, 1, 0.3], "radius": 0.12}}]}}})";

/// A blend of two segments, tapered, united with a bent box: fields, meshes, two warps.
const char* kMixed = R"({"union": [
  {"taper": {"axis": {"point": [0, 0, 0], "direction": [0, 1, 0]},
             "range": [-1, 1], "scale": [1, 0.4],
             "child": {"blend": [
               {"field": {"skeleton": {"segment": [[0, -1, 0], [0, 1, 0]]},
                          "radius": 0.3, "influence": 0.6}},
               {"field": {"skeleton": {"segment": [[-0.5, 0.4, 0], [0.5, 0.4, 0]]},
                          "radius": 0.3, "influence": 0.6}}]}}},
  {"bend": {"axis": {"point": [0, 0, -0.8], "direction": [1, 0, 0]}, "toward": [0, 0, 1],
            "range": [-0.2, 1.2], "center": -0.2, "radius": 1.5,
            "child": {"box": {"min": [-1, -0.3, -0.9], "max": [1.2, 0.3, -0.7]}}}}]})";

/// The child's classification at w⁻¹(q) against the warped model's at q: they differ at most
/// at the points the warped model counts uncertain.
void expect_matches_child(const Model& warped, const Model& child, const WarpLeaf& w,
                          const std::vector<Vec3>& pts) {
  const Classification c = warped.classify_counted(pts);
  std::vector<Vec3> back;
  std::vector<size_t> index;
  size_t outside_image = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const Vec3 p = field::inverse(w, pts[i]);
    if (!std::isfinite(p.x)) {
      outside_image += c.classes[i] != PointClass::kOutside;
      continue;
    }
    back.push_back(p);
    index.push_back(i);
  }
  EXPECT_EQ(outside_image, 0u);
  const std::vector<PointClass> ref = child.classify(back);
  size_t differ = 0, inside = 0;
  for (size_t k = 0; k < back.size(); ++k) {
    const PointClass a = c.classes[index[k]], b = ref[k];
    differ += (a == PointClass::kOutside) != (b == PointClass::kOutside);
    inside += b == PointClass::kInside;
  }
  EXPECT_LE(differ, c.uncertain);
  EXPECT_LE(c.uncertain, pts.size() / 1000);  // only a thin band around the surface
  EXPECT_GT(inside, pts.size() / 50);
}

TEST(Warps, TwistedMeshAgreesWithItsChildAtInverseMappedPoints) {
  const Model m = scene(kTwistedBar);
  ASSERT_EQ(m.solid().leaves.size(), 1u);
  ASSERT_TRUE(m.solid().leaves[0].is_warp());
  const WarpLeaf& w = m.solid().warps[0];
  const Model child(Solid(*w.child));
  expect_matches_child(m, child, w, random_points(100000, {-0.7, -0.7, -1.1}, {0.7, 0.7, 1.1}, 1));
}

TEST(Warps, BentAndTaperedLeavesAgreeWithTheirChildren) {
  const Model m = scene(kMixed);
  ASSERT_EQ(m.solid().warps.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    const WarpLeaf& w = m.solid().warps[k];
    const Model warped(make_warp_leaf(w, m.solid().leaves[k].bbox, "w"));
    const Model child(Solid(*w.child));
    const Bbox b = m.solid().leaves[k].bbox;
    expect_matches_child(warped, child, w, random_points(50000, b.min, b.max, 2 + k));
  }
}

TEST(Warps, CapsuleTwistedAboutItsOwnAxisIsTheCapsule) {
  const std::string capsule =
      R"({"field": {"skeleton": {"segment": [[0.1, 0.2, -0.8], [0.1, 0.2, 0.8]]},
                    "radius": 0.4, "influence": 0.8, "exponent": 3}})";
  const Model plain = scene(capsule);
  const Model twisted =
      scene(R"({"twist": {"axis": {"point": [0.1, 0.2, 5], "direction": [0, 0, 2]},
      "degrees_per_unit": 135, "child": )" +
            capsule + "}}");
  const std::vector<Vec3> pts = random_points(100000, {-1, -1, -1.7}, {1.2, 1.4, 1.7}, 3);
  const Classification a = plain.classify_counted(pts), b = twisted.classify_counted(pts);
  size_t differ = 0;
  for (size_t i = 0; i < pts.size(); ++i)
    differ += (a.classes[i] == PointClass::kOutside) != (b.classes[i] == PointClass::kOutside);
  EXPECT_EQ(a.uncertain, 0u);
  EXPECT_LE(differ, b.uncertain);
  EXPECT_LE(b.uncertain, 100u);
}

/// Exact class of q against the box [−1/2, 1/2]³ tapered along y over [−1/2, 1/2] from scale 1
/// to 1/2 (s(y) = 3/4 − y/2 inside the range): the preimage (x/s, y, z/s) in rationals.
field::Sign tapered_box_sign(const Vec3& q) {
  using Q = CGAL::Gmpq;
  const Q y(q.y);
  if (y < Q(-1, 2) || y > Q(1, 2)) return field::Sign::kOutside;
  const Q s = Q(3, 4) - y / 2;
  bool on = y == Q(-1, 2) || y == Q(1, 2);
  for (const double c : {q.x, q.z}) {
    const Q v = Q(c) / s;
    if (v < Q(-1, 2) || v > Q(1, 2)) return field::Sign::kOutside;
    on |= v == Q(-1, 2) || v == Q(1, 2);
  }
  return on ? field::Sign::kOn : field::Sign::kInside;
}

TEST(Warps, TaperedBoxIsItsExactRationalClassification) {
  const Model m = scene(R"({"taper": {"axis": {"direction": [0, 1, 0]},
      "range": [-0.5, 0.5], "scale": [1, 0.5],
      "child": {"box": {"min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}}}})");
  std::vector<Vec3> pts = random_points(100000, {-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6}, 4);
  // Points built on the surface: s(y) dyadic at y = k/8, x = ±s/2 exactly.
  for (int k = -4; k <= 4; ++k) {
    const double y = k / 8.0, s = 0.75 - y / 2;
    pts.push_back({s / 2, y, 0.1});
    pts.push_back({-s / 2, y, -0.05});
    pts.push_back({0.01, y, s / 2});
    pts.push_back({s / 2, y, s / 2});  // an edge
  }
  // Their neighbours one ulp off in x and z: preimages a hair inside or outside, never doubles.
  const size_t built = pts.size();
  for (size_t i = built - 36; i < built; ++i)
    for (const double to : {-1.0, 1.0}) {
      pts.push_back({std::nextafter(pts[i].x, to), pts[i].y, pts[i].z});
      pts.push_back({pts[i].x, pts[i].y, std::nextafter(pts[i].z, to)});
    }
  const Classification c = m.classify_counted(pts);
  size_t wrong = 0, on = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const field::Sign want = tapered_box_sign(pts[i]);
    const PointClass got = c.classes[i];
    const bool ok = want == field::Sign::kInside    ? got == PointClass::kInside
                    : want == field::Sign::kOutside ? got == PointClass::kOutside
                                                    : got == PointClass::kFace;
    wrong += !ok;
    on += want == field::Sign::kOn;
  }
  EXPECT_GE(on, 36u);
  EXPECT_EQ(wrong, 0u);
  // Preimages that are not doubles are classified as rational points: nothing is left to the
  // tie rule.
  EXPECT_EQ(c.uncertain, 0u);
}

/// A tapered convex polyhedron (an octahedron with tilted faces) at points within an ulp or two
/// of its surface, whose preimages are rational but not doubles: every class equals the exact
/// plane tests of the rational preimage (x/s, y, z/s), s = 3/4 − y/2, against the child's
/// faces, and none is left to the tie rule.
TEST(Warps, TaperedPolyhedronNearItsSurfaceIsItsExactRationalClassification) {
  using Q = CGAL::Gmpq;
  PolygonMesh octahedron;
  octahedron.vertices = {{0.5, 0.03, 0.01},    {-0.41, -0.02, 0.05}, {0.02, 0.44, -0.03},
                         {-0.03, -0.47, 0.02}, {0.01, 0.04, 0.43},   {0.04, -0.01, -0.46}};
  for (const int sx : {0, 1})
    for (const int sy : {0, 1})
      for (const int sz : {0, 1}) {
        const uint32_t x = sx, y = 2 + sy, z = 4 + sz;
        if ((sx + sy + sz) % 2 == 0)
          octahedron.add_face({x, y, z});
        else
          octahedron.add_face({x, z, y});
      }
  WarpLeaf w = scene(R"({"taper": {"axis": {"direction": [0, 1, 0]},
      "range": [-0.5, 0.5], "scale": [1, 0.5],
      "child": {"box": {"min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}}}})")
                   .solid()
                   .warps[0];
  w.child = std::make_shared<const Solid>(make_leaf(octahedron, "octahedron"));
  const Model m(make_warp_leaf(w, field::forward_box(w, w.child->bbox()), "tapered"));
  const Solid& child = *w.child;
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> pts;
  for (size_t f = 0; f < child.face_count(); ++f) {
    const std::span<const uint32_t> face = child.face(f);
    for (int k = 0; k < 8; ++k) {
      // A point of the face (a fan triangle's barycentric point), mapped forward in doubles.
      const size_t i = 1 + rng() % (face.size() - 2);
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Vec3 &p0 = child.vertices[face[0]], &p1 = child.vertices[face[i]],
                 &p2 = child.vertices[face[i + 1]];
      const Vec3 p = p0 + a * (p1 - p0) + b * (p2 - p0);
      const double s = 0.75 - p.y / 2;
      pts.push_back({p.x * s, p.y, p.z * s});
    }
  }
  size_t wrong = 0, undecided_by_boxes = 0;
  const Classification c = m.classify_counted(pts);
  for (size_t i = 0; i < pts.size(); ++i) {
    const Vec3& q = pts[i];
    const Q s = Q(3, 4) - Q(q.y) / 2;
    const Q P[3] = {Q(q.x) / s, Q(q.y), Q(q.z) / s};
    bool out = false, on = false;
    for (size_t f = 0; f < child.face_count(); ++f) {
      const std::span<const uint32_t> face = child.face(f);
      const Vec3 &a = child.vertices[face[0]], &b = child.vertices[face[1]],
                 &d = child.vertices[face[2]];
      const Q u0 = Q(b.x) - Q(a.x), u1 = Q(b.y) - Q(a.y), u2 = Q(b.z) - Q(a.z);
      const Q v0 = Q(d.x) - Q(a.x), v1 = Q(d.y) - Q(a.y), v2 = Q(d.z) - Q(a.z);
      const Q n0 = u1 * v2 - u2 * v1, n1 = u2 * v0 - u0 * v2, n2 = u0 * v1 - u1 * v0;
      const Q side = n0 * (P[0] - Q(a.x)) + n1 * (P[1] - Q(a.y)) + n2 * (P[2] - Q(a.z));
      out |= side > 0;
      on |= side == 0;
    }
    const PointClass want =
        out ? PointClass::kOutside : (on ? PointClass::kFace : PointClass::kInside);
    const PointClass got = c.classes[i] == PointClass::kFace ? PointClass::kFace : c.classes[i];
    wrong += got != want;
    Vec3 exact;
    undecided_by_boxes += !field::exact_inverse(m.solid().warps[0], q, exact);
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(c.uncertain, 0u);
  EXPECT_GT(undecided_by_boxes, pts.size() / 2);  // the rational path is what decides them
}

TEST(Warps, VoxelsEqualClassificationOfTheirCentres) {
  const Model m = scene(kMixed);
  VoxelizeOptions vo;
  vo.resolution = 40;
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
  EXPECT_GT(set, 500u);
}

TEST(Warps, RaySpansAgreeWithClassificationAlongEachRay) {
  for (const char* text : {kTwistedBar, kMixed}) {
    const Model m = scene(text);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Ray> rays(300);
    for (Ray& r : rays) r = {{3 * u(rng), 3 * u(rng), 3 * u(rng)}, {u(rng), u(rng), u(rng)}};
    const std::vector<RayResult> res = m.cast(rays);
    std::vector<Vec3> pts;
    std::vector<uint8_t> in_span;
    size_t uncertain = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      uncertain += res[i].uncertain;
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
    const Classification c = m.classify_counted(pts);
    size_t disagree = 0, inside = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      disagree += (c.classes[i] != PointClass::kOutside) != (in_span[i] != 0);
      inside += in_span[i];
    }
    EXPECT_EQ(disagree, 0u) << text;
    EXPECT_GT(inside, 50u) << text;
    EXPECT_LE(uncertain, rays.size() / 10) << text;
  }
}

TEST(Warps, RenderShowsTheWarpedPart) {
  const Model m = scene(kMixed);
  CameraOptions co;
  co.width = co.height = 48;
  const Image img = m.render(co);
  size_t seen = 0;
  for (uint32_t id : img.ids) seen += id != Image::kBackgroundId;
  EXPECT_GT(seen, 100u);
  EXPECT_EQ(img.ids[0], Image::kBackgroundId);
}

TEST(Warps, OctreeClaimsFullAndEmptyOnlyWhereDenseSamplingAgrees) {
  const Model m = scene(kMixed);
  OctreeOptions o;
  o.depth = 5;
  const Octree t = m.octree(o);
  const std::array<uint64_t, 3> counts = t.leaf_counts();
  EXPECT_GT(counts[0], 100u);
  EXPECT_GT(counts[1], 5u);
  EXPECT_EQ(test::certified_cells_wrong(m, t, 3), 0u);
}

TEST(Warps, BracketVolumeContainsTheKnownVolumes) {
  // A twist keeps volumes: the twisted bar's is the bar's minus the hole's (a 32-gon prism).
  const Model bar = scene(kTwistedBar);
  const Model child(Solid(*bar.solid().warps[0].child));
  const double want = child.volume().volume;
  VolumeOptions o;
  o.bracket_relative_error = 0.05;
  const VolumeResult v = bar.volume(o);
  EXPECT_EQ(v.method, "bracket");
  EXPECT_LE(std::abs(v.volume - want), v.error_bound);
  // The tapered unit box: ∫ s(y)² dy = ∫_{-1/2}^{1/2} (3/4 − y/2)² dy = 9/16 + 1/48.
  const Model taper = scene(R"({"taper": {"axis": {"direction": [0, 1, 0]},
      "range": [-0.5, 0.5], "scale": [1, 0.5],
      "child": {"box": {"min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5]}}}})");
  VolumeOptions fine;
  fine.bracket_relative_error = 0.02;
  const VolumeResult t = taper.volume(fine);
  EXPECT_LE(std::abs(t.volume - (9.0 / 16 + 1.0 / 48)), t.error_bound);
  EXPECT_LT(t.error_bound, 0.03 * t.volume);
}

TEST(Warps, SameResultsWithOneAndTwoThreads) {
  const Model m = scene(kMixed);
  const std::vector<Vec3> pts = random_points(30000, {-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, 5);
  VoxelizeOptions vo;
  vo.resolution = 32;
  VolumeOptions vol;
  vol.bracket_relative_error = 0.1;
  Classification one, two;
  VoxelGrid g1, g2;
  VolumeResult v1, v2;
  {
    ThreadLimit limit(1);
    one = m.classify_counted(pts);
    g1 = m.voxelize(vo);
    v1 = m.volume(vol);
  }
  {
    ThreadLimit limit(2);
    two = m.classify_counted(pts);
    g2 = m.voxelize(vo);
    v2 = m.volume(vol);
  }
  EXPECT_EQ(one.classes, two.classes);
  EXPECT_EQ(one.uncertain, two.uncertain);
  EXPECT_EQ(g1.bits, g2.bits);
  EXPECT_EQ(v1.volume, v2.volume);
  EXPECT_EQ(v1.error_bound, v2.error_bound);
}

TEST(Warps, BytesAndTransformsKeepTheWarps) {
  const Model m = scene(kMixed);
  const Model back = Model::from_bytes(m.to_bytes());
  ASSERT_EQ(back.solid().warps.size(), 2u);
  const std::vector<Vec3> pts = random_points(20000, {-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}, 8);
  EXPECT_EQ(back.classify(pts), m.classify(pts));
  std::string bytes = m.to_bytes();
  bytes.resize(bytes.size() - 3);
  EXPECT_THROW(Model::from_bytes(bytes), InputError);
  // A rotation and a uniform scale move the warps with their children: the transformed model
  // at M·p is the model at p (up to the points the two count uncertain).
  const Transform t = Transform::trs({2, 2, 2}, {1, 2, 3}, 40, {0.5, -1, 2});
  const Model moved = m.transformed(t);
  std::vector<Vec3> mapped;
  for (const Vec3& p : pts) mapped.push_back(t(p));
  const Classification a = m.classify_counted(pts), b = moved.classify_counted(mapped);
  size_t differ = 0;
  for (size_t i = 0; i < pts.size(); ++i)
    differ += (a.classes[i] == PointClass::kOutside) != (b.classes[i] == PointClass::kOutside);
  EXPECT_LE(differ, a.uncertain + b.uncertain + 2);
  EXPECT_THROW(m.transformed(Transform::scaling({1, 2, 1})), InputError);
}

TEST(Warps, FieldThroughATwistAndInfo) {
  const Model m = scene(R"({"twist": {"axis": {"direction": [0, 0, 1]}, "degrees_per_unit": 90,
      "child": {"field": {"skeleton": {"segment": [[0.3, 0, -1], [0.3, 0, 1]]},
                          "radius": 0.2, "influence": 0.5}}}})");
  // At z = 1 the skeleton has turned by 90° (right hand about +z): (0, 0.3, 1) is on it.
  const Model::FieldValues f = m.field(std::vector<Vec3>{{0, 0.3, 1}, {0.3, 0, 0}, {2, 2, 2}});
  ASSERT_EQ(f.leaves.size(), 1u);
  EXPECT_NEAR(f.values[0].value, 1.0, 1e-12);
  EXPECT_NEAR(f.values[1].value, 1.0, 1e-12);
  EXPECT_EQ(f.values[2].value, 0.0);
  const ModelInfo i = info(m);
  ASSERT_EQ(i.leaves.size(), 1u);
  ASSERT_TRUE(i.leaves[0].warp.has_value());
  EXPECT_EQ(i.leaves[0].warp->kind, WarpKind::kTwist);
  EXPECT_EQ(i.leaves[0].child_leaves, 1u);
}

TEST(Warps, BadNodesAreOneLineErrorsNamingThePath) {
  auto error = [](const std::string& text) {
    try {
      scene(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string box = R"({"box": {"min": [0, 0, 0], "max": [1, 1, 1]}})";
  EXPECT_NE(error(R"({"twist": {"axis": {"direction": [0, 0, 0]}, "degrees_per_unit": 1,
                     "child": )" +
                  box + "}}")
                .find("warps.json: /twist"),
            std::string::npos);
  EXPECT_NE(error(R"({"taper": {"axis": {"direction": [0, 0, 1]}, "range": [0, 1],
                     "scale": [1, -1], "child": )" +
                  box + "}}")
                .find("scale"),
            std::string::npos);
  EXPECT_NE(error(R"({"bend": {"axis": {"direction": [1, 0, 0]}, "toward": [0, 0, 1],
                     "range": [0, 1], "radius": 0.5, "child": )" +
                  box + "}}")
                .find("centre of curvature"),
            std::string::npos);
  EXPECT_NE(error(R"({"twist": {"axis": {"direction": [0, 0, 1]}, "degrees_per_unit": 1}})")
                .find("/twist: missing key 'child'"),
            std::string::npos);
  EXPECT_NE(error(R"({"twist": {"axis": {"direction": [0, 0, 1]}, "degrees_per_unit": 1,
                     "spin": 2, "child": )" +
                  box + "}}")
                .find("/twist/spin: unknown key"),
            std::string::npos);
  const std::string what = error(R"({"bend": {"axis": {"direction": [1, 0, 0]},
      "toward": [1, 0, 0], "range": [0, 1], "radius": 5, "child": )" +
                                 box + "}}");
  EXPECT_NE(what.find("toward"), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos);
}

TEST(Warps, EvaluateMeshesTheWarpFirst) {
  const Model m = scene(kTwistedBar);
  const EvaluateResult e = m.evaluate({.mesh_resolution = 24});
  ASSERT_EQ(e.meshed.size(), 1u);
  EXPECT_GT(e.mesh.face_count(), 0u);
  EXPECT_EQ(e.components, 1);
  EXPECT_EQ(e.genus, 1);  // the bored hole
}

}  // namespace
}  // namespace cover
