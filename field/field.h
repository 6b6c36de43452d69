#pragma once
// Kernels of field leaves (solid/field_leaf.h): validation, support box, value and gradient,
// the certified sign of f − T at a point, and a sound enclosure of f − T over a box.
//
// Exactness ladder of sign() (docs/design.md "Fields"): an outward-rounded interval evaluation
// (CGAL::Interval_nt) decides almost every point; where its enclosure of f − T contains 0 the
// point is decided exactly in rationals (CGAL::Gmpq) for point, segment, triangle and polyline
// skeletons: f is a rational function of the point there (squared distances to those skeletons
// are rational; the potential is a polynomial in d²), so points exactly on the surface are found
// (kOn). A circle skeleton's distance needs a square root: there the interval enclosure, refined
// by nothing, is the answer, and an undecided point is kUndecided. A mesh skeleton's
// pseudo-distance needs one too, except where it is constant (on ∂M, or beyond its cap) or the
// only term (then M's exact side decides: field/detail/mesh.h): kUndecided only where it blends
// with other terms and the interval cannot decide.
// Distances use the closest point of each skeleton (Ericson, Real-Time Collision Detection
// §5.1): segment by the clamped projection parameter, triangle by its Voronoi regions.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cover/solid/field_leaf.h"
#include "cover/solid/types.h"

namespace cover::field {

/// "" when `leaf` is valid, else its first problem as "primitive i: ..." (solid/field_leaf.h
/// lists the rules: at least one primitive; finite coordinates within ±kMaxCoordinate;
/// 0 < r_T < R < ∞; 2 ≤ n ≤ kMaxFieldExponent; weight ±1; point counts per kind; segments and
/// polyline pieces of positive length; triangles not collinear; circles with a non-zero normal
/// and a finite radius > 0; the same threshold T for every primitive, compared exactly).
std::string validate(const FieldLeaf& leaf);
/// validate() without the one-threshold rule: a blend whose primitives a transform rescaled
/// (their r_T, R rounded apart) keeps its first primitive's threshold (solid/field_leaf.h), and
/// the solid format (io/serialize.h) carries it as it is.
std::string validate_placed(const FieldLeaf& leaf);

/// The union of the positive primitives' support boxes (solid/field_leaf.h field_support_box).
Bbox support_box(const FieldLeaf& leaf);

/// The threshold T = (1 − r_T²/R²)^n of the leaf (its first primitive's), nearest double.
double threshold(const FieldLeaf& leaf);

/// f(p) and ∇f(p) in doubles (the `cover field` query; not a decision).
struct FieldValue {
  double value = 0;
  Vec3 gradient;
};
FieldValue evaluate(const FieldLeaf& leaf, const Vec3& p);

/// Sign of f(p) − T.
enum class Sign : int8_t { kOutside = -1, kOn = 0, kInside = 1, kUndecided = 2 };

/// The certified sign at p (ladder above). Never wrong; kUndecided only for leaves with a circle
/// primitive or a blended mesh skeleton. \pre p finite.
Sign sign(const FieldLeaf& leaf, const Vec3& p);

/// The exact sign in rationals alone (the independent reference path of the tests).
/// \pre the leaf has no circle primitive; kUndecided where a blended mesh skeleton's potential
/// is irrational.
Sign sign_exact(const FieldLeaf& leaf, const Vec3& p);

/// True when the leaf's decisions are exact everywhere (no circle primitive, no mesh skeleton in a
/// blend of several primitives).
bool exact(const FieldLeaf& leaf);

/// A sound enclosure [lo, hi] of f(p) − T for every p in the closed box (interval arithmetic,
/// outward rounding). lo > 0: the box is inside; hi < 0: outside.
struct Range {
  double lo = 0, hi = 0;
};
Range bound(const FieldLeaf& leaf, const Bbox& box);
/// The same summing only `primitives` (indices into leaf.primitives): sound when every other
/// primitive's support misses the box (rays pass the ones whose support box they cross).
Range bound(const FieldLeaf& leaf, std::span<const uint32_t> primitives, const Bbox& box);

}  // namespace cover::field
