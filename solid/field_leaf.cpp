#include "cover/solid/field_leaf.h"

#include <cmath>
#include <limits>

namespace cover {

Bbox primitive_support_box(const FieldPrimitive& prim) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Bbox box;
  if (prim.points.empty()) return box;
  const bool circle = prim.kind == SkeletonKind::kCircle;
  // Each rounded sum is within half an ulp; one step outward after each covers it.
  const double grow =
      circle ? std::nextafter(prim.circle_radius + prim.influence, kInf) : prim.influence;
  Bbox skeleton;
  if (circle)
    skeleton.add(prim.points[0]);
  else
    for (const Vec3& p : prim.points) skeleton.add(p);
  const Vec3 lo = skeleton.min, hi = skeleton.max;
  box.add(Vec3{std::nextafter(lo.x - grow, -kInf), std::nextafter(lo.y - grow, -kInf),
               std::nextafter(lo.z - grow, -kInf)});
  box.add(Vec3{std::nextafter(hi.x + grow, kInf), std::nextafter(hi.y + grow, kInf),
               std::nextafter(hi.z + grow, kInf)});
  return box;
}

Bbox field_support_box(const FieldLeaf& leaf) {
  Bbox box;
  for (const FieldPrimitive& prim : leaf.primitives)
    if (prim.weight > 0) box.add(primitive_support_box(prim));
  return box;
}

}  // namespace cover
