#pragma once
// Exact geometric predicates on double coordinates. Each returns the exact sign −1, 0 or +1.
// A static floating-point filter (Shewchuk's error bounds, "Adaptive Precision Floating-Point
// Arithmetic and Fast Robust Geometric Predicates", 1997, stage A) answers inline; when it
// cannot, the exact CGAL predicate (Epick: interval filter, then exact arithmetic) decides.
// No epsilons anywhere (DESIGN.md §2).

#include <cmath>

#include "solid/types.h"

namespace cover {

namespace detail {
int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
int orient2d_exact(const Vec3& a, const Vec3& b, const Vec3& c, int axis);
// Below kFilterMin the bound could fail through underflow; above kFilterMax through overflow.
inline constexpr double kFilterMin = 1e-200;
/// Shewchuk's stage-A error factors: orient2d (3 + 16ε)ε, orient3d (7 + 56ε)ε.
inline constexpr double kOrient2dErr = 3.3306690738754716e-16;
inline constexpr double kOrient3dErr = 7.7715611723761027e-16;
inline constexpr double kFilterMax = 1e200;
}  // namespace detail

/// Sign of det[b−a, c−a, d−a] = ((b−a)×(c−a))·(d−a): +1 when d lies on the side the normal of
/// the counter-clockwise triangle abc points to (outside, for an outward face).
inline int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double adx = a.x - d.x, bdx = b.x - d.x, cdx = c.x - d.x;
  const double ady = a.y - d.y, bdy = b.y - d.y, cdy = c.y - d.y;
  const double adz = a.z - d.z, bdz = b.z - d.z, cdz = c.z - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  // Shewchuk's orient3d: det[a−d, b−d, c−d], positive when d is BELOW abc; ours is its negation.
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                           (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                           (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
  const double bound = detail::kOrient3dErr * permanent;
  if (permanent > detail::kFilterMin && permanent < detail::kFilterMax) {
    if (det > bound) return -1;
    if (det < -bound) return 1;
  }
  return detail::orient3d_exact(a, b, c, d);
}

/// Sign of the 2D orientation of (a, b, c) projected on the coordinate plane that drops `axis`
/// (axis 0: (y, z); 1: (z, x); 2: (x, y)) — i.e. the sign of the `axis` component of
/// (b−a)×(c−a).
inline int orient2d(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
  const int u = axis == 2 ? 0 : axis + 1, w = axis == 0 ? 2 : (axis == 1 ? 0 : 1);
  const double left = (a[u] - c[u]) * (b[w] - c[w]);
  const double right = (a[w] - c[w]) * (b[u] - c[u]);
  const double det = left - right;
  const double sum = std::abs(left) + std::abs(right);
  if (sum > detail::kFilterMin && sum < detail::kFilterMax) {
    const double bound = detail::kOrient2dErr * sum;
    if (det > bound) return 1;
    if (det < -bound) return -1;
  }
  return detail::orient2d_exact(a, b, c, axis);
}

}  // namespace cover
