#include "cover/covering/detail/triangles.h"

#include "cover/solid/predicates.h"

namespace cover::detail {

LeafTriangles covering_triangles(const Solid& solid) {
  LeafTriangles out;
  for (uint32_t l = 0; l < solid.leaves.size(); ++l) {
    const Leaf& leaf = solid.leaves[l];
    for (uint32_t f = leaf.first_face; f < leaf.first_face + leaf.face_count; ++f) {
      auto face = solid.face(f);
      if (face.size() < 3) continue;
      // Stored order is the combined orientation; undo the sign to get the leaf's own.
      const bool rev = solid.face_sign[f] < 0;
      auto vtx = [&](size_t i) { return solid.vertices[face[rev ? face.size() - 1 - i : i]]; };
      const Vec3 a = vtx(0);
      for (size_t i = 1; i + 1 < face.size(); ++i) {
        CoverTri t{a, vtx(i), vtx(i + 1), {}};
        if (orient2d(t.a, t.b, t.c, 0) == 0 && orient2d(t.a, t.b, t.c, 1) == 0 &&
            orient2d(t.a, t.b, t.c, 2) == 0)
          continue;  // collinear
        t.box.add(t.a);
        t.box.add(t.b);
        t.box.add(t.c);
        out.tris.push_back(t);
      }
    }
    out.leaf_start.push_back(static_cast<uint32_t>(out.tris.size()));
  }
  return out;
}

bool on_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q) {
  Bbox box;
  box.add(a);
  box.add(b);
  box.add(c);
  const CoverTri t{a, b, c, box};
  if (!box.contains(q) || orient3d(a, b, c, q) != 0) return false;
  for (int axis = 0; axis < 3; ++axis) {
    const int s = orient2d(t.a, t.b, t.c, axis);
    if (s == 0) continue;
    // q is in the plane, so containment in this non-degenerate projection is containment.
    const int s1 = orient2d(t.a, t.b, q, axis), s2 = orient2d(t.b, t.c, q, axis),
              s3 = orient2d(t.c, t.a, q, axis);
    return (s1 == 0 || s1 == s) && (s2 == 0 || s2 == s) && (s3 == 0 || s3 == s);
  }
  return false;
}

}  // namespace cover::detail
