// Field and warp leaves' membership, box states and normals (covering/detail/implicit.h).

#include "cover/covering/detail/implicit.h"

#include <cmath>

#include "cover/covering/box_states.h"
#include "cover/covering/classify.h"
#include "cover/covering/detail/local.h"
#include "cover/field/warp.h"

namespace cover::detail {
namespace {

field::Sign of_class(PointClass c) {
  return c == PointClass::kInside    ? field::Sign::kInside
         : c == PointClass::kOutside ? field::Sign::kOutside
                                     : field::Sign::kOn;
}

/// The child's class at one point (its own classification: exact for the child's mesh and
/// polynomial field leaves; its own uncertain points are counted in `uncertain`).
field::Sign child_class(const Prepared& child, const Vec3& p, std::atomic<size_t>* uncertain) {
  ClassifyOptions options;
  options.grid_min_points = SIZE_MAX;  // one point: no empty-cell grid
  const Classification c = classify_counted(child, std::span<const Vec3>(&p, 1), options);
  if (uncertain != nullptr && c.uncertain > 0)
    uncertain->fetch_add(c.uncertain, std::memory_order_relaxed);
  return of_class(c.classes[0]);
}

field::Sign warp_member(const Prepared& prepared, const Leaf& leaf, const Vec3& q,
                        std::atomic<size_t>* uncertain) {
  const WarpLeaf& w = prepared.solid().warps[leaf.warp];
  const Prepared& child = prepared.warp_child(leaf.warp);
  Vec3 exact;
  if (field::exact_inverse(w, q, exact)) return child_class(child, exact, uncertain);
  const field::InverseBox b = field::inverse_box(w, Bbox{q, q});
  if (b.none) return field::Sign::kOutside;
  const uint8_t state = box_state(child, b.box);
  if (state == kBoxOutside) return field::Sign::kOutside;
  if (state == kBoxInside && !b.partial) return field::Sign::kInside;
  // A rational preimage (taper): the child's exact class there (covering/detail/local.h).
  if (const std::optional<field::Sign> s = exact_warp_member(prepared, leaf.warp, q)) return *s;
  // The tie rule: the child's class at the rounded preimage.
  if (uncertain != nullptr) uncertain->fetch_add(1, std::memory_order_relaxed);
  const Vec3 p = field::inverse(w, q);
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
    return field::Sign::kOutside;
  return child_class(child, p, nullptr);
}

}  // namespace

field::Sign implicit_member(const Prepared& prepared, uint32_t leaf_id, const Vec3& q,
                            std::atomic<size_t>* uncertain) {
  const Solid& solid = prepared.solid();
  const Leaf& leaf = solid.leaves[leaf_id];
  if (!leaf.bbox.contains(q)) return field::Sign::kOutside;
  if (leaf.is_warp()) return warp_member(prepared, leaf, q, uncertain);
  // Field leaf: the certified sign; the tie rule where a circle skeleton's enclosure leaves it
  // undecided: the double evaluation's sign (f > T inside).
  const FieldLeaf& f = solid.fields[leaf.field];
  const field::Sign s = field::sign(f, q);
  if (s != field::Sign::kUndecided) return s;
  if (uncertain != nullptr) uncertain->fetch_add(1, std::memory_order_relaxed);
  return field::evaluate(f, q).value > field::threshold(f) ? field::Sign::kInside
                                                           : field::Sign::kOutside;
}

uint8_t implicit_box_state(const Prepared& prepared, uint32_t leaf_id, const Bbox& box) {
  const Solid& solid = prepared.solid();
  const Leaf& leaf = solid.leaves[leaf_id];
  const bool meets = leaf.bbox.min.x <= box.max.x && leaf.bbox.max.x >= box.min.x &&
                     leaf.bbox.min.y <= box.max.y && leaf.bbox.max.y >= box.min.y &&
                     leaf.bbox.min.z <= box.max.z && leaf.bbox.max.z >= box.min.z;
  if (!meets) return kBoxOutside;
  if (leaf.is_field()) {
    const field::Range r = field::bound(solid.fields[leaf.field], box);
    return r.lo > 0 ? kBoxInside : (r.hi < 0 ? kBoxOutside : kBoxUndecided);
  }
  const field::InverseBox b = field::inverse_box(solid.warps[leaf.warp], box);
  if (b.none) return kBoxOutside;
  const uint8_t s = box_state(prepared.warp_child(leaf.warp), b.box);
  return s == kBoxInside && b.partial ? uint8_t{kBoxUndecided} : s;
}

Vec3 implicit_normal(const Prepared& prepared, const RayHit& hit, const Ray& ray) {
  const Solid& solid = prepared.solid();
  const Leaf& leaf = solid.leaves[hit.leaf];
  const Vec3 p = ray.origin + hit.t * ray.dir;
  Vec3 n;
  if (leaf.is_field()) {
    n = field::evaluate(solid.fields[leaf.field], p).gradient;
  } else {
    // The child's surface near w⁻¹(p): its hit nearest to w⁻¹(p) along the mapped direction.
    const WarpLeaf& w = solid.warps[leaf.warp];
    const Prepared& child = prepared.warp_child(leaf.warp);
    const Vec3 m = field::inverse(w, p);
    const field::Mat3 j = field::inverse_jacobian(w, p);
    Vec3 dc{dot(j.row[0], ray.dir), dot(j.row[1], ray.dir), dot(j.row[2], ray.dir)};
    const double len = std::sqrt(dot(dc, dc));
    const Bbox cb = child.solid().bbox();
    const Vec3 diag = cb.max - cb.min;
    const double reach = 2 * std::sqrt(dot(diag, diag)) + std::sqrt(dot(m - cb.min, m - cb.min));
    if (!(len > 0) || !std::isfinite(reach)) return -1.0 * ray.dir;
    dc = (1 / len) * dc;
    const Ray cr{m - reach * dc, dc};
    const std::vector<RayResult> r = cast(child, std::span<const Ray>(&cr, 1));
    const RayHit* best = nullptr;
    for (const RayHit& h : r[0].hits)
      if (best == nullptr || std::abs(h.t - reach) < std::abs(best->t - reach)) best = &h;
    if (best == nullptr) return -1.0 * ray.dir;
    Vec3 nc;
    if (best->tri == Span::kNone) {
      nc = implicit_normal(child, *best, cr);
    } else {
      const Bvh::Tri t = child.bvh().triangle(best->tri);
      nc = cross(t.b - t.a, t.c - t.a);
    }
    n = nc.x * j.row[0] + nc.y * j.row[1] + nc.z * j.row[2];
  }
  return dot(n, ray.dir) > 0 ? -1.0 * n : n;
}

}  // namespace cover::detail
