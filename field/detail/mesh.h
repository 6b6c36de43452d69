#pragma once
// Kernels of mesh skeletons (solid/field_leaf.h kMesh): distances to the triangles through their
// hierarchy, and the exact side of a point. Internal to field/, not installed.
//
// Conventions
//   side        +1 inside M (winding number ≥ 1), 0 on ∂M, −1 outside; exact: on ∂M by exact
//               orientation tests, the winding number by the crossings of the ray from p toward
//               +x, the query point perturbed to p + (0, ε, ε²) (Simulation of Simplicity on the
//               query alone: the ray then misses every edge and vertex, and each crossing counts
//               the sign of its triangle's normal x-component).
//   distances   d² enclosures in Interval_nt<false> (the caller holds the rounding guard),
//               capped: min(d², cap²) for a cap beyond which the potential no longer changes.

#include <CGAL/Gmpq.h>

#include "cover/field/detail/interval.h"
#include "cover/solid/field_leaf.h"

namespace cover::field::detail {

/// An enclosure of min(cap2, min over triangles of d²(p, t)) for every p in the box [lo, hi].
/// \pre rounding guard held; prim.kind == kMesh with its index.
I mesh_d2(const FieldPrimitive& prim, const Vec3& lo, const Vec3& hi, double cap2);

/// The exact side of p (conventions). Sets its own rounding mode (safe under the guard).
int mesh_side(const FieldPrimitive& prim, const Vec3& p);

/// The exact squared distance from p to ∂M (rationals over the triangles an interval pass
/// cannot rule out). Sets its own rounding guard.
CGAL::Gmpq mesh_exact_d2(const FieldPrimitive& prim, const Vec3& p);

/// The squared distance to the nearest triangle and its closest point, in doubles (evaluate()).
double mesh_closest(const FieldPrimitive& prim, const Vec3& p, Vec3& closest);

}  // namespace cover::field::detail
