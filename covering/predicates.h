#pragma once
// Exact geometric predicates on double coordinates (CGAL's filtered Epick predicates: a fast
// floating-point filter with an exact fallback). No epsilons anywhere (DESIGN.md §2).
// Every function returns the exact sign −1, 0 or +1.

#include "solid/types.h"

namespace cover {

/// Sign of det[b−a, c−a, d−a] = ((b−a)×(c−a))·(d−a): +1 when d lies on the side the normal of
/// the counter-clockwise triangle abc points to (outside, for an outward face).
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Sign of the 2D orientation of (a, b, c) projected on the coordinate plane that drops `axis`
/// (axis 0: (y, z); 1: (z, x); 2: (x, y)) — i.e. the sign of the `axis` component of
/// (b−a)×(c−a).
int orient2d(const Vec3& a, const Vec3& b, const Vec3& c, int axis);

}  // namespace cover
