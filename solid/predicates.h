#pragma once
// Exact geometric predicates on double coordinates, shared by every module. Each returns the
// exact sign −1, 0 or +1 of a polynomial in the input doubles. No epsilons anywhere
// (docs/design.md#exactness).
//
// Filter scheme: the polynomial is evaluated in doubles next to the sum M of the magnitudes of
// its terms; an a-priori forward error bound err·M (the error factors below) decides the sign
// when the value lies outside [−err·M, err·M]. The bound holds only while no intermediate can
// underflow into denormals or overflow, i.e. for M in (kFilterMin, kFilterMax); otherwise, and
// whenever the bound does not separate the value from 0, the exact fallback (predicates.cpp:
// for the orientations an error-free re-evaluation, exact when every difference and product is,
// then CGAL's Epick predicates; exact rationals for the others) decides. The filters are inline
// because the hot loops (ray–triangle tests, octree cells) call them per edge.
//
// The error factors, with u = 2⁻⁵³ and γ_n = nu/(1 − nu) (Higham §3.1):
//   orient2d, orient3d   Shewchuk's stage-A bounds ("Adaptive Precision Floating-Point
//                        Arithmetic and Fast Robust Geometric Predicates", 1997): (3 + 16u)u and
//                        (7 + 56u)u times the permanent
//   triple_sign          γ_7, rounded up generously (M is itself rounded)
//   cross_axis_sign      γ_3, rounded up likewise
//   plane_side           four roundings of a sum of four terms plus the product roundings:
//                        ≤ 5u·M(1 + 5u); 1e-15 (> 9u) also covers the rounding of M
//   kPlaneBoxErr         octree/'s PlaneSide: one bound for all points of a box, 8u·Σ P_i|d_i|
//                        doubled for the rounding of the bound (octree/box_overlap.cpp)

#include <cmath>
#include <cstdint>
#include <span>

#include "cover/solid/types.h"

namespace cover {

namespace detail {

/// The range of magnitude sums M in which the error factors below are valid bounds.
inline constexpr double kFilterMin = 1e-200;
inline constexpr double kFilterMax = 1e200;
inline constexpr double kOrient2dErr = 3.3306690738754716e-16;
inline constexpr double kOrient3dErr = 7.7715611723761027e-16;
inline constexpr double kTripleErr = 1.0e-15;
inline constexpr double kCrossErr = 5.0e-16;
inline constexpr double kPlaneSideErr = 1.0e-15;
inline constexpr double kPlaneBoxErr = 0x1p-49;  // 16u

/// True when a magnitude sum lies where the error factors hold.
inline bool in_filter_range(double magnitude) {
  return magnitude > kFilterMin && magnitude < kFilterMax;
}

/// The filter: the sign of `value` when the bound err·magnitude separates it from 0 (and the
/// magnitude is in range), else 0, "undecided" (the caller then asks the exact predicate).
inline int filter_sign(double value, double magnitude, double err) {
  if (!in_filter_range(magnitude)) return 0;
  const double bound = err * magnitude;
  return value > bound ? 1 : (value < -bound ? -1 : 0);
}

/// The exact fallbacks (predicates.cpp), for when the filters cannot decide.
int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
int orient2d_exact(const Vec3& a, const Vec3& b, const Vec3& c, int axis);
int triple_sign_exact(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& d);
int cross_axis_sign_exact(const Vec3& a, const Vec3& b, const Vec3& d, int axis);
int plane_side_exact(const Vec3& n, double d, const Vec3& v);

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
  if (const int s = detail::filter_sign(det, permanent, detail::kOrient3dErr)) return -s;
  return detail::orient3d_exact(a, b, c, d);
}

/// orient2d's filter alone: the exact sign where the filter decides it, else 0 (zero or
/// undecided). For filters that only need to prove strict signs: a 0 makes them give up.
inline int orient2d_strict(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
  const int u = axis == 2 ? 0 : axis + 1, w = axis == 0 ? 2 : (axis == 1 ? 0 : 1);
  const double left = (a[u] - c[u]) * (b[w] - c[w]);
  const double right = (a[w] - c[w]) * (b[u] - c[u]);
  return detail::filter_sign(left - right, std::abs(left) + std::abs(right), detail::kOrient2dErr);
}

/// Sign of the 2D orientation of (a, b, c) projected on the coordinate plane that drops `axis`
/// (axis 0: (y, z); 1: (z, x); 2: (x, y)) — i.e. the sign of the `axis` component of
/// (b−a)×(c−a).
inline int orient2d(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
  if (const int s = orient2d_strict(a, b, c, axis)) return s;
  return detail::orient2d_exact(a, b, c, axis);
}

/// Sign of ((a − o) × (b − o)) · d.
inline int triple_sign(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& d) {
  const double ax = a.x - o.x, ay = a.y - o.y, az = a.z - o.z;
  const double bx = b.x - o.x, by = b.y - o.y, bz = b.z - o.z;
  const double cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
  const double det = cx * d.x + cy * d.y + cz * d.z;
  const double mag = (std::abs(ay * bz) + std::abs(az * by)) * std::abs(d.x) +
                     (std::abs(az * bx) + std::abs(ax * bz)) * std::abs(d.y) +
                     (std::abs(ax * by) + std::abs(ay * bx)) * std::abs(d.z);
  if (const int s = detail::filter_sign(det, mag, detail::kTripleErr)) return s;
  return detail::triple_sign_exact(o, a, b, d);
}

/// Sign of component `axis` of (a − b) × d.
inline int cross_axis_sign(const Vec3& a, const Vec3& b, const Vec3& d, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const double eu = a[u] - b[u], ev = a[v] - b[v];
  const double p = eu * d[v], q = ev * d[u];
  const double val = p - q;
  const double mag = std::abs(p) + std::abs(q);
  if (const int s = detail::filter_sign(val, mag, detail::kCrossErr)) return s;
  return detail::cross_axis_sign_exact(a, b, d, axis);
}

/// Sign of n·v − d: +1 on the side n points to.
inline int plane_side(const Vec3& n, double d, const Vec3& v) {
  const double px = n.x * v.x, py = n.y * v.y, pz = n.z * v.z;
  const double value = ((px + py) + pz) - d;
  const double mag = std::abs(px) + std::abs(py) + std::abs(pz) + std::abs(d);
  if (const int s = detail::filter_sign(value, mag, detail::kPlaneSideErr)) return s;
  return detail::plane_side_exact(n, d, v);
}

/// Sign of the signed area of the closed polygon `points` (in order) projected on the coordinate
/// plane that drops `axis` (as orient2d): +1 when counter-clockwise there. Exact rationals only.
int polygon_orientation(std::span<const Vec3> points, int axis);

/// True when the points vertices[loop[i]] lie on one line. Fewer than three distinct points
/// (coincident coordinates count once) are collinear. Precondition: every loop[i] <
/// vertices.size().
bool all_collinear(std::span<const Vec3> vertices, std::span<const uint32_t> loop);

}  // namespace cover
