// The exact fallbacks of predicates.h: CGAL's Epick predicates (interval filter, then exact
// arithmetic) for the orientations, exact rationals for the other polynomials.
#include "solid/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

namespace cover {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Q = CGAL::Exact_rational;

int sign_of(const Q& q) { return static_cast<int>(CGAL::sign(q)); }

K::Point_3 to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

}  // namespace

namespace detail {

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // CGAL::orientation(p, q, r, s) is POSITIVE when det[q−p, r−p, s−p] > 0.
  return static_cast<int>(CGAL::orientation(to_point(a), to_point(b), to_point(c), to_point(d)));
}

int orient2d_exact(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  return static_cast<int>(CGAL::orientation(K::Point_2(a[u], a[v]), K::Point_2(b[u], b[v]),
                                            K::Point_2(c[u], c[v])));
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
