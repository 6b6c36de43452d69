// The exact fallbacks of predicates.h: for the orientations, first a stage that is exact when
// every step of the double evaluation is (error-free transformations: a difference whose TwoSum
// error is 0, a product whose FMA residual is 0), then CGAL's Epick predicates (interval
// filter, then exact arithmetic); exact rationals for the other polynomials.
#include "cover/solid/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

#include <cmath>

namespace cover {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Q = CGAL::Exact_rational;

int sign_of(const Q& q) { return static_cast<int>(CGAL::sign(q)); }

K::Point_3 to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

// The error-free stage. Degenerate input reaches the fallbacks (the filters cannot decide a
// zero), and degenerate input is mostly low-precision (CAD meshes: flat regions, straight
// feature lines), where every difference and product of the evaluation is exact in doubles: then
// the sign of the evaluated determinant is exact, at a few dozen flops instead of CGAL's interval
// and multiprecision stages (about 1 µs; coplanar neighbours made them 5 % of an evaluation).

/// d = a − b; whether that is exact (Knuth's TwoSum error is 0; false on overflow).
bool exact_difference(double a, double b, double& d) {
  d = a - b;
  const double bv = a - d;
  const double av = d + bv;
  return (a - av) + (bv - b) == 0;
}

/// p = a·b; whether that is exact: the FMA residual is 0, and p is far enough from underflow
/// for the residual to be representable (or a factor is 0); false on overflow.
bool exact_product(double a, double b, double& p) {
  p = a * b;
  if (a == 0 || b == 0) return true;
  return std::abs(p) >= 0x1p-960 && std::fma(a, b, -p) == 0;
}

int sign_of(double x) { return (x > 0) - (x < 0); }

}  // namespace

namespace detail {

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // The inline filter's evaluation (predicates.h), every step checked.
  double ad[3], bd[3], cd[3];
  bool exact = true;
  for (int i = 0; i < 3; ++i)
    exact = exact && exact_difference(a[i], d[i], ad[i]) && exact_difference(b[i], d[i], bd[i]) &&
            exact_difference(c[i], d[i], cd[i]);
  double p[6], m[3], t[3], s;
  if (exact && exact_product(bd[0], cd[1], p[0]) && exact_product(cd[0], bd[1], p[1]) &&
      exact_product(cd[0], ad[1], p[2]) && exact_product(ad[0], cd[1], p[3]) &&
      exact_product(ad[0], bd[1], p[4]) && exact_product(bd[0], ad[1], p[5]) &&
      exact_difference(p[0], p[1], m[0]) && exact_difference(p[2], p[3], m[1]) &&
      exact_difference(p[4], p[5], m[2]) && exact_product(ad[2], m[0], t[0]) &&
      exact_product(bd[2], m[1], t[1]) && exact_product(cd[2], m[2], t[2]) &&
      exact_difference(t[0], -t[1], s))
    return -sign_of(s + t[2]);  // the sign of a rounded sum is exact
  // CGAL::orientation(p, q, r, s) is POSITIVE when det[q−p, r−p, s−p] > 0.
  return static_cast<int>(CGAL::orientation(to_point(a), to_point(b), to_point(c), to_point(d)));
}

int orient2d_exact(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  // The inline filter's evaluation (predicates.h), every step checked.
  double x1, y1, x2, y2, l, r;
  if (exact_difference(a[u], c[u], x1) && exact_difference(b[v], c[v], y2) &&
      exact_difference(a[v], c[v], y1) && exact_difference(b[u], c[u], x2) &&
      exact_product(x1, y2, l) && exact_product(y1, x2, r))
    return sign_of(l - r);  // the sign of a rounded difference is exact
  return static_cast<int>(
      CGAL::orientation(K::Point_2(a[u], a[v]), K::Point_2(b[u], b[v]), K::Point_2(c[u], c[v])));
}

int triple_sign_exact(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& d) {
  const Q rax = Q(a.x) - Q(o.x), ray = Q(a.y) - Q(o.y), raz = Q(a.z) - Q(o.z);
  const Q rbx = Q(b.x) - Q(o.x), rby = Q(b.y) - Q(o.y), rbz = Q(b.z) - Q(o.z);
  return sign_of((ray * rbz - raz * rby) * Q(d.x) + (raz * rbx - rax * rbz) * Q(d.y) +
                 (rax * rby - ray * rbx) * Q(d.z));
}

int cross_axis_sign_exact(const Vec3& a, const Vec3& b, const Vec3& d, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  return sign_of((Q(a[u]) - Q(b[u])) * Q(d[v]) - (Q(a[v]) - Q(b[v])) * Q(d[u]));
}

int plane_side_exact(const Vec3& n, double d, const Vec3& v) {
  return sign_of(Q(n.x) * Q(v.x) + Q(n.y) * Q(v.y) + Q(n.z) * Q(v.z) - Q(d));
}

}  // namespace detail

int polygon_orientation(std::span<const Vec3> points, int axis) {
  const int u = axis == 2 ? 0 : axis + 1, w = axis == 0 ? 2 : (axis == 1 ? 0 : 1);
  Q twice_area = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    const Vec3& q = points[i + 1 < points.size() ? i + 1 : 0];
    twice_area += Q(p[u]) * Q(q[w]) - Q(p[w]) * Q(q[u]);
  }
  return sign_of(twice_area);
}

bool all_collinear(std::span<const Vec3> vertices, std::span<const uint32_t> loop) {
  if (loop.empty()) return true;
  const Vec3& a = vertices[loop[0]];
  size_t i = 1;
  while (i < loop.size() && vertices[loop[i]] == a) ++i;
  if (i == loop.size()) return true;
  const K::Point_3 pa = to_point(a), pb = to_point(vertices[loop[i]]);
  for (++i; i < loop.size(); ++i)
    if (!CGAL::collinear(pa, pb, to_point(vertices[loop[i]]))) return false;
  return true;
}

}  // namespace cover
