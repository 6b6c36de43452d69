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
// point, segment, triangle and polyline skeletons (f is a rational function of p there), and for
// a mesh skeleton wherever it is the only primitive with g > 0 (then the sign is M's exact side).

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cover/solid/types.h"

namespace cover {

enum class SkeletonKind : uint8_t { kPoint, kSegment, kTriangle, kPolyline, kCircle, kMesh };

/// "point", "segment", "triangle", "polyline", "circle", "mesh".
inline std::string_view to_string(SkeletonKind kind) {
  constexpr std::string_view kNames[] = {"point",    "segment", "triangle",
                                         "polyline", "circle",  "mesh"};
  return kNames[static_cast<int>(kind)];
}

/// The bounding-volume hierarchy of a mesh skeleton's triangles (derived from its points by
/// index_skeleton_mesh; never edited). Node 0 is the root; an inner node's children are
/// node + 1 and `right`; a leaf node (count > 0) holds triangles order[first, first + count).
/// Boxes are exact: the min and max of their triangles' vertex coordinates.
struct SkeletonMeshIndex {
  struct Node {
    Bbox box;
    uint32_t first = 0, count = 0, right = 0;
  };
  std::vector<Node> nodes;
  std::vector<uint32_t> order;  ///< triangle t is points[3t], points[3t + 1], points[3t + 2]
  /// "" when every directed edge (a, b) is matched by as many (b, a) (coordinates compared
  /// exactly): the soup bounds a solid; else the first unmatched edge, as "triangle t: edge
  /// (x, y, z) -> (x, y, z) has no opposite".
  std::string open_edge;
};

/// One skeletal primitive.
///   kPoint: points[0]. kSegment: points[0..1]. kTriangle: points[0..2].
///   kPolyline: points[0..k−1], k ≥ 2 (the skeleton is the union of the k − 1 segments, so the
///   distance is the least over them: one primitive, no bulge at the joints).
///   kCircle: points[0] the centre, points[1] the plane's normal (any length, not zero),
///   circle_radius > 0.
///   kMesh: a closed, consistently oriented triangle soup, points[3t..3t+2] triangle t
///   counter-clockwise seen from outside; M the solid it bounds (winding number ≥ 1). Its d is
///   the pseudo-distance (paper §4.2): r_T + dist(p, ∂M) outside M, max(0, r_T − dist(p, ∂M))
///   inside, so that the primitive alone has the surface ∂M itself (g(r_T) = T) and blends with
///   other primitives round it. `mesh` is the triangles' hierarchy (index_skeleton_mesh).
struct FieldPrimitive {
  SkeletonKind kind = SkeletonKind::kPoint;
  std::vector<Vec3> points;
  double circle_radius = 0;
  double radius = 0.5;     ///< r_T: the surface's distance from the skeleton alone, 0 < r_T < R
  double influence = 1.0;  ///< R: the support's radius
  int exponent = 2;        ///< n, 2 ≤ n ≤ kMaxFieldExponent
  int weight = 1;          ///< ±1: a negative primitive carves
  std::shared_ptr<const SkeletonMeshIndex> mesh;  ///< kMesh only: built from `points`
};

/// The hierarchy of a kMesh primitive's points (call again whenever they change).
std::shared_ptr<const SkeletonMeshIndex> index_skeleton_mesh(const std::vector<Vec3>& points);

inline constexpr int kMaxFieldExponent = 16;
inline constexpr size_t kMaxPolylinePoints = 1 << 20;

/// A field leaf: the global blend of its primitives (one primitive for a lone `field` node).
struct FieldLeaf {
  std::vector<FieldPrimitive> primitives;
};

/// One primitive's support box: the skeleton's box grown by R (a circle's centre by its radius
/// + R; a mesh's box by R − r_T rounded up), rounded outward; every point where its g > 0 is
/// inside, whatever its weight.
Bbox primitive_support_box(const FieldPrimitive& prim);

/// The union of the positive primitives' support boxes (the skeleton's box grown by R; a
/// circle's centre by its radius + R), rounded outward: every point where some positive g_i > 0
/// is inside. Empty when no primitive is positive (then the leaf is empty).
Bbox field_support_box(const FieldLeaf& leaf);

}  // namespace cover
