// The exact fallbacks of predicates.h: the only translation unit of the fast path that includes
// CGAL (compile time, STYLE.md §2).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "covering/predicates.h"

namespace cover::detail {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
}

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // CGAL::orientation(p, q, r, s) is POSITIVE when det[q−p, r−p, s−p] > 0.
  return static_cast<int>(CGAL::orientation(K::Point_3(a.x, a.y, a.z), K::Point_3(b.x, b.y, b.z),
                                            K::Point_3(c.x, c.y, c.z), K::Point_3(d.x, d.y, d.z)));
}

int orient2d_exact(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  return static_cast<int>(CGAL::orientation(K::Point_2(a[u], a[v]), K::Point_2(b[u], b[v]),
                                            K::Point_2(c[u], c[v])));
}

}  // namespace cover::detail
