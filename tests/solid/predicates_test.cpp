// Exact predicates (solid/predicates.h): sign conventions and exactness where doubles fail.
#include "cover/solid/predicates.h"

#include <CGAL/Exact_rational.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace cover {
namespace {

TEST(Predicates, SignConventions) {
  const Vec3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  EXPECT_EQ(orient3d(o, x, y, z), 1);  // z is on the side of (x−o)×(y−o)
  EXPECT_EQ(orient3d(o, y, x, z), -1);
  EXPECT_EQ(orient3d(o, x, y, {0.3, 0.4, 0}), 0);
  EXPECT_EQ(orient2d(o, y, z, 0), 1);  // x component of y × z
  EXPECT_EQ(orient2d(o, z, x, 1), 1);  // y component of z × x
  EXPECT_EQ(orient2d(o, x, y, 2), 1);  // z component of x × y
  EXPECT_EQ(orient2d(o, y, x, 2), -1);
}

TEST(Predicates, ExactOnNearlyDegenerateInput) {
  // Points on the line y = x with coordinates that are not exactly representable sums:
  // the naive determinant in doubles gets the sign wrong for some of these; the exact one
  // must say 0 for truly collinear points and ±1 for the neighbours.
  const double a = 0.1, b = 0.3;
  for (int i = 1; i < 200; ++i) {
    const double t = i * 0.01;
    const Vec3 p{t, t, 0}, q{a, a, 0}, r{b, b, 0};
    EXPECT_EQ(orient2d(q, r, p, 2), 0);
    EXPECT_EQ(orient2d(q, r, {t, std::nextafter(t, 2.0), 0}, 2), 1);
    EXPECT_EQ(orient2d(q, r, {t, std::nextafter(t, -2.0), 0}, 2), -1);
  }
  // A point one ulp off a plane through three far-apart points.
  const Vec3 p0{1e8, 0, 0}, p1{0, 1e8, 0}, p2{0, 0, 1e8};
  const Vec3 on{1e8 / 4, 1e8 / 4, 1e8 / 2};
  EXPECT_EQ(orient3d(p0, p1, p2, on), 0);
  EXPECT_EQ(orient3d(p0, p1, p2, {on.x, on.y, std::nextafter(on.z, 1e300)}), 1);
}

TEST(Predicates, TripleAndCrossSignsAreExact) {
  const Vec3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  EXPECT_EQ(triple_sign(o, x, y, z), 1);  // (x × y)·z
  EXPECT_EQ(triple_sign(o, y, x, z), -1);
  EXPECT_EQ(triple_sign(o, x, y, {1, 1, 0}), 0);
  EXPECT_EQ(cross_axis_sign(x, o, y, 2), 1);  // z component of x × y
  EXPECT_EQ(cross_axis_sign(y, o, x, 2), -1);
  // d one ulp off the plane spanned by a − o and b − o.
  const Vec3 a{0.1, 0.2, 0.3}, b{0.7, 0.1, 0.5};
  EXPECT_EQ(triple_sign(o, a, b, o), 0);
  const int s = triple_sign(o, a, b, {0, 0, 1e-300});
  EXPECT_EQ(s, triple_sign(o, a, b, z));
  EXPECT_EQ(cross_axis_sign(a, a, z, 0), 0);
}

TEST(Predicates, PlaneSideAndPolygonOrientation) {
  const Vec3 n{1, 1, 1};
  const Vec3 v{1e-30, 1, -1};  // n·v = 1e-30 exactly; in doubles ((1e-30 + 1) − 1) = 0
  EXPECT_EQ(plane_side(n, 1e-30, v), 0);
  EXPECT_EQ(plane_side(n, std::nextafter(1e-30, 1.0), v), -1);
  EXPECT_EQ(plane_side(n, std::nextafter(1e-30, 0.0), v), 1);
  const std::vector<Vec3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_EQ(polygon_orientation(square, 2), 1);
  EXPECT_EQ(polygon_orientation(std::vector<Vec3>(square.rbegin(), square.rend()), 2), -1);
  EXPECT_EQ(polygon_orientation(square, 0), 0);  // seen edge-on
}

TEST(Predicates, AllCollinear) {
  const std::vector<Vec3> v{
      {0, 0, 0}, {0, 0, 0}, {0.1, 0.1, 0.1}, {0.3, 0.3, 0.3}, {0.3, 0.3, std::nextafter(0.3, 1.0)}};
  EXPECT_TRUE(all_collinear(v, std::vector<uint32_t>{}));
  EXPECT_TRUE(all_collinear(v, std::vector<uint32_t>{0, 1}));
  EXPECT_TRUE(all_collinear(v, std::vector<uint32_t>{0, 1, 2, 3}));
  EXPECT_FALSE(all_collinear(v, std::vector<uint32_t>{0, 2, 4}));
}

// The exact fallbacks (expansion arithmetic where the coordinate differences are exact, CGAL
// otherwise) against determinants in exact rationals: points on random planes and lines with
// small-integer, binary-fraction and decimal coordinates (exactly degenerate), the same nudged by
// one ulp, mixed magnitudes (inexact differences) and values near the range limits.
TEST(Predicates, ExactFallbacksAgreeWithRationals) {
  using Q = CGAL::Exact_rational;
  auto sign = [](const Q& q) { return static_cast<int>(CGAL::sign(q)); };
  std::mt19937_64 rng(20261203);
  std::uniform_int_distribution<int> small(-8, 8), kind(0, 5);
  std::uniform_real_distribution<double> unit(-1, 1);
  auto coordinate = [&](int k) {
    switch (k) {
      case 0:
        return static_cast<double>(small(rng));
      case 1:
        return small(rng) / 64.0;
      case 2:
        return std::round(unit(rng) * 1000) / 1000;  // decimals: differences inexact at times
      case 3:
        return unit(rng) * 1e-200;
      case 4:
        return unit(rng) * 1e200;
      default:
        return unit(rng) * std::ldexp(1.0, small(rng) * 8);
    }
  };
  auto nudge = [&](double v) {
    return small(rng) > 4 ? std::nextafter(v, small(rng) > 0 ? 1e308 : -1e308) : v;
  };
  int zeros = 0, zeros2 = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int k = kind(rng);
    // a, b, c random; d = a + s(b − a) + t(c − a) with small rational s, t: on the plane whenever
    // the arithmetic is exact.
    Vec3 p[4];
    for (int i = 0; i < 3; ++i) p[i] = {coordinate(k), coordinate(k), coordinate(k)};
    const double s = small(rng) / 4.0, t = small(rng) / 4.0;
    double q[3];
    for (int a = 0; a < 3; ++a)
      q[a] = nudge(p[0][a] + s * (p[1][a] - p[0][a]) + t * (p[2][a] - p[0][a]));
    p[3] = {q[0], q[1], q[2]};
    Q m[3][3];
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a) m[r][a] = Q(p[r + 1][a]) - Q(p[0][a]);
    const Q det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                  m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                  m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    zeros += sign(det) == 0;
    ASSERT_EQ(detail::orient3d_exact(p[0], p[1], p[2], p[3]), sign(det)) << trial;
    ASSERT_EQ(orient3d(p[0], p[1], p[2], p[3]), sign(det)) << trial;
    // 2D: c on the line through p0 and p1 (when exact), then nudged.
    for (int a = 0; a < 3; ++a) q[a] = nudge(p[0][a] + s * (p[1][a] - p[0][a]));
    const Vec3 c{q[0], q[1], q[2]};
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      const Q d2 = (Q(p[0][u]) - Q(c[u])) * (Q(p[1][w]) - Q(c[w])) -
                   (Q(p[0][w]) - Q(c[w])) * (Q(p[1][u]) - Q(c[u]));
      zeros2 += sign(d2) == 0;
      ASSERT_EQ(detail::orient2d_exact(p[0], p[1], c, axis), sign(d2)) << trial;
      ASSERT_EQ(orient2d(p[0], p[1], c, axis), sign(d2)) << trial;
    }
  }
  EXPECT_GT(zeros, 2000);  // the degenerate cases are exercised
  EXPECT_GT(zeros2, 6000);
}

}  // namespace
}  // namespace cover
