// Exact predicates (covering/predicates.h): sign conventions and exactness where doubles fail;
// the outward float rounding that lets classification compare a double point with float node
// bounds in single precision (covering/detail/float_bounds.h).
#include "covering/predicates.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <random>

#include "covering/detail/float_bounds.h"

namespace cover {
namespace {

TEST(Predicates, SignConventions) {
  const Vec3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  EXPECT_EQ(orient3d(o, x, y, z), 1);   // z is on the side of (x−o)×(y−o)
  EXPECT_EQ(orient3d(o, y, x, z), -1);
  EXPECT_EQ(orient3d(o, x, y, {0.3, 0.4, 0}), 0);
  EXPECT_EQ(orient2d(o, y, z, 0), 1);   // x component of y × z
  EXPECT_EQ(orient2d(o, z, x, 1), 1);   // y component of z × x
  EXPECT_EQ(orient2d(o, x, y, 2), 1);   // z component of x × y
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

TEST(FloatRounding, DownAndUpAreTheNeighbouringFloats) {
  using detail::float_down;
  using detail::float_up;
  // The defining property, for every float f near x: f <= x ⟺ f <= down(x), f >= x ⟺ f >= up(x).
  auto check = [](double x) {
    const float d = float_down(x), u = float_up(x);
    EXPECT_LE(static_cast<double>(d), x) << x;
    EXPECT_GE(static_cast<double>(u), x) << x;
    // No float lies strictly between d and x, or between x and u.
    EXPECT_TRUE(std::isinf(d) || static_cast<double>(std::nextafter(d, INFINITY)) > x) << x;
    EXPECT_TRUE(std::isinf(u) || static_cast<double>(std::nextafter(u, -INFINITY)) < x) << x;
    if (static_cast<double>(static_cast<float>(x)) == x) {
      EXPECT_EQ(d, u) << x;
    }
  };
  for (const double x :
       {0.0, -0.0, 1.0, -1.0, 0.1, -0.1, 1e-40, -1e-40, 1e-46, -1e-46, static_cast<double>(FLT_MAX),
        -static_cast<double>(FLT_MAX), 1e39, -1e39, static_cast<double>(FLT_MIN), 3.0000001, -7.25})
    check(x);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> mant(-1, 1);
  std::uniform_int_distribution<int> exp(-140, 130);
  for (int i = 0; i < 100000; ++i) check(std::ldexp(mant(rng), exp(rng)));
  // Beyond the float range the bounds are FLT_MAX and infinity.
  EXPECT_EQ(float_down(1e39), FLT_MAX);
  EXPECT_EQ(float_up(1e39), INFINITY);
  EXPECT_EQ(float_up(-1e39), -FLT_MAX);
  EXPECT_EQ(float_down(-1e39), -INFINITY);
  // Below the smallest denormal: zero and the smallest denormal.
  EXPECT_EQ(float_down(1e-46), 0.0f);
  EXPECT_EQ(float_up(1e-46), FLT_TRUE_MIN);
  EXPECT_EQ(float_down(-1e-46), -FLT_TRUE_MIN);
}

}  // namespace
}  // namespace cover
