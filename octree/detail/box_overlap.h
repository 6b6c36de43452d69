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
// it. crossed_octants tests the 8 children of one octree cell against one triangle at once
// (the octree's lists); OctantOverlap, octant by octant with lazily cached signs, is the
// single-box test and the independent path the tests compare crossed_octants with.
// Edge-axis filter: orient2d(p, q, x) is linear in x, g(x) = (p_w − q_w)(x_u − p_u) +
// (q_u − p_u)(x_w − p_w) (the coefficients' signs exact: one rounded subtraction each), so at
// the 3 × 3 lattice points of the plane dropping an axis it is the sum of two of 6 products,
// computed once per triangle and axis with one bound 1e-15·M for all 9 (M the largest sum of
// the two magnitudes; ≥ 9u, as kPlaneSideErr) in the filter range; orient2d (exact) decides a
// point the bound leaves undecided. An axis whose 9 signs are all strictly the third vertex's
// separates no octant and is dropped. The 27 plane signs come the same way from
// PlaneSide::grid_signs / lattice_masks.
// PlaneSide: sign of orient3d(a, b, c, p) for many points p of one box, from a floating-point
// evaluation n·(p − a) with one forward error bound valid for the whole box; orient3d (exact)
// decides whenever the value is inside the bound.

#include <cstddef>
#include <cstdint>

#include "cover/solid/types.h"

namespace cover::detail {

/// Octant o's low corner in a 3 × 3 × 3 lattice (index (iz·3 + iy)·3 + ix).
inline constexpr int kOctantCorner[8] = {0, 1, 3, 4, 9, 10, 12, 13};

/// Bit i of the result set where any of the bits i + {0, 1, 3, 4, 9, 10, 12, 13} of m is: over
/// a 3 × 3 × 3 lattice's bit mask, bit kOctantCorner[o] says whether any of octant o's 8
/// corners is set.
constexpr uint32_t spread27(uint32_t m) {
  m |= m >> 1;
  m |= m >> 3;
  return m | m >> 9;
}

/// The vector instructions PlaneSide::grid_masks and lattice_masks use. Every level computes
/// the same sums in the same order (IEEE doubles, no contraction: -ffp-contract=off), so every
/// level gives the same signs; the widest the CPU has is used unless use_simd() narrows it.
enum class Simd : int {
  kBaseline = 0,  ///< SSE2 on x86-64 (part of the baseline), scalar elsewhere
  kAvx2 = 1,
  kAvx512 = 2,
};
/// The widest level this CPU supports (detected once).
Simd best_simd();
/// The level in use.
Simd simd();
/// Uses `level`, or best_simd() when the CPU lacks it (for tests comparing the levels).
void use_simd(Simd level);

/// orient3d(r, q, a, b), orient3d(r, q, b, c) and orient3d(r, q, c, a) (exact), the three at
/// once: the sides of the line rq that the triangle abc's edges pass (a segment's crossing test).
void edge_orientations(const Vec3& r, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                       int (&out)[3]);

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

  /// (b − a) × (c − a) in floating point.
  const Vec3& normal() const { return normal_; }

  int sign(const Vec3& p) const {
    const double f = normal_.x * (p.x - a_.x) + normal_.y * (p.y - a_.y) + normal_.z * (p.z - a_.z);
    if (f > bound_) return 1;
    if (f < -bound_) return -1;
    return exact_sign(p);
  }

