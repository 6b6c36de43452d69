// round_crossing (boolean/assemble.cpp): the nearest doubles of an edge × plane crossing from the
// input doubles in Mpzf, against the exact rational crossing rounded by rational comparisons;
// crossing_point (boolean/intersect.cpp), the one-node lazy crossing, against the same point
// built with the lazy kernel's operators.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "cover/boolean/detail/arrangement.h"

namespace cover::boolean_detail {
namespace {

using ET = K::Exact_kernel::FT;

/// The exact rational rounded to the nearest double, ties to even (independent of the code
/// under test: rational comparisons with the two neighbours' midpoint).
double nearest_rational(const ET& x) {
  double d = CGAL::to_double(x);
  for (int i = 0; i < 4; ++i) {  // to_double is within an ulp; step to the nearest
    const double up = std::nextafter(d, INFINITY), down = std::nextafter(d, -INFINITY);
    if (x > (ET(d) + ET(up)) / 2)
      d = up;
    else if (x < (ET(d) + ET(down)) / 2)
      d = down;
  }
  for (const double n : {std::nextafter(d, INFINITY), std::nextafter(d, -INFINITY)})
    if (x == (ET(d) + ET(n)) / 2) {  // a tie
      uint64_t bits;
      std::memcpy(&bits, &d, sizeof bits);
      if ((bits & 1) != 0) d = n;
    }
  return d;
}

/// The crossing through the lazy kernel's operators (the reference for crossing_point).
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

TEST(CrossingPoint, EqualsTheKernelExpressionAndItsIntervalsHoldIt) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> scale(-30, 30), lattice(-3, 3), kind(0, 2);
  int tried = 0;
  while (tried < 3000) {
    const double s = std::ldexp(1.0, scale(rng));
    const int k = kind(rng);  // 0: random doubles; 1: small lattice (exact ties, double results)
    auto pick = [&] {         // 2: a short segment along the normal (a steep crossing)
      if (k == 1) return Vec3{double(lattice(rng)), double(lattice(rng)), double(lattice(rng))};
      return Vec3{unit(rng) * s, unit(rng) * s, unit(rng) * s};
    };
    const Vec3 p = pick(), q = pick(), r = pick(), a = pick();
    Vec3 b = pick();
    if (k == 2) b = a + 1e-9 * cross(q - p, r - p);  // a short segment along the normal
    const Point pa(a.x, a.y, a.z), pb(b.x, b.y, b.z), pp(p.x, p.y, p.z), pq(q.x, q.y, q.z),
        pr(r.x, r.y, r.z);
    const int sa = CGAL::orientation(pp, pq, pr, pa), sb = CGAL::orientation(pp, pq, pr, pb);
    if (sa * sb >= 0) continue;  // the segment must cross the plane
    ++tried;
    const Point x = crossing_point(a, b, p, q, r);
    const auto box = CGAL::approx(x);  // before any exact evaluation
    const Point reference = lazy_crossing(a, b, p, q, r);
    const auto& e = CGAL::exact(reference);
    for (int c = 0; c < 3; ++c)  // (doubles printed: a failing rational can be huge)
      EXPECT_TRUE(ET(box[c].inf()) <= e[c] && e[c] <= ET(box[c].sup()))
          << tried << " kind " << k << " axis " << c << ": [" << box[c].inf() << ", "
          << box[c].sup() << "] vs " << CGAL::to_double(e[c]);
    EXPECT_TRUE(CGAL::exact(x) == e) << tried;
  }
}

TEST(RoundCrossing, TiesGoToTheEvenNeighbour) {
  // Plane z = 0; the segment from (x0, y, −1) to (x1, y, 1) crosses it at ((x0 + x1)/2, y, 0).
  const Vec3 p{0, 0, 0}, q{1, 0, 0}, r{0, 1, 0};
  const double u = std::ldexp(1.0, -52);
  int decided = 0;
  struct Case {
    double x0, x1, want;
  };
  for (const Case& c : {Case{1, 1 + u, 1},                  // tie between 1 and 1 + u: even 1
                        Case{1 + u, 1 + 2 * u, 1 + 2 * u},  // 1 + u is odd: up
                        Case{-1 - u, -1 - 2 * u, -1 - 2 * u}, Case{3, 3, 3},  // exactly a double
                        Case{0.1, 0.3, 0.2}}) {                               // not a tie
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
