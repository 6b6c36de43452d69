#pragma once
// Exact signs of small polynomials in double inputs that the ray code needs beyond orient2d /
// orient3d (internal to covering/). Each is a floating-point evaluation with a forward error
// bound (γ_n · Σ|terms|, Higham §3.1) and an exact rational fallback when the bound does not
// separate the value from 0 (or when under/overflow could void the bound).

#include "solid/types.h"

namespace cover::detail {

/// Sign of ((a − o) × (b − o)) · d.
int triple_sign(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& d);

/// Sign of component `axis` of (a − b) × d.
int cross_axis_sign(const Vec3& a, const Vec3& b, const Vec3& d, int axis);

}  // namespace cover::detail
