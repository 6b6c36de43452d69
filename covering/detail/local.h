#pragma once
// Result-level classification of a point that lies on the surface of at least one leaf.
// (internal to covering/)
//
// Notation: Q the query point; T_Q the covering triangles (of the leaves whose surface holds Q)
// that contain Q; Π the distinct planes of T_Q (normals n_i, exact rationals). Near Q every leaf's
// membership is constant inside each open cell of the central arrangement of Π, so the result is
// too. Every cell of that arrangement (on the unit sphere: every face of the great-circle
// arrangement) has a vertex ±n_i×n_j, and every cell around a vertex v is a sector between two
// consecutive tangent lines t_a, t_b of the circles through v, so it contains v + δ(±t_a ± t_b)
// for small δ > 0: this enumerates all cells. In a cell with probe direction d the leaf's
// membership is the winding number of Q + εd = signed crossings of the ray Q + t·d (t > 0) with
// the leaf's triangles whose plane misses Q (triangles through Q are left behind at t = 0).
// Then: all cells in → inside; all out → outside; membership a function of the side of one plane
// → face; a function of the planes through one line → edge; else vertex.
//
// A warp's rational preimage P (a taper's w⁻¹(q), field/detail/exact.h) is classified the same
// way with P's exact coordinates: each leaf's membership at P (closed meshes: on a triangle, or
// a probe ray's winding; fields: their exact sign; nested warps: recursively), the tree, and on
// mesh surfaces the arrangement above with rational Q.

#include <optional>
#include <span>
#include <vector>

#include "cover/covering/classify.h"
#include "cover/covering/detail/triangles.h"
#include "cover/covering/prepared.h"
#include "cover/field/field.h"

namespace cover::detail {

/// Precondition: on_surface[l] for at least one leaf; inside[l] holds the (constant) membership
/// of every other leaf. All arithmetic exact (interval filter, then rationals).
PointClass classify_on_surface(const LeafTriangles& tris, const CsgTree& tree, const Vec3& q,
                               std::span<const uint8_t> on_surface,
                               std::span<const uint8_t> inside);

/// The class of warp leaf `warp`'s child (prepared.warp_child) at w⁻¹(q), exactly, where w⁻¹(q)
/// is rational (taper; twist and bend where they are the identity): kInside, kOutside or kOn.
/// nullopt where exactness is out of reach: no rational preimage, or on the way a circle
/// primitive near P, an open mesh leaf, a warp without a rational inverse, or several implicit
/// surfaces (or implicit and mesh surfaces together) through P.
std::optional<field::Sign> exact_warp_member(const Prepared& prepared, size_t warp, const Vec3& q);

}  // namespace cover::detail
