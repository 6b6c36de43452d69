// The outward float rounding that lets classification compare a double point with float node
// bounds in single precision (covering/detail/float_bounds.h).
#include "cover/covering/detail/float_bounds.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <random>

namespace cover {
namespace {

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
