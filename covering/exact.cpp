#include "covering/detail/exact.h"

#include <CGAL/Exact_rational.h>

#include <cmath>

namespace cover::detail {
namespace {

using Rat = CGAL::Exact_rational;

int sign_of(const Rat& r) { return static_cast<int>(CGAL::sign(r)); }

}  // namespace

int triple_sign_exact(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& d) {
  const Rat rax = Rat(a.x) - Rat(o.x), ray = Rat(a.y) - Rat(o.y), raz = Rat(a.z) - Rat(o.z);
  const Rat rbx = Rat(b.x) - Rat(o.x), rby = Rat(b.y) - Rat(o.y), rbz = Rat(b.z) - Rat(o.z);
  return sign_of((ray * rbz - raz * rby) * Rat(d.x) + (raz * rbx - rax * rbz) * Rat(d.y) +
                 (rax * rby - ray * rbx) * Rat(d.z));
}

int cross_axis_sign_exact(const Vec3& a, const Vec3& b, const Vec3& d, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  return sign_of((Rat(a[u]) - Rat(b[u])) * Rat(d[v]) - (Rat(a[v]) - Rat(b[v])) * Rat(d[u]));
}

}  // namespace cover::detail
