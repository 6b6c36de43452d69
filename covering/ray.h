#pragma once
// Ray casting through a non-evaluated CSG solid ([Segura2004 §6] "Ray-Casting").
//
// A ray o + t·d (t > 0) meets covering triangles; each hit carries its leaf, face and sign
// (+1: leaving the leaf, n·d > 0 for the leaf's outward normal n; −1: entering). Crossing
// decisions are exact: the line is symbolically perturbed, o → o + ε·e_u + ε²·e_w + ε³·e_k
// (k = the axis of d's largest component, u, w the other two), so a ray through an edge or a
// vertex is counted once, consistently for all triangles, and a hit at t = 0 is decided too.
// The winding of leaf L at o is the sum of its hit signs; sweeping the sorted hits with per-leaf
// counters and evaluating the CSG tree on each interval gives the inside spans (Roth 1982).
// Hit parameters t are floating point (for ordering and lengths only, never for decisions).

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "cover/covering/bvh.h"
#include "cover/covering/gwn.h"
#include "cover/covering/prepared.h"
#include "cover/solid/solid.h"

namespace cover {

/// A half-line origin + t·dir, t > 0. Precondition: dir != 0, all coordinates finite.
struct Ray {
  Vec3 origin;
  Vec3 dir;
};

struct RayHit {
  double t = 0;
  uint32_t tri = 0;  ///< triangle index: Bvh::triangle(tri)
  uint32_t leaf = 0;
  uint32_t face = 0;
  int8_t sign = 0;  ///< +1 leaving the leaf, −1 entering it
};

/// An interval of the ray inside the result. `enter` / `exit` index the hits that bound it
/// (kNone: the span starts at the origin / never ends, for unbounded results).
struct Span {
  static constexpr uint32_t kNone = UINT32_MAX;
  double t0 = 0, t1 = 0;
  uint32_t enter = kNone, exit = kNone;
};

struct RayResult {
  std::vector<RayHit> hits;  ///< sorted by t (ties: by leaf, then face, then triangle index)
  std::vector<Span> spans;   ///< disjoint, increasing, non-empty
  /// Field leaves: pieces of the ray where bisection could not certify the crossings (field_spans);
  /// 0 for solids of meshes.
  uint32_t uncertain = 0;
};

/// The first surface point of the result along the ray.
struct FirstHit {
  bool hit = false;
  double t = 0;
  Vec3 normal;  ///< outward normal of the result there (unnormalized, n·dir < 0)
  uint32_t leaf = 0, face = 0;
};

/// The first point of the result seen along the ray within the parameter window [lo, hi]: the
/// start of the first span of cast() that overlaps it, clipped to it.
struct VisibleHit {
  bool hit = false;
  bool cap = false;  ///< the window starts inside the result (lo cuts a span): no surface there
  double t = 0;
  RayHit enter;  ///< when hit && !cap: the hit where the span starts (its last hit at t)
};

/// All hits and the CSG inside spans of one ray. It walks the BVH level by level (walk_batch
/// with one ray), so the node loads of a level (and of a treelet) overlap: about twice as fast
/// as the depth-first walk at 1M triangles (bench_queries BM_CastRay, docs/benchmarks.md).
RayResult cast(const Bvh& bvh, const CsgTree& tree, size_t leaves, const Ray& ray);

/// The same result through the depth-first walk() of the BVH: the independent path that tests
/// compare cast() and the batch cast() against (same hits, same t, same spans).
RayResult cast_depth_first(const Bvh& bvh, const CsgTree& tree, size_t leaves, const Ray& ray);

/// First entry into the result (the start of the first span that does not begin at the origin).
/// At a field leaf's hit (tri Span::kNone) the normal is zero: field_normal() gives it.
FirstHit first_hit(const Bvh& bvh, const RayResult& result);

/// The visible point of `result`'s spans within [lo, hi].
VisibleHit first_visible(const RayResult& result, double lo, double hi);

/// The same as first_visible(cast(bvh, tree, leaves, ray), lo, hi), computed front to back: only
/// the hits up to the visible point are found. Precondition (as for cast()): closed leaves. Falls
/// back to cast() when the origin lies in a leaf's box or the expression contains the point
/// outside every leaf. `outside_in_result`, when given, must be tree.evaluate() with every leaf
/// outside (a per-frame constant that render() computes once instead of once per ray).
VisibleHit first_visible(const Bvh& bvh, const CsgTree& tree, size_t leaves, const Ray& ray,
                         double lo, double hi, std::optional<bool> outside_in_result = {});

struct CastOptions {
  size_t grain = 256;  ///< rays per parallel chunk (results never depend on it)
};

/// Open leaves (Leaf::open): recomputes result.spans (hits sorted as cast() leaves them) with
/// each open leaf's membership on each interval between distinct hit parameters taken from its
/// generalized winding number (gwn_inside) at the interval's midpoint (the last, unbounded
/// interval: half a box diagonal beyond the last hit); closed leaves keep their exact crossing
/// counts. So spans change only at surface hits: a hole's membrane (|w| = 1/2 away from the
/// surface) is not a span end. Used by cast() and render for solids with open leaves.
void open_spans(RayResult& result, const Solid& solid, const GwnForest& forest, const Ray& ray,
                const GwnOptions& options = {});

/// Field leaves (solid/field_leaf.h): the crossings of field leaf `leaf`'s surface along the ray,
/// appended to `hits` (tri and face Span::kNone; sign +1 leaving, −1 entering; alternating, so
/// the leaf's signs sum to its membership at the origin), found by certified interval bisection
/// to 2^-20 of the ray's run through the support box: each t is within that of a crossing of
/// the true ray (covering/field_ray.cpp). Returns the pieces it could not certify (a tangency or
/// a film thinner than a piece, undecided ends).
uint32_t field_crossings(const Solid& solid, uint32_t leaf, const Ray& ray,
                         std::vector<RayHit>& hits);

/// The normal a field or warp leaf's hit shows (as FirstHit::normal: facing the ray; not unit):
/// a field's −∇f at the hit (∇f leaving), a warp's Jᵀ·n (covering/detail/implicit.h).
Vec3 field_normal(const Prepared& prepared, const RayHit& hit, const Ray& ray);

/// Adds every field and warp leaf's crossings to result.hits and sweeps the spans again (open
/// leaves, if any, by open_spans()); adds the uncertain pieces to result.uncertain. Used by
/// cast() and render for solids with such leaves.
void field_spans(RayResult& result, const Prepared& prepared, const Ray& ray);

/// Casts many rays in parallel; results[i] belongs to rays[i]. Open leaves: open_spans(); field
/// leaves: field_spans().
/// \pre every ray has a finite origin and a finite, non-zero direction
/// (Model::cast checks).
std::vector<RayResult> cast(const Prepared& prepared, std::span<const Ray> rays,
                            const CastOptions& options = {});

}  // namespace cover
