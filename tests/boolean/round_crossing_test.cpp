// round_crossing (boolean/assemble.cpp): the nearest doubles of an edge × plane crossing from the
// input doubles in Mpzf, against the exact rational crossing rounded by rational comparisons.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "boolean/detail/arrangement.h"

namespace cover::boolean_detail {
namespace {

using ET = K::Exact_kernel::FT;

/// The exact rational rounded to the nearest double, ties to even (independent of the code
/// under test: rational comparisons with the two neighbours' midpoint).
double nearest_rational(const ET& x) {
  double d = CGAL::to_double(x);
  for (int i = 0; i < 4; ++i) {  // to_double is within an ulp; step to the nearest
    const double up = std::nextafter(d, INFINITY), down = std::nextafter(d, -INFINITY);
    if (x > (ET(d) + ET(up)) / 2) d = up;
    else if (x < (ET(d) + ET(down)) / 2) d = down;
  }
  for (const double n : {std::nextafter(d, INFINITY), std::nextafter(d, -INFINITY)})
    if (x == (ET(d) + ET(n)) / 2) {  // a tie
      uint64_t bits;
      std::memcpy(&bits, &d, sizeof bits);
      if ((bits & 1) != 0) d = n;
    }
  return d;
}

/// The lazy crossing as intersect.cpp builds it, and the exact one in rationals.
Point lazy_crossing(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r) {
  const Point pa(a.x, a.y, a.z), pb(b.x, b.y, b.z), pp(p.x, p.y, p.z), pq(q.x, q.y, q.z),
      pr(r.x, r.y, r.z);
  const K::Vector_3 n = CGAL::cross_product(pq - pp, pr - pp);
  const K::FT da = n * (pa - pp), db = n * (pb - pp);
  return pa + (pb - pa) * (da / (da - db));
}

void expect_rounds(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r,
                   int& decided) {
  const Point x = lazy_crossing(a, b, p, q, r);
  Vec3 out;
  if (!round_crossing(a, b, p, q, r, CGAL::approx(x), out)) return;  // the exact path instead
  ++decided;
  const auto& e = CGAL::exact(x);
  EXPECT_EQ(out.x, nearest_rational(e.x()));
  EXPECT_EQ(out.y, nearest_rational(e.y()));
  EXPECT_EQ(out.z, nearest_rational(e.z()));
}

TEST(RoundCrossing, RandomCrossingsRoundAsTheExactRationals) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> scale(-20, 20);
  int decided = 0, tried = 0;
  while (tried < 3000) {
    const double s = std::ldexp(1.0, scale(rng));
    auto pick = [&] { return Vec3{unit(rng) * s, unit(rng) * s, unit(rng) * s}; };
    const Vec3 p = pick(), q = pick(), r = pick(), a = pick(), b = pick();
    const Vec3 n = cross(q - p, r - p);
    if ((dot(n, a - p) > 0) == (dot(n, b - p) > 0)) continue;  // the segment must cross
    ++tried;
    expect_rounds(a, b, p, q, r, decided);
  }
  EXPECT_GT(decided, 2900);  // the Mpzf path, not the fallback, decides nearly all of them
}

TEST(RoundCrossing, TiesGoToTheEvenNeighbour) {
  // Plane z = 0; the segment from (x0, y, −1) to (x1, y, 1) crosses it at ((x0 + x1)/2, y, 0).
  const Vec3 p{0, 0, 0}, q{1, 0, 0}, r{0, 1, 0};
  const double u = std::ldexp(1.0, -52);
  int decided = 0;
  struct Case {
    double x0, x1, want;
  };
  for (const Case& c : {Case{1, 1 + u, 1},                    // tie between 1 and 1 + u: even 1
                        Case{1 + u, 1 + 2 * u, 1 + 2 * u},   // 1 + u is odd: up
                        Case{-1 - u, -1 - 2 * u, -1 - 2 * u},
                        Case{3, 3, 3},                        // exactly a double
                        Case{0.1, 0.3, 0.2}}) {               // not a tie
    const Vec3 a{c.x0, 0.5, -1}, b{c.x1, 0.5, 1};
    const Point x = lazy_crossing(a, b, p, q, r);
    Vec3 out;
    ASSERT_TRUE(round_crossing(a, b, p, q, r, CGAL::approx(x), out));
    ++decided;
    EXPECT_EQ(out.x, nearest_rational(CGAL::exact(x).x())) << c.x0 << " " << c.x1;
    if (c.x0 != 0.1) {
      EXPECT_EQ(out.x, c.want);
    }
    EXPECT_EQ(out.y, 0.5);
    EXPECT_EQ(out.z, 0.0);
  }
  // A tilted plane, z = x: the vertical segment at x = 1 + u crosses it at z = 1 + u.
  expect_rounds({1 + u, 0.25, 0}, {1 + u, 0.25, 2 + 4 * u}, {0, 0, 0}, {1, 0, 1}, {0, 1, 0},
                decided);
  EXPECT_EQ(decided, 6);
}

}  // namespace
}  // namespace cover::boolean_detail
