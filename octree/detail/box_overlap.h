#pragma once
// Exact predicates between triangles, planes and CLOSED axis-aligned boxes (internal to octree/).
//
// Notation: box B = [lo, hi]³ given as a Bbox (min = lo, max = hi, lo ≤ hi); triangle T = abc,
// not collinear (the BVH drops collinear covering triangles).
// triangle_meets_box, OctantOverlap: the separating-axis theorem with the 13 axes of a triangle
// and a box (Akenine-Möller, "Fast 3D triangle-box overlap testing", 2001): the 3 box normals
// (exact coordinate comparisons), the triangle's normal (the sign at the 8 corners) and the 9
// products e_i × edge (orient2d in the coordinate plane that drops axis i). Every sign is exact
// (solid/predicates.h), and only a STRICT separation counts, so a triangle that merely touches
// the box (a face lying on a box face, a vertex on a corner) meets it.
// triangle_crosses_box, OctantOverlap::crosses: the same axes against the box's INTERIOR, where a
// weak separation (touching allowed) suffices: T misses the open box iff 0 is not inside the
// Minkowski difference B − T, a polytope whose facet normals are among the 13 axes (the e_i ×
// edge axes that are non-zero). A triangle touching the box only on its boundary does not cross
// it. OctantOverlap tests the 8 children of one octree cell against one triangle, sharing the
// signs at their common corners.
// PlaneSide: sign of orient3d(a, b, c, p) for many points p of one box, from a floating-point
// evaluation n·(p − a) with one forward error bound valid for the whole box; orient3d (exact)
// decides whenever the value is inside the bound.

#include <cstdint>

#include "solid/types.h"

namespace cover::detail {

/// True when the closed triangle abc and the closed box intersect (exact).
bool triangle_meets_box(const Vec3& a, const Vec3& b, const Vec3& c, const Bbox& box);

/// True when the closed triangle abc meets the interior of the box (exact). Precondition: the
/// box has positive size on every axis.
bool triangle_crosses_box(const Vec3& a, const Vec3& b, const Vec3& c, const Bbox& box);

/// Side of the plane of abc for points of one closed box: +1 on the side the normal
/// (b − a) × (c − a) points to, −1 on the other, 0 on the plane — the sign of orient3d(a, b, c, p).
class PlaneSide {
 public:
  /// Precondition: every point later passed to sign() lies in `box`.
  PlaneSide(const Vec3& a, const Vec3& b, const Vec3& c, const Bbox& box);

  int sign(const Vec3& p) const;

 private:
  Vec3 a_, b_, c_;
  Vec3 normal_;   ///< (b − a) × (c − a) in floating point
  double bound_;  ///< |computed n·(p − a) − exact value| ≤ bound_ for every p in the box
};

/// triangle_meets_box for the 8 octants of one box, sharing the work: the octants' corners are
/// the 27 points of the lattice planes[0] × planes[1] × planes[2] (per axis: low face, split
/// plane, high face), and every sign at a lattice point is computed once, when first needed.
class OctantOverlap {
 public:
  /// Precondition: planes[a][0] ≤ planes[a][1] ≤ planes[a][2] for every axis a.
  OctantOverlap(const Vec3& a, const Vec3& b, const Vec3& c, const double (&planes)[3][3]);

  /// True when the triangle meets the closed octant o (offset (o&1, (o>>1)&1, (o>>2)&1)).
  bool meets(int o) { return !separated(o, false); }
  /// True when the triangle meets the interior of octant o. Precondition: octant o has positive
  /// size on every axis.
  bool crosses(int o) { return !separated(o, true); }

 private:
  static constexpr int8_t kUnknown = 2;  ///< cache entry not computed yet

  /// True when one of the 13 axes separates the triangle from octant o: strictly (`open` false:
  /// the closed octant) or weakly (`open`: its interior).
  bool separated(int o, bool open);
  int plane_sign(int ix, int iy, int iz);
  int edge_sign(int e, int axis, int iu, int iw);

  Vec3 v_[3];
  double planes_[3][3];
  Vec3 lo_, hi_;  ///< the triangle's box
  PlaneSide plane_;
  int8_t plane_cache_[27];
  int8_t edge_cache_[9][9];  ///< [edge·3 + axis][lattice point of the plane dropping axis]
  int8_t third_cache_[9];    ///< [edge·3 + axis]: side of the third vertex
};

}  // namespace cover::detail
