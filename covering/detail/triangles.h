#pragma once
// Covering triangles of every leaf, in the leaf's OWN orientation (internal to covering/).
// Face f = (v0, v1, ..., vk) is covered by the fan (v0, vi, vi+1), i = 1..k−1 ([Segura2004 §2 Def.
// 5] with the face's first vertex as the covering point). Fan triangles of a non-convex face or of
// a face with false edges overlap with opposite signs, exactly as in the paper's covering.
// Triangles whose three points are collinear (exactly) are dropped: they bound no volume and no
// point is strictly inside their projection.

#include <cstdint>
#include <vector>

#include "cover/solid/solid.h"

namespace cover::detail {

struct CoverTri {
  Vec3 a, b, c;  ///< counter-clockwise seen from outside the leaf
  Bbox box;
};

/// #L+1 offsets: the triangles of leaf l are tris[leaf_start[l] .. leaf_start[l+1]).
struct LeafTriangles {
  std::vector<CoverTri> tris;
  std::vector<uint32_t> leaf_start{0};
};

LeafTriangles covering_triangles(const Solid& solid);

/// True when q lies in the closed triangle abc (exact). Precondition: abc is not degenerate.
bool on_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q);

}  // namespace cover::detail
