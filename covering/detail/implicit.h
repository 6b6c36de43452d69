#pragma once
// The one place where a leaf answered by a function of the point — a field leaf
// (solid/field_leaf.h) or a warp leaf (solid/warp_leaf.h) — plugs into the covering kernels
// (internal to covering/). classify, leaf_windings, box_states, cast and render ask these and
// nothing else about such leaves.
//
// Warp leaf w with child C: p is inside iff w⁻¹(p) is inside C. Decisions:
//   point     w⁻¹(p) exact as doubles (field/warp.h exact_inverse: taper mostly, the identity
//             parts of twist and bend): C's own classification there (exact). Otherwise the
//             enclosure B of w⁻¹(p) (inverse_box): C's box state on B (box_states.h) when it
//             is inside or outside. Else, where w⁻¹(p) is rational (taper), C's exact class
//             at that rational point (covering/detail/local.h exact_warp_member). Else the tie
//             rule: C's classification at the rounded w⁻¹(p), counted uncertain. A point with
//             no preimage (bend) is outside.
//   box       C's box state over the enclosure of the world box's preimage; undecided when
//             the box may hold points without a preimage and C's state is inside.
//   ray       certified bisection as for fields (covering/warp_ray.cpp).
//   normal    Jᵀ·n, J the Jacobian of w⁻¹ and n a normal of C's surface near w⁻¹(p) (C's hit
//             nearest to it along the mapped ray direction), turned to face the ray.

#include <atomic>
#include <utility>
#include <vector>

#include "cover/covering/prepared.h"
#include "cover/covering/ray.h"
#include "cover/field/field.h"

namespace cover::detail {

/// Leaf `leaf`'s (is_implicit) membership at q: kInside, kOutside or kOn (on its surface). Never
/// kUndecided: an undecided point takes the tie rule (field leaves: the double evaluation's
/// sign; warp leaves: above) and is counted in `uncertain` when given.
field::Sign implicit_member(const Prepared& prepared, uint32_t leaf, const Vec3& q,
                            std::atomic<size_t>* uncertain = nullptr);

/// Leaf `leaf`'s (is_implicit) three-valued state on the closed box (box_states.h values).
uint8_t implicit_box_state(const Prepared& prepared, uint32_t leaf, const Bbox& box);

/// The crossings of warp leaf `leaf`'s surface along the ray, appended to hits (as
/// field_crossings); returns the pieces it could not certify.
uint32_t warp_crossings(const Prepared& prepared, uint32_t leaf, const Ray& ray,
                        std::vector<RayHit>& hits);

/// The normal an implicit leaf's hit shows: facing the ray (n·d ≤ 0), not unit.
Vec3 implicit_normal(const Prepared& prepared, const RayHit& hit, const Ray& ray);

/// The box of the ray's points for t in [a, b], padded for the rounding of o + t·d.
Bbox piece_box(const Ray& ray, double a, double b);
/// [t0, t1] of the ray inside the closed box (t ≥ 0), padded; empty (t0 > t1) when it misses.
std::pair<double, double> clip(const Ray& ray, const Bbox& box);

}  // namespace cover::detail
