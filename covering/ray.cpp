#include "covering/ray.h"

#include <algorithm>
#include <cmath>

#include "covering/detail/exact.h"
#include "covering/predicates.h"
#include "solid/parallel.h"

namespace cover {
namespace {

/// The perturbation axes (u, w, k) for direction d: k is the axis of d's largest component.
struct Axes {
  int u, w, k;
};
Axes axes_for(const Vec3& d) {
  const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  const int k = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
  return {(k + 1) % 3, (k + 2) % 3, k};
}

/// Sign of ((a − o') × (b − o')) · d for o' = o + ε·e_u + ε²·e_w + ε³·e_k:
/// s0 + Σ ε^i ((a − b) × d)_axis_i (see ray.h).
int perturbed_side(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, Axes ax) {
  if (const int s = detail::triple_sign(o, a, b, d)) return s;
  if (const int s = detail::cross_axis_sign(a, b, d, ax.u)) return s;
  if (const int s = detail::cross_axis_sign(a, b, d, ax.w)) return s;
  return detail::cross_axis_sign(a, b, d, ax.k);
}

/// Sign of n·(o' − a): which side of the triangle's plane the perturbed origin is on.
int perturbed_plane_side(const Bvh::Tri& t, const Vec3& o, Axes ax) {
  if (const int s = orient3d(t.a, t.b, t.c, o)) return s;
  // n·(ε e_u + ε² e_w + ε³ e_k): the normal's components in that order (exact).
  if (const int s = orient2d(t.a, t.b, t.c, ax.u)) return s;
  if (const int s = orient2d(t.a, t.b, t.c, ax.w)) return s;
  return orient2d(t.a, t.b, t.c, ax.k);
}

bool ray_meets_box(const Bvh::Node& node, const Vec3& o, const Vec3& inv) {
  // Slab test. Node bounds are already widened (bvh.h), and the t interval gets a relative
  // slack, so floating-point error can only keep a box, never drop one the exact ray meets.
  double t0 = 0, t1 = INFINITY;
  for (int i = 0; i < 3; ++i) {
    const double lo = node.lo[i], hi = node.hi[i];
    if (std::isinf(inv[i])) {  // parallel to this slab
      if (o[i] < lo || o[i] > hi) return false;
      continue;
    }
    double ta = (lo - o[i]) * inv[i], tb = (hi - o[i]) * inv[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta * (1 - 1e-12));
    t1 = std::min(t1, tb * (1 + 1e-12));
    if (t0 > t1) return false;
  }
  return true;
}

/// Distance parameter of the hit, from the face's shared plane (bit-identical for all fan
/// triangles of a face); the triangle's own plane when the face plane is parallel to the ray.
double hit_t(const Bvh& bvh, const Bvh::Tri& t, const Ray& r) {
  const Bvh::FacePlane& p = bvh.face_planes()[t.face];
  const double nd = dot(p.normal, r.dir);
  if (nd != 0) return dot(p.normal, p.point - r.origin) / nd;
  const Vec3 n = cross(t.b - t.a, t.c - t.a);
  return dot(n, t.a - r.origin) / dot(n, r.dir);
}

}  // namespace

RayResult cast(const Bvh& bvh, const CsgTree& tree, size_t leaves, const Ray& ray) {
  RayResult out;
  if (bvh.nodes().empty()) return out;
  const Axes ax = axes_for(ray.dir);
  const Vec3 inv{1.0 / ray.dir.x, 1.0 / ray.dir.y, 1.0 / ray.dir.z};
  const auto& tris = bvh.triangles();
  walk(bvh, [&](const Bvh::Node& node) { return ray_meets_box(node, ray.origin, inv); },
       [&](uint32_t i) {
         const Bvh::Tri& t = tris[i];
         const int s1 = perturbed_side(ray.origin, ray.dir, t.a, t.b, ax);
         const int s2 = perturbed_side(ray.origin, ray.dir, t.b, t.c, ax);
         if (s1 != s2) return;
         const int s3 = perturbed_side(ray.origin, ray.dir, t.c, t.a, ax);
         if (s3 != s1 || s1 == 0) return;  // the perturbed line misses the triangle
         // The line crosses with sign(n·d) = s1; the hit is ahead iff o' is behind the plane.
         if (perturbed_plane_side(t, ray.origin, ax) != -s1) return;
         out.hits.push_back({std::max(0.0, hit_t(bvh, t, ray)), i, t.leaf, t.face, static_cast<int8_t>(s1)});
       });
  std::sort(out.hits.begin(), out.hits.end(), [](const RayHit& a, const RayHit& b) {
    return a.t < b.t || (a.t == b.t && (a.leaf < b.leaf || (a.leaf == b.leaf && a.tri < b.tri)));
  });
  // Winding at the origin = Σ signs; sweep and evaluate the expression on each interval.
  thread_local std::vector<int> winding;  // per-thread scratch: no allocation per ray
  thread_local std::vector<uint8_t> inside;
  winding.assign(leaves, 0);
  inside.resize(leaves);
  for (const RayHit& h : out.hits) winding[h.leaf] += h.sign;
  auto member = [&] {
    for (size_t l = 0; l < leaves; ++l) inside[l] = winding[l] != 0;
    return tree.evaluate(inside);
  };
  bool in = member();
  Span open{0, 0, Span::kNone, Span::kNone};
  for (size_t i = 0; i < out.hits.size(); ++i) {
    winding[out.hits[i].leaf] -= out.hits[i].sign;
    // Evaluate only after the last hit at this t (coincident faces change together).
    if (i + 1 < out.hits.size() && out.hits[i + 1].t == out.hits[i].t) continue;
    const bool now = member();
    if (now == in) continue;
    if (now) {
      open = {out.hits[i].t, 0, static_cast<uint32_t>(i), Span::kNone};
    } else {
      open.t1 = out.hits[i].t;
      open.exit = static_cast<uint32_t>(i);
      if (open.t1 > open.t0) out.spans.push_back(open);
    }
    in = now;
  }
  if (in) {
    open.t1 = INFINITY;
    out.spans.push_back(open);
  }
  return out;
}

FirstHit first_hit(const Bvh& bvh, const RayResult& result) {
  FirstHit f;
  for (const Span& s : result.spans) {
    if (s.enter == Span::kNone) continue;  // starts at the origin: no visible surface
    const RayHit& h = result.hits[s.enter];
    const Bvh::Tri& t = bvh.triangles()[h.tri];
    const Vec3 n = cross(t.b - t.a, t.c - t.a);
    f.hit = true;
    f.t = s.t0;
    // Entering a leaf (sign −1) shows its outward normal; leaving one (a subtrahend, or a
    // complement) shows the reversed normal.
    f.normal = h.sign < 0 ? n : -1.0 * n;
    f.leaf = h.leaf;
    f.face = h.face;
    return f;
  }
  return f;
}

std::vector<RayResult> cast(const Bvh& bvh, const Solid& solid, std::span<const Ray> rays,
                            const CastOptions& options) {
  std::vector<RayResult> out(rays.size());
  parallel_for(rays.size(), options.grain, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) out[i] = cast(bvh, solid.tree, solid.leaves.size(), rays[i]);
  });
  return out;
}

}  // namespace cover
