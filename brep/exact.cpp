// Exact fallbacks for predicates on input doubles (CGAL private to brep/exact.cpp and cap.cpp).
#include <CGAL/Exact_rational.h>

#include "brep/detail/clip_internal.h"

namespace cover::brep::detail {
namespace {

using Q = CGAL::Exact_rational;

int sign_of(const Q& q) { return q > 0 ? 1 : (q < 0 ? -1 : 0); }

}  // namespace

int plane_side_exact(const Vec3& n, double d, const Vec3& v) {
  const Q value = Q(n.x) * Q(v.x) + Q(n.y) * Q(v.y) + Q(n.z) * Q(v.z) - Q(d);
  return sign_of(value);
}

int polygon_orientation(const std::vector<Vec3>& points, int axis) {
  const int u = axis == 2 ? 0 : axis + 1, w = axis == 0 ? 2 : (axis == 1 ? 0 : 1);
  Q twice_area = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    const Vec3& q = points[i + 1 < points.size() ? i + 1 : 0];
    twice_area += Q(p[u]) * Q(q[w]) - Q(p[w]) * Q(q[u]);
  }
  return sign_of(twice_area);
}

}  // namespace cover::brep::detail
