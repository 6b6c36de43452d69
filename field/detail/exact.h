#pragma once
// Exact rational points (CGAL::Gmpq coordinates) for the exact classification of a warp leaf's
// preimages (covering/local.cpp): a taper's w⁻¹(q) at a double q is rational but rarely a double
// point, and its child's class there is decided on the rational point itself. Includes CGAL:
// only translation units that already do include it (field.cpp, warp.cpp, covering/local.cpp).

#include <CGAL/Gmpq.h>

#include "cover/field/closest.h"
#include "cover/field/field.h"
#include "cover/solid/warp_leaf.h"

namespace cover::field::detail {

using QPoint = V3<CGAL::Gmpq>;

/// The sign of f(p) − T at the rational point p: an interval filter over p's enclosure, then
/// exact rationals; kUndecided where a circle primitive's support holds p and the filter cannot
/// decide (as sign() at a double point).
Sign sign_at(const FieldLeaf& leaf, const QPoint& p);

/// w⁻¹(q) exactly, for the warps whose inverse is rational there: taper everywhere, twist and
/// bend where they are the identity (θ = 0). False otherwise (w⁻¹(q) is not rational in general).
bool rational_inverse(const WarpLeaf& w, const QPoint& q, QPoint& out);

/// The closed box of doubles holding p (each coordinate's enclosing interval).
Bbox enclosure(const QPoint& p);

}  // namespace cover::field::detail
