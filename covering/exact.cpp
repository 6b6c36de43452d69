#include "covering/detail/exact.h"

#include <CGAL/Exact_rational.h>

#include <cmath>

namespace cover::detail {
namespace {

using Rat = CGAL::Exact_rational;

// Bounds are applied only when the magnitude sum is in a range where no intermediate can
// underflow into denormals or overflow (then the a-priori bound holds); otherwise exact.
constexpr double kTiny = 1e-250;
constexpr double kHuge = 1e250;
// γ_7 and γ_3 with u = 2^-53, rounded up generously (the magnitude sum is itself rounded).
constexpr double kTripleBound = 1.0e-15;
constexpr double kCrossBound = 5.0e-16;

int sign_of(const Rat& r) { return static_cast<int>(CGAL::sign(r)); }

}  // namespace

int triple_sign(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& d) {
  const double ax = a.x - o.x, ay = a.y - o.y, az = a.z - o.z;
  const double bx = b.x - o.x, by = b.y - o.y, bz = b.z - o.z;
  const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
  const double det = cx * d.x + cy * d.y + cz * d.z;
  const double mag = (std::abs(ay * bz) + std::abs(az * by)) * std::abs(d.x) +
                     (std::abs(az * bx) + std::abs(ax * bz)) * std::abs(d.y) +
                     (std::abs(ax * by) + std::abs(ay * bx)) * std::abs(d.z);
  if (mag > kTiny && mag < kHuge) {
    const double bound = kTripleBound * mag;
    if (det > bound) return 1;
    if (det < -bound) return -1;
  }
  const Rat rax = Rat(a.x) - Rat(o.x), ray = Rat(a.y) - Rat(o.y), raz = Rat(a.z) - Rat(o.z);
  const Rat rbx = Rat(b.x) - Rat(o.x), rby = Rat(b.y) - Rat(o.y), rbz = Rat(b.z) - Rat(o.z);
  return sign_of((ray * rbz - raz * rby) * Rat(d.x) + (raz * rbx - rax * rbz) * Rat(d.y) +
                 (rax * rby - ray * rbx) * Rat(d.z));
}

int cross_axis_sign(const Vec3& a, const Vec3& b, const Vec3& d, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const double eu = a[u] - b[u], ev = a[v] - b[v];
  const double p = eu * d[v], q = ev * d[u];
  const double val = p - q;
  const double mag = std::abs(p) + std::abs(q);
  if (mag > kTiny && mag < kHuge) {
    const double bound = kCrossBound * mag;
    if (val > bound) return 1;
    if (val < -bound) return -1;
  }
  return sign_of((Rat(a[u]) - Rat(b[u])) * Rat(d[v]) - (Rat(a[v]) - Rat(b[v])) * Rat(d[u]));
}

}  // namespace cover::detail
