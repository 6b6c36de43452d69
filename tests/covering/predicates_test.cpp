// Exact predicates (covering/predicates.h): sign conventions and exactness where doubles fail.
#include "covering/predicates.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace
}  // namespace cover
