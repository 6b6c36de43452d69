// Exact predicates (solid/predicates.h): sign conventions and exactness where doubles fail.
#include "solid/predicates.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

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
  const std::vector<Vec3> v{{0, 0, 0}, {0, 0, 0}, {0.1, 0.1, 0.1}, {0.3, 0.3, 0.3},
                            {0.3, 0.3, std::nextafter(0.3, 1.0)}};
  EXPECT_TRUE(all_collinear(v, std::vector<uint32_t>{}));
  EXPECT_TRUE(all_collinear(v, std::vector<uint32_t>{0, 1}));
  EXPECT_TRUE(all_collinear(v, std::vector<uint32_t>{0, 1, 2, 3}));
  EXPECT_FALSE(all_collinear(v, std::vector<uint32_t>{0, 2, 4}));
}

}  // namespace
}  // namespace cover