  /// sign() at the n³ points (xs[i], ys[j], zs[k]), i fastest: out[((k·n + j)·n + i)·stride].
  /// The same doubles as sign() (n·(p − a) summed x, y, z in that order), from 3n products.
  /// Precondition: n ≤ 32.
  void grid_signs(const double* xs, const double* ys, const double* zs, int n, int8_t* out,
                  size_t stride) const;
  /// The same signs as bit masks (bit (k·n + j)·n + i): `pos` where +1, `neg` where −1.
  /// Precondition: n³ ≤ 64.
  void grid_masks(const double* xs, const double* ys, const double* zs, int n, uint64_t& pos,
                  uint64_t& neg) const;
  /// grid_masks for the cells of `cells` (bit c) of a sibling set: cell c's points are
  /// (xs[c & 1][i], ys[(c >> 1) & 1][j], zs[c >> 2][k]), its masks pos[c] and neg[c]. The
  /// same signs, the terms computed once per half. Precondition: n³ ≤ 64.
  void cell_masks(const double* const (&xs)[2], const double* const (&ys)[2],
                  const double* const (&zs)[2], int n, uint8_t cells, uint64_t* pos,
                  uint64_t* neg) const;
  /// The signs at the 27 points of the lattice planes[0] × planes[1] × planes[2] as bit masks
  /// (bit (iz·3 + iy)·3 + ix). Precondition: the lattice lies in the box.
  void lattice_masks(const double (&planes)[3][3], uint32_t& pos, uint32_t& neg) const;

 private:
  int exact_sign(const Vec3& p) const;

  Vec3 a_, b_, c_;
  Vec3 normal_;   ///< (b − a) × (c − a) in floating point
  double bound_;  ///< |computed n·(p − a) − exact value| ≤ bound_ for every p in the box
};

/// The octants among `wanted` (bit o = octant o, offset (o&1, (o>>1)&1, (o>>2)&1) in the lattice
/// planes[0] × planes[1] × planes[2]) whose interior the closed triangle abc meets (exact): the
/// 13 axes per half (box normals), per octant (the plane's signs at the 27 lattice points) and
/// per quadrant of the plane dropping an axis (edge axes), on bit masks. Preconditions:
/// planes[a][0] < planes[a][1] < planes[a][2]; abc not collinear.
uint8_t crossed_octants(const Vec3& a, const Vec3& b, const Vec3& c, const double (&planes)[3][3],
                        uint8_t wanted);
/// The same with the plane's lattice signs given (PlaneSide over the lattice's box,
/// lattice_masks), as a caller that needs them too computes them once.
uint8_t crossed_octants(const Vec3& a, const Vec3& b, const Vec3& c, const double (&planes)[3][3],
                        uint32_t pos, uint32_t neg, uint8_t wanted);

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
  /// The octants among `wanted` (bit o = octant o) whose interior the triangle meets:
  /// detail::crossed_octants on this lattice. Precondition: the octants have positive size on
  /// every axis.
  uint8_t crossed_octants(uint8_t wanted);
  /// The exact plane sign at lattice point (ix, iy, iz), each 0..2.
  int plane_sign(int ix, int iy, int iz) const { return plane_cache_[(iz * 3 + iy) * 3 + ix]; }

 private:
  static constexpr int8_t kUnknown = 2;  ///< cache entry not computed yet

  /// True when one of the 13 axes separates the triangle from octant o: strictly (`open` false:
  /// the closed octant) or weakly (`open`: its interior).
  bool separated(int o, bool open);
  int edge_sign(int e, int axis, int iu, int iw);
  int third_sign(int e, int axis);
  /// True when axis e_axis × edge e can separate no octant. The first call fills that axis's
  /// edge_cache_ row with the filtered signs (kUnknown where the filter cannot decide).
  bool skip(int e, int axis);

  Vec3 v_[3];
  double planes_[3][3];
  Vec3 lo_, hi_;  ///< the triangle's box
  PlaneSide plane_;
  int8_t plane_cache_[27];   ///< [(iz·3 + iy)·3 + ix], all computed by the constructor
  int8_t edge_cache_[9][9];  ///< [edge·3 + axis][lattice point of the plane dropping axis]
  int8_t third_cache_[9];    ///< [edge·3 + axis]: side of the third vertex
  /// [edge·3 + axis]: 1 when that axis can separate no octant (the edge is parallel to it, or
  /// the lattice's rectangle lies strictly on the third vertex's side), 0 when it may.
  int8_t skip_[9];
};

}  // namespace cover::detail
