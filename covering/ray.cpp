#include "cover/covering/ray.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <optional>

#include "cover/covering/bvh_walk.h"
#include "cover/covering/detail/implicit.h"
#include "cover/covering/ray_steps.h"
#include "cover/field/field.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"
#include "cover/solid/simd.h"

namespace cover {
namespace detail {

Axes axes_for(const Vec3& d) {
  const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  const int k = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
  return {(k + 1) % 3, (k + 2) % 3, k};
}

/// Sign of ((a − o') × (b − o')) · d for o' = o + ε·e_u + ε²·e_w + ε³·e_k:
/// s0 + Σ ε^i ((a − b) × d)_axis_i (see ray.h).
int perturbed_side(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, Axes ax) {
  if (const int s = triple_sign(o, a, b, d)) return s;
  if (const int s = cross_axis_sign(a, b, d, ax.u)) return s;
  if (const int s = cross_axis_sign(a, b, d, ax.w)) return s;
  return cross_axis_sign(a, b, d, ax.k);
}

/// Sign of n·(o' − a): which side of the triangle's plane the perturbed origin is on.
int perturbed_plane_side(const Bvh::Tri& t, const Vec3& o, Axes ax) {
  if (const int s = orient3d(t.a, t.b, t.c, o)) return s;
  // n·(ε e_u + ε² e_w + ε³ e_k): the normal's components in that order (exact).
  if (const int s = orient2d(t.a, t.b, t.c, ax.u)) return s;
  if (const int s = orient2d(t.a, t.b, t.c, ax.w)) return s;
  return orient2d(t.a, t.b, t.c, ax.k);
}

}  // namespace detail

namespace {

using detail::Axes;
using detail::axes_for;
using detail::crosses;
using detail::hit_before;
using detail::sweep_spans;

/// The ray's parameter interval [t0, t1] (t0 >= 0) inside a node box; t0 > t1 when it misses.
/// Slab test: node bounds are already widened (bvh.h), and the interval gets a relative slack,
/// so floating-point error can only keep a box, never drop one the exact ray meets. The computed
/// bounds are monotone in the box (a child's interval lies inside its parent's), which the
/// front-to-back traversal below relies on.
struct Interval {
  double t0, t1;
};
using detail::v2d;

/// The slab test with the per-ray work done once: which bound each axis enters through (no
/// swap) and which axes are parallel. Computes exactly the values of the plain loop
/// t0 = max(0, max_i min(ta_i, tb_i)·(1 − 1e-12)), t1 = min(∞, min_i max(ta_i, tb_i)·(1 + 1e-12)),
/// with the slack factor applied once after the max (min): rounding is monotone, so
/// max_i round(x_i·c) = round(max_i x_i · c) for c > 0, bit for bit (NaN terms are skipped by
/// both forms). Hand-unrolled, and both children of a node at once in SSE2 lanes, because it
/// is the hottest code of rendering (about a fifth of render_vs_cgal's samples in scalar form).
struct Slab {
  static constexpr double kShrink = 1 - 1e-12, kGrow = 1 + 1e-12;
  double o[3], inv[3];
  int near[3], far[3];  ///< offsets into a node's {lo[3], hi[3]} of the bound entered / left
  bool any_parallel;    ///< some inv is infinite: that axis only checks o against the slab
  Slab(const Vec3& origin, const Vec3& dir) {
    any_parallel = false;
    for (int i = 0; i < 3; ++i) {
      o[i] = origin[i];
      inv[i] = 1.0 / dir[i];
      any_parallel |= std::isinf(inv[i]);
      near[i] = inv[i] < 0 ? 3 + i : i;
      far[i] = inv[i] < 0 ? i : 3 + i;
    }
  }
  /// [t0, t1] over the non-parallel axes of the box b = {lo[3], hi[3]} (empty or not);
  /// `outside`: o lies outside the slab of some parallel axis.
  template <typename T>
  Interval bounds(const T* b, bool& outside) const {
    outside = false;
    double enter = -INFINITY, leave = INFINITY;
    for (int i = 0; i < 3; ++i) {
      if (any_parallel && std::isinf(inv[i])) {
        outside |= o[i] < b[i] || o[i] > b[3 + i];
        continue;
      }
      enter = std::max(enter, (b[near[i]] - o[i]) * inv[i]);
      leave = std::min(leave, (b[far[i]] - o[i]) * inv[i]);
    }
    return {std::max(0.0, enter * kShrink), leave * kGrow};
  }
  Interval operator()(const Bvh::Node& node) const {
    static_assert(offsetof(Bvh::Node, lo) == 0 && offsetof(Bvh::Node, hi) == 3 * sizeof(float));
    float b[6];  // lo then hi (copied so that the offsets index one array)
    std::memcpy(b, &node, sizeof b);
    bool outside;
    const Interval in = bounds(b, outside);
    return !outside && in.t0 <= in.t1 ? in : Interval{1, 0};
  }
  /// The same for a box of doubles (a triangle's exact box), as computed: monotone in the box as
  /// above, so a triangle's interval lies inside the interval of every node box that contains
  /// it. A ray that crosses the triangle has o inside its parallel axes' slabs.
  Interval operator()(const Bbox& box) const {
    const double b[6] = {box.min.x, box.min.y, box.min.z, box.max.x, box.max.y, box.max.z};
    bool outside;
    return bounds(b, outside);
  }
  /// The intervals of two nodes (a node's children), the same values as two calls above.
  void operator()(const Bvh::Node& l, const Bvh::Node& r, Interval& il, Interval& ir) const {
    if (any_parallel) {
      il = (*this)(l);
      ir = (*this)(r);
      return;
    }
    float bl[6], br[6];
    std::memcpy(bl, &l, sizeof bl);
    std::memcpy(br, &r, sizeof br);
    v2d enter = {-INFINITY, -INFINITY}, leave = {INFINITY, INFINITY};
    for (int i = 0; i < 3; ++i) {
      const v2d near_t = (v2d{bl[near[i]], br[near[i]]} - o[i]) * inv[i];
      const v2d far_t = (v2d{bl[far[i]], br[far[i]]} - o[i]) * inv[i];
      enter = enter < near_t ? near_t : enter;  // std::max(enter, near_t) per lane
      leave = far_t < leave ? far_t : leave;    // std::min(leave, far_t) per lane
    }
    const v2d shrunk = enter * kShrink, t1 = leave * kGrow;
    const v2d zero = {0.0, 0.0};
    const v2d t0 = zero < shrunk ? shrunk : zero;  // std::max(0.0, shrunk)
    il = t0[0] <= t1[0] ? Interval{t0[0], t1[0]} : Interval{1, 0};
    ir = t0[1] <= t1[1] ? Interval{t0[1], t1[1]} : Interval{1, 0};
  }
};

/// Distance parameter of the hit, from the face's shared plane (bit-identical for all fan
/// triangles of a face); the triangle's own plane when the face plane is parallel to the ray.
/// Clamped into the slab interval of the triangle's own exact box, where the exact crossing
/// lies: this changes only hits whose computed t was off (grazing rays, non-planar faces, NaN
/// for a ray in the triangle's plane), and it guarantees t >= the entry parameter of every node
/// above the triangle (Slab is monotone in the box), which makes front-to-back traversal exact.
/// The interval depends on the triangle alone, so every traversal (single ray, batch, front to
/// back) gives the same t.
double hit_t(const Bvh::FacePlane* p, const Bvh::Tri& t, const Ray& r, const Slab& slab) {
  Bbox box;
  box.add(t.a);
  box.add(t.b);
  box.add(t.c);
  const Interval in = slab(box);
  double v;
  const double nd = p ? dot(p->normal, r.dir) : 0;
  if (nd != 0) {
    v = dot(p->normal, p->point - r.origin) / nd;
  } else {  // a triangular face (its own plane), or a face plane parallel to the ray
    const Vec3 n = cross(t.b - t.a, t.c - t.a);
    v = dot(n, t.a - r.origin) / dot(n, r.dir);
  }
  if (!(v >= in.t0)) return in.t0;
  return v > in.t1 ? in.t1 : v;
}
double hit_t(const Bvh& bvh, const Bvh::Tri& t, const Ray& r, const Slab& slab) {
  return hit_t(bvh.face_plane(t.face), t, r, slab);
}

}  // namespace

namespace detail {

bool crosses(const Bvh::Tri& t, const Ray& ray, Axes ax, int& sign) {
  const int s1 = perturbed_side(ray.origin, ray.dir, t.a, t.b, ax);
  const int s2 = perturbed_side(ray.origin, ray.dir, t.b, t.c, ax);
  if (s1 != s2) return false;
  const int s3 = perturbed_side(ray.origin, ray.dir, t.c, t.a, ax);
  if (s3 != s1 || s1 == 0) return false;  // the perturbed line misses the triangle
  if (!ahead(t, ray, ax, s1)) return false;
  sign = s1;
  return true;
}

bool ahead(const Bvh::Tri& t, const Ray& ray, Axes ax, int sign) {
  // The line crosses with sign(n·d) = sign; the hit is ahead iff o' is behind the plane.
  return perturbed_plane_side(t, ray.origin, ax) == -sign;
}

bool hit_before(const RayHit& a, const RayHit& b) {
  if (a.t != b.t) return a.t < b.t;
  if (a.leaf != b.leaf) return a.leaf < b.leaf;
  if (a.face != b.face) return a.face < b.face;
  return a.tri < b.tri;
}

double hit_t(const Bvh::FacePlane* plane, const Bvh::Tri& t, const Ray& r) {
  return cover::hit_t(plane, t, r, Slab(r.origin, r.dir));
}

/// Sorts result.hits and sweeps them into the CSG inside spans: the winding at the origin is the
/// sum of the signs; per-leaf counters and the expression evaluated on each interval
/// ([Segura2004 §6]).
void sweep_spans(RayResult& out, const CsgTree& tree, size_t leaves) {
  std::sort(out.hits.begin(), out.hits.end(), hit_before);
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
}

}  // namespace detail

namespace {

/// The hits of the rays of one batch (walk_batch: their node loads overlap), then their spans.
/// Each ray gets the same hits (same t: the same leaf interval) as from cast() of that ray.
void cast_batch(const Bvh& bvh, const CsgTree& tree, size_t leaves, std::span<const Ray> rays,
                std::span<RayResult> out) {
  struct PerRay {
    Slab slab;
    Axes ax;
  };
  thread_local std::vector<PerRay> per;
  per.clear();
  for (const Ray& r : rays) per.push_back({Slab(r.origin, r.dir), axes_for(r.dir)});
  walk_batch(
      bvh, static_cast<uint32_t>(rays.size()),
      [&](uint32_t j, const Bvh::Node& l, const Bvh::Node& r) {
        Interval il, ir;
        per[j].slab(l, r, il, ir);
        return unsigned{il.t0 <= il.t1} | unsigned{ir.t0 <= ir.t1} << 1;
      },
      [&](uint32_t j, uint32_t first, uint32_t count) {
        for_each_triangle(bvh, first, count, [&](const Bvh::Tri& t, uint32_t i) {
          int sign;
          if (crosses(t, rays[j], per[j].ax, sign))
            out[j].hits.push_back({hit_t(bvh, t, rays[j], per[j].slab), i, t.leaf, t.face,
                                   static_cast<int8_t>(sign)});
        });
      });
  for (RayResult& r : out) sweep_spans(r, tree, leaves);
}

}  // namespace

RayResult cast(const Bvh& bvh, const CsgTree& tree, size_t leaves, const Ray& ray) {
  RayResult out;
  if (bvh.nodes().empty()) return out;
  cast_batch(bvh, tree, leaves, std::span<const Ray>(&ray, 1), std::span<RayResult>(&out, 1));
  return out;
}

RayResult cast_depth_first(const Bvh& bvh, const CsgTree& tree, size_t leaves, const Ray& ray) {
  RayResult out;
  if (bvh.nodes().empty()) return out;
  const Axes ax = axes_for(ray.dir);
  const Slab slab(ray.origin, ray.dir);
  walk(
      bvh,
      [&](const Bvh::Node& node) {
        const Interval in = slab(node);
        return in.t0 <= in.t1;
      },
      [&](const Bvh::Tri& t, uint32_t i) {
        int sign;
        if (crosses(t, ray, ax, sign))
          out.hits.push_back(
              {hit_t(bvh, t, ray, slab), i, t.leaf, t.face, static_cast<int8_t>(sign)});
      });
  sweep_spans(out, tree, leaves);
  return out;
}

VisibleHit first_visible(const RayResult& result, double lo, double hi) {
  VisibleHit v;
  for (const Span& span : result.spans) {
    const double a = std::max(span.t0, lo), b = std::min(span.t1, hi);
    if (!(a < b)) continue;  // no visible part of this span
    v.hit = true;
    v.t = a;
    v.cap = !(a == span.t0 && span.enter != Span::kNone);
    if (!v.cap) v.enter = result.hits[span.enter];
    return v;
  }
  return v;
}

VisibleHit first_visible(const Bvh& bvh, const CsgTree& tree, size_t leaves, const Ray& ray,
                         double lo, double hi, std::optional<bool> outside_in_result) {
  VisibleHit v;
  if (bvh.nodes().empty() || !(lo < hi)) return v;
  // Front-to-back needs the windings at the origin: 0 for a closed leaf whose box does not hold
  // the origin. Otherwise (or when the expression holds the all-outside point) cast all hits.
  // The scene box is tested first: a camera outside it skips the per-leaf boxes.
  thread_local std::vector<uint8_t> inside;
  inside.assign(leaves, 0);
  if (!outside_in_result) outside_in_result = tree.evaluate(inside);
  auto holds = [&](const Bbox& b) {
    return !b.empty() && ray.origin.x >= b.min.x && ray.origin.x <= b.max.x &&
           ray.origin.y >= b.min.y && ray.origin.y <= b.max.y && ray.origin.z >= b.min.z &&
           ray.origin.z <= b.max.z;
  };
  bool origin_outside = !*outside_in_result;
  if (origin_outside && holds(bvh.bounds()))
    for (size_t l = 0; l < leaves && origin_outside; ++l)
      origin_outside = !holds(bvh.leaf_bounds()[l]);
  if (!origin_outside) return first_visible(cast(bvh, tree, leaves, ray), lo, hi);

  // When every node not yet visited enters at τ or later, every hit with t < τ has been found
  // (hit_t clamps t into its triangle's interval, which lies in every enclosing node's), so
  // those hits are final: they are sorted and swept with per-leaf winding counters exactly as
  // in cast(), and the sweep stops at the first span that shows inside [lo, hi]. Why: a frame
  // needs only the first span in view, and this walk takes 16–24% fewer instructions per frame
  // than collecting every hit of every ray with cast() (callgrind, 296k-face 5-leaf scene, 256²).
  // A stack of nodes is enough: a priority queue saves no instructions.
  const Axes ax = axes_for(ray.dir);
  const Slab slab(ray.origin, ray.dir);
  const auto& nodes = bvh.nodes();
  struct Entry {
    double t0, t1;
    uint32_t node;
  };
  Entry stack[Bvh::kMaxStack];  // a local array: no thread_local vector on the hot path
  int top = 0;
  thread_local std::vector<RayHit> pending;
  thread_local std::vector<int> winding;
  pending.clear();
  winding.assign(leaves, 0);
  bool in = false;
  double span_t0 = 0;
  // Sweeps the pending hits with t < tau; true once the answer is known.
  auto sweep = [&](double tau) {
    auto final_end = std::partition(pending.begin(), pending.end(),
                                    [tau](const RayHit& h) { return h.t < tau; });
    std::sort(pending.begin(), final_end, hit_before);
    const size_t n = static_cast<size_t>(final_end - pending.begin());
    for (size_t i = 0; i < n; ++i) {
      const RayHit& h = pending[i];
      winding[h.leaf] -= h.sign;
      // Evaluate only after the last hit at this t (coincident faces change together).
      if (i + 1 < n && pending[i + 1].t == h.t) continue;
      for (size_t l = 0; l < leaves; ++l) inside[l] = winding[l] != 0;
      const bool now = tree.evaluate(inside);
      if (now == in) continue;
      in = now;
      if (now) {
        span_t0 = h.t;
        if (h.t >= lo) {  // the span starts in view if h.t < hi (its end is later than h.t)
          if (h.t < hi) {
            v = {true, false, h.t, h};
            return true;
          }
          return true;  // spans only start later: nothing in view
        }
      } else if (std::min(h.t, hi) > lo) {  // a span that began before lo ends after it: a cap
        v = {true, true, lo, {}};
        return true;
      }
    }
    pending.erase(pending.begin(), final_end);
    // An open span that began before lo and ends at or after tau > lo: a cap at lo.
    if (in && tau > lo && std::min(tau, hi) > lo && span_t0 < lo) {
      v = {true, true, lo, {}};
      return true;
    }
    return false;
  };
  // Depth first, nearer child first (a stack, cheaper per node than a priority queue). Hits
  // are swept only when the node taken next enters after the nearest pending hit; then τ is the
  // least entry parameter of every node not yet visited (the stack and that node).
  double pending_min = INFINITY;
  const Interval root = slab(nodes[0]);
  if (root.t0 <= root.t1) stack[top++] = {root.t0, root.t1, 0};
  while (top > 0) {
    const Entry cur = stack[--top];
    if (cur.t0 > pending_min) {
      double tau = cur.t0;
      for (int e = 0; e < top; ++e) tau = std::min(tau, stack[e].t0);
      if (tau > pending_min) {
        if (sweep(tau)) return v;
        pending_min = INFINITY;
        for (const RayHit& h : pending) pending_min = std::min(pending_min, h.t);
      }
    }
    const Bvh::Node& node = nodes[cur.node];
    if (node.count == 0) {
      Interval l, r;
      slab(nodes[node.first], nodes[node.first + 1], l, r);
      const bool l_in = l.t0 <= l.t1, r_in = r.t0 <= r.t1;
      if (r.t0 < l.t0) {  // right child nearer: pushed last, popped first
        if (l_in) stack[top++] = {l.t0, l.t1, node.first};
        if (r_in) stack[top++] = {r.t0, r.t1, node.first + 1};
      } else {
        if (r_in) stack[top++] = {r.t0, r.t1, node.first + 1};
        if (l_in) stack[top++] = {l.t0, l.t1, node.first};
      }
      continue;
    }
    for_each_triangle(bvh, node, [&](const Bvh::Tri& t, uint32_t i) {
      int sign;
      if (!crosses(t, ray, ax, sign)) return;
      pending.push_back({hit_t(bvh, t, ray, slab), i, t.leaf, t.face, static_cast<int8_t>(sign)});
      pending_min = std::min(pending_min, pending.back().t);
    });
  }
  if (!pending.empty() && sweep(INFINITY)) return v;
  // After the last hit every winding is 0 again (closed leaves) and the result is outside.
  return v;
}

FirstHit first_hit(const Bvh& bvh, const RayResult& result) {
  FirstHit f;
  for (const Span& s : result.spans) {
    if (s.enter == Span::kNone) continue;  // starts at the origin: no visible surface
    const RayHit& h = result.hits[s.enter];
    // A field leaf's crossing has no triangle: its normal is the caller's (field_normal).
    const Bvh::Tri t = h.tri == Span::kNone ? Bvh::Tri{} : bvh.triangle(h.tri);
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

Vec3 field_normal(const Prepared& prepared, const RayHit& hit, const Ray& ray) {
  return detail::implicit_normal(prepared, hit, ray);
}

void field_spans(RayResult& result, const Prepared& prepared, const Ray& ray) {
  const Solid& solid = prepared.solid();
  for (uint32_t l = 0; l < solid.leaves.size(); ++l) {
    if (solid.leaves[l].is_field())
      result.uncertain += field_crossings(solid, l, ray, result.hits);
    else if (solid.leaves[l].is_warp())
      result.uncertain += detail::warp_crossings(prepared, l, ray, result.hits);
  }
  result.spans.clear();
  if (const GwnForest* open = prepared.gwn(); open != nullptr) {
    std::sort(result.hits.begin(), result.hits.end(), detail::hit_before);
    open_spans(result, solid, *open, ray);
  } else {
    detail::sweep_spans(result, solid.tree, solid.leaves.size());
  }
}

std::vector<RayResult> cast(const Prepared& prepared, std::span<const Ray> rays,
                            const CastOptions& options) {
  const Solid& solid = prepared.solid();
  const Bvh& bvh = prepared.bvh();
  std::vector<RayResult> out(rays.size());
  if (solid.has_implicit_leaf()) {
    prepared.gwn();
    parallel_for(rays.size(), options.grain, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        out[i] = cast(bvh, solid.tree, solid.leaves.size(), rays[i]);
        field_spans(out[i], prepared, rays[i]);
      }
    });
    return out;
  }
  if (bvh.nodes().empty()) return out;
  const GwnForest* forest = prepared.gwn();
  constexpr size_t kBatch = 256;  // rays walking the BVH together (walk_batch)
  parallel_for(rays.size(), options.grain, [&](size_t begin, size_t end) {
    for (size_t b = begin; b < end; b += kBatch) {
      const size_t e = std::min(end, b + kBatch);
      cast_batch(bvh, solid.tree, solid.leaves.size(), rays.subspan(b, e - b),
                 std::span(out).subspan(b, e - b));
      if (forest != nullptr)
        for (size_t i = b; i < e; ++i) open_spans(out[i], solid, *forest, rays[i]);
    }
  });
  return out;
}

void open_spans(RayResult& result, const Solid& solid, const GwnForest& forest, const Ray& ray,
                const GwnOptions& options) {
  const size_t leaves = solid.leaves.size();
  const std::vector<RayHit>& hits = result.hits;
  result.spans.clear();
  std::vector<int> winding(leaves, 0);
  std::vector<uint8_t> inside(leaves);
  for (const RayHit& h : hits) winding[h.leaf] += h.sign;
  const Bbox box = solid.bbox();
  const double diag = box.empty() ? 1.0 : std::sqrt(dot(box.max - box.min, box.max - box.min));
  const double beyond = 0.5 * diag / std::sqrt(dot(ray.dir, ray.dir));
  // Membership on the interval (t0, t1) (t1 = ∞: the last one), closed leaves by `winding`.
  auto member = [&](double t0, double t1) {
    const double t = std::isinf(t1) ? t0 + beyond : 0.5 * (t0 + t1);
    const Vec3 p = ray.origin + t * ray.dir;
    for (size_t l = 0; l < leaves; ++l) {
      const int32_t tree = forest.tree_of_leaf[l];
      inside[l] = tree < 0 ? winding[l] != 0 : gwn_inside(forest.trees[tree], p, options);
    }
    return solid.tree.evaluate(inside);
  };
  double t_prev = 0;
  bool in = member(0, hits.empty() ? INFINITY : hits[0].t);
  Span open{0, 0, Span::kNone, Span::kNone};
  for (size_t i = 0; i < hits.size(); ++i) {
    winding[hits[i].leaf] -= hits[i].sign;
    if (i + 1 < hits.size() && hits[i + 1].t == hits[i].t) continue;
    t_prev = hits[i].t;
    const bool now = member(t_prev, i + 1 < hits.size() ? hits[i + 1].t : INFINITY);
    if (now == in) continue;
    if (now) {
      open = {hits[i].t, 0, static_cast<uint32_t>(i), Span::kNone};
    } else {
      open.t1 = hits[i].t;
      open.exit = static_cast<uint32_t>(i);
      if (open.t1 > open.t0) result.spans.push_back(open);
    }
    in = now;
  }
  if (in) {
    open.t1 = INFINITY;
    result.spans.push_back(open);
  }
}

}  // namespace cover
