#pragma once
// Exact signs of small polynomials in double inputs that the ray code needs beyond orient2d /
// orient3d (internal to covering/). Each is a floating-point evaluation with a forward error
// bound (γ_n · Σ|terms|, Higham §3.1) and an exact rational fallback when the bound does not
// separate the value from 0 (or when under/overflow could void the bound).

#include <cmath>

#include "solid/types.h"

namespace cover::detail {

// Bounds are applied only when the magnitude sum is in a range where no intermediate can
// underflow into denormals or overflow (then the a-priori bound holds); otherwise exact.
inline constexpr double kTiny = 1e-250;
inline constexpr double kHuge = 1e250;
// γ_7 and γ_3 with u = 2^-53, rounded up generously (the magnitude sum is itself rounded).
inline constexpr double kTripleBound = 1.0e-15;
inline constexpr double kCrossBound = 5.0e-16;

/// The exact rational evaluations (exact.cpp), for when the filters below cannot decide.
int triple_sign_exact(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& d);
int cross_axis_sign_exact(const Vec3& a, const Vec3& b, const Vec3& d, int axis);

/// Sign of ((a − o) × (b − o)) · d. The filter is inline because the ray-triangle tests call it
/// for every edge (out of line it was 14% of a render's instructions, callgrind).
inline int triple_sign(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& d) {
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
  return triple_sign_exact(o, a, b, d);
}

/// Sign of component `axis` of (a − b) × d.
inline int cross_axis_sign(const Vec3& a, const Vec3& b, const Vec3& d, int axis) {
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
  return cross_axis_sign_exact(a, b, d, axis);
}

}  // namespace cover::detail
