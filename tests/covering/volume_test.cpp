// Covering volume (covering/volume.h): analytic volumes, transforms, exactness decisions.
#include "cover/covering/volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "helpers.h"

namespace cover {
namespace {

Solid leaf(PolygonMesh m) { return make_leaf(std::move(m), "leaf"); }

TEST(Volume, BoxAndTetrahedron) {
  EXPECT_DOUBLE_EQ(volume(leaf(make_box({0, 0, 0}, {1, 2, 3}))).volume, 6.0);
  EXPECT_DOUBLE_EQ(*volume(leaf(make_box({0, 0, 0}, {1, 2, 3}))).area, 22.0);
  EXPECT_DOUBLE_EQ(volume(leaf(test::unit_tetrahedron())).volume, 1.0 / 6.0);
}

TEST(Volume, FrameBoxWithFalseEdges) {
  // 4³ minus the 2×2×4 hole = 48; area: 2·(16 − 4) outer caps + 4·16 sides + 4·8 hole walls.
  const VolumeResult r = volume(leaf(test::frame_box(0, 4, 1, 3)));
  EXPECT_DOUBLE_EQ(r.volume, 48.0);
  EXPECT_DOUBLE_EQ(*r.area, 2 * 12.0 + 64.0 + 32.0);
}

TEST(Volume, CylinderMatchesPrismFormula) {
  const int n = 17;
  const double r = 0.75, h = 2.5;
  const double expected = 0.5 * n * r * r * std::sin(2 * std::numbers::pi / n) * h;
  EXPECT_NEAR(volume(leaf(make_cylinder({1, 2, 3}, {1, 2, 3 + h}, r, n))).volume, expected,
              1e-13 * expected);
}

TEST(Volume, TransformsScaleByDeterminantAndMirrorsStaySolid) {
  PolygonMesh m = make_sphere({0.3, -0.2, 0.1}, 1.0, 20);
  const double base = volume(leaf(m)).volume;
  ASSERT_GT(base, 0);
  PolygonMesh scaled = m;
  apply_transform(Transform::trs({2, 3, 0.5}, {1, 1, 0}, 33, {5, 6, 7}), scaled);
  EXPECT_NEAR(volume(leaf(scaled)).volume, 3.0 * base, 1e-12 * base);
  PolygonMesh mirrored = m;
  apply_transform(Transform::trs({-1, 1, 1}, {0, 0, 1}, 0, {0, 0, 0}), mirrored);
  EXPECT_NEAR(volume(leaf(mirrored)).volume, base, 1e-13 * base);
}

TEST(Volume, ExactnessDecisions) {
  const Solid a = leaf(make_box({0, 0, 0}, {1, 1, 1}));
  const Solid far = leaf(make_box({5, 5, 5}, {6, 7, 8}));
  const Solid touching = leaf(make_box({1, 0, 0}, {2, 1, 1}));
  const Solid overlapping = leaf(make_box({0.5, 0.5, 0.5}, {2, 2, 2}));
  // Disjoint union: volumes and areas add; the summed covering value is the volume too.
  const Solid u = unite({a, far});
  EXPECT_DOUBLE_EQ(volume(u).volume, 7.0);
  EXPECT_DOUBLE_EQ(*volume(u).area, 6.0 + 2 * (2 + 3 + 6));
  EXPECT_DOUBLE_EQ(covering_volume(u), 7.0);
  // Touching union: volume adds, area does not (shared face).
  EXPECT_DOUBLE_EQ(volume(unite({a, touching})).volume, 2.0);
  EXPECT_FALSE(volume(unite({a, touching})).area.has_value());
  // A difference that removes nothing.
  EXPECT_DOUBLE_EQ(volume(subtract({a, far})).volume, 1.0);
  // An intersection of disjoint operands is empty.
  EXPECT_DOUBLE_EQ(volume(intersect({a, far})).volume, 0.0);
  // Everything else is integrated over rays (or refused when --exact is asked for).
  EXPECT_TRUE(covering_inexact_reason(unite({a, overlapping})).has_value());
  EXPECT_EQ(volume(unite({a, overlapping})).method, "rays");
  EXPECT_THROW(volume(complement(a)), NotComputable);  // unbounded
  VolumeOptions exact;
  exact.exact = true;
  EXPECT_THROW(volume(unite({a, overlapping}), exact), NotComputable);
  EXPECT_DOUBLE_EQ(volume(u, exact).volume, 7.0);
  EXPECT_DOUBLE_EQ(volume(a, exact).volume, 1.0);
}

TEST(Volume, RaysMatchAnalyticVolumesOfOverlappingBoxes) {
  const Solid a = leaf(make_box({0, 0, 0}, {1, 1, 1}));
  const Solid b = leaf(make_box({0.5, 0.5, 0.5}, {2, 2, 2}));
  const Solid c = leaf(make_box({-1, 0.25, 0.25}, {0.75, 0.75, 3}));
  struct Case {
    Solid s;
    double expected;
  };
  // |A∩B| = 0.125, |A∩C| = 0.75·0.5·0.75, |B∩C| = 0.25·0.25·1.5, |A∩B∩C| = 0.25·0.25·0.5.
  const double ab = 0.125, ac = 0.75 * 0.5 * 0.75, bc = 0.25 * 0.25 * 1.5, abc = 0.25 * 0.25 * 0.5;
  const double va = 1, vb = 3.375, vc = 1.75 * 0.5 * 2.75;
  const std::vector<Case> cases = {
      {unite({a, b}), va + vb - ab},
      {intersect({a, b}), ab},
      {subtract({a, b}), va - ab},
      {unite({subtract({a, b}), c}), (va - ab) + vc - (ac - abc)},
      {intersect({unite({a, b}), c}), ac + bc - abc},
  };
  for (const Case& k : cases) {
    const VolumeResult r = volume(k.s);
    EXPECT_EQ(r.method, "rays");
    EXPECT_NEAR(r.volume, k.expected, 1e-4 * k.expected);
    EXPECT_LE(r.error_bound, 1e-4 * r.volume);
    EXPECT_NEAR(r.volume, k.expected, std::max(r.error_bound, 1e-12));
  }
}

TEST(Volume, RayIdentityUnionPlusIntersection) {
  // vol(A∪B) + vol(A∩B) = vol(A) + vol(B) for two overlapping spheres.
  const Solid a = leaf(make_sphere({0, 0, 0}, 1.0, 24));
  const Solid b = leaf(make_sphere({0.7, 0.2, 0.1}, 0.8, 20));
  const VolumeResult u = volume(unite({a, b})), i = volume(intersect({a, b}));
  const double va = volume(a).volume, vb = volume(b).volume;
  EXPECT_NEAR(u.volume + i.volume, va + vb, u.error_bound + i.error_bound + 1e-12);
  EXPECT_NEAR(u.volume + i.volume, va + vb, 1e-4 * (va + vb));
}

TEST(Volume, SelfIntersectingLeafUsesRaysAndNonzeroRule) {
  PolygonMesh m = make_box({0, 0, 0}, {2, 2, 2});
  const PolygonMesh b = make_box({1, 1, 1}, {3, 3, 3});
  for (Vec3 v : b.vertices) m.vertices.push_back(v);
  for (size_t f = 0; f < b.face_count(); ++f) {
    std::vector<uint32_t> loop(b.face(f).begin(), b.face(f).end());
    for (uint32_t& v : loop) v += 8;
    m.add_face(loop);
  }
  // Two overlapping shells in one leaf: the union under the nonzero rule, 8 + 8 − 1.
  const VolumeResult r = volume(leaf(m));
  EXPECT_EQ(r.method, "rays");
  EXPECT_NEAR(r.volume, 15.0, 15e-4);
}

TEST(Volume, SameWithOneAndTwoThreads) {
  Solid s = leaf(make_sphere({0.1, 0.2, 0.3}, 2.0, 300));
  double v1, v2;
  {
    ThreadLimit limit(1);
    v1 = covering_volume(s);
  }
  {
    ThreadLimit limit(2);
    v2 = covering_volume(s);
  }
  EXPECT_EQ(v1, v2);
}

}  // namespace
}  // namespace cover
