#pragma once
// Kernels of warp leaves (solid/warp_leaf.h holds the data and its conventions): the frame,
// validation, the map w and its inverse in doubles, the inverse's Jacobian, and sound
// enclosures (outward-rounded interval arithmetic, CGAL::Interval_nt; sine and cosine from the
// C library widened by 4 ulps, whose documented error is ≤ 1 ulp) of w over a box and of w⁻¹
// over a box. Taper's inverse is rational: exact_inverse() computes it in CGAL::Gmpq.

#include <string>

#include "cover/solid/types.h"
#include "cover/solid/warp_leaf.h"

namespace cover::field {

/// Sets w.frame from w.direction and w.toward (solid/warp_leaf.h): e1 = direction/|direction|,
/// e2 = toward minus its e1 part, normalized (for twist and taper, when toward is parallel to
/// the axis, any unit vector ⊥ e1), e0 = e2 × e1 normalized. "" or the problem ("axis direction
/// is zero or not finite", "bend: toward is parallel to the axis").
std::string make_frame(WarpLeaf& w);

/// "" when w's parameters are valid for a child whose box is `child_box` (finite, non-empty),
/// else the first problem, one line naming the key ("taper: scale must be > 0 (got -1)"):
/// finite numbers; |degrees_per_unit| ≤ 1e6; range[0] < range[1]; taper scales in (0, 1e6];
/// bend radius > 0 with (range[1] − range[0])/radius ≤ π, and the child's box entirely on the
/// near side of the centre of curvature (local z < radius everywhere on the box, checked
/// soundly: "bend: the child reaches the centre of curvature (radius R, child extends to z = Z)").
/// \pre make_frame(w) succeeded.
std::string validate(const WarpLeaf& w, const Bbox& child_box);

/// w(p) in doubles (tests, meshes of warped children).
Vec3 forward(const WarpLeaf& w, const Vec3& p);
/// w⁻¹(q) in doubles. Bend: a point outside the image of the half-space z < 1/k gives
/// {NaN, NaN, NaN}.
Vec3 inverse(const WarpLeaf& w, const Vec3& q);

/// Row i: the gradient of the i-th coordinate of w⁻¹ at q (doubles). A child field f gives the
/// warped field f∘w⁻¹ with gradient Jᵀ·∇f(w⁻¹(q)); a child surface normal n at w⁻¹(q) maps to
/// Jᵀ·n (not unit). Undefined (NaN) where inverse() is.
struct Mat3 {
  Vec3 row[3];
};
Mat3 inverse_jacobian(const WarpLeaf& w, const Vec3& q);

/// A sound enclosure of w(box): every w(p), p in the closed box, is inside. The leaf's box is
/// forward_box(w, child's box).
Bbox forward_box(const WarpLeaf& w, const Bbox& box);

/// A sound enclosure of the preimage of a closed world box.
struct InverseBox {
  Bbox box;              ///< encloses w⁻¹(q) for every q of the world box that has a preimage
  bool none = false;     ///< no point of the world box has a preimage (bend): box is empty
  bool partial = false;  ///< some points of the world box may have no preimage (bend)
};
InverseBox inverse_box(const WarpLeaf& w, const Bbox& world);

/// The exact preimage of q when it is a point of doubles: true and `out` set when every
/// coordinate of w⁻¹(q) (computed in rationals for taper; for twist and bend only where the
/// angle is exactly 0, i.e. q's local y is 0 for twist or in the unbent part for bend, else
/// false) is exactly a double.
bool exact_inverse(const WarpLeaf& w, const Vec3& q, Vec3& out);

}  // namespace cover::field
