#pragma once
// Field leaves: skeletal implicit primitives and their global blend (the HybridTree's skeletal
// nodes), as plain data. Their kernels (validation, value, gradient, certified sign, bounds over a
// box) are in field/field.h; a Solid holds them in Solid::fields and a Leaf refers to one by
// Leaf::field.
//
// Conventions
//   primitive i   skeleton S_i, d_i(p) = distance from p to S_i, potential
//                 g_i(d) = (1 − d²/R_i²)^n_i on [0, R_i], 0 beyond (I = 1), weight w_i = ±1;
//                 surface radius r_T,i gives the threshold T_i = g_i(r_T,i) = (1 − r_T²/R²)^n.
//   blend         f(p) = Σ_i w_i·g_i(d_i(p)) (global blending); every primitive of one blend has
//                 the same threshold T (exactly, as rationals: checked by validate_field_leaf).
//                 Inside where f > T, on the surface where f = T, outside where f < T.
//   support       where g_i > 0: the points within R_i of S_i. Outside every positive primitive's
//                 support f ≤ 0 < T, so the union of the positive supports' boxes bounds the
//                 leaf (support boxes, not surface boxes: a blend's surface can leave the boxes
//                 of its primitives' own surfaces).
// Every number is a double, hence an exact rational: the decisions built on them are exact for
// point, segment, triangle and polyline skeletons (f is a rational function of p there).

#include <cstdint>
#include <string_view>
#include <vector>

#include "cover/solid/types.h"

namespace cover {

enum class SkeletonKind : uint8_t { kPoint, kSegment, kTriangle, kPolyline, kCircle };

/// "point", "segment", "triangle", "polyline", "circle".
inline std::string_view to_string(SkeletonKind kind) {
  constexpr std::string_view kNames[] = {"point", "segment", "triangle", "polyline", "circle"};
  return kNames[static_cast<int>(kind)];
}

/// One skeletal primitive.
///   kPoint: points[0]. kSegment: points[0..1]. kTriangle: points[0..2].
///   kPolyline: points[0..k−1], k ≥ 2 (the skeleton is the union of the k − 1 segments, so the
///   distance is the least over them: one primitive, no bulge at the joints).
///   kCircle: points[0] the centre, points[1] the plane's normal (any length, not zero),
///   circle_radius > 0.
struct FieldPrimitive {
  SkeletonKind kind = SkeletonKind::kPoint;
  std::vector<Vec3> points;
  double circle_radius = 0;
  double radius = 0.5;     ///< r_T: the surface's distance from the skeleton alone, 0 < r_T < R
  double influence = 1.0;  ///< R: the support's radius
  int exponent = 2;        ///< n, 2 ≤ n ≤ kMaxFieldExponent
  int weight = 1;          ///< ±1: a negative primitive carves
};

inline constexpr int kMaxFieldExponent = 16;
inline constexpr size_t kMaxPolylinePoints = 1 << 20;

/// A field leaf: the global blend of its primitives (one primitive for a lone `field` node).
struct FieldLeaf {
  std::vector<FieldPrimitive> primitives;
};

/// One primitive's support box: the skeleton's box grown by R (a circle's centre by its radius
/// + R), rounded outward; every point where its g > 0 is inside, whatever its weight.
Bbox primitive_support_box(const FieldPrimitive& prim);

/// The union of the positive primitives' support boxes (the skeleton's box grown by R; a
/// circle's centre by its radius + R), rounded outward: every point where some positive g_i > 0
/// is inside. Empty when no primitive is positive (then the leaf is empty).
Bbox field_support_box(const FieldLeaf& leaf);

}  // namespace cover
