// Kernels of mesh skeletons (field/detail/mesh.h): capped distance enclosures over the triangle
// hierarchy (solid/field_leaf.h SkeletonMeshIndex) and the exact side of a point.
#include "cover/field/detail/mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "cover/field/closest.h"

namespace cover::field::detail {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Node = SkeletonMeshIndex::Node;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Depth-first walk: `visit_node(node)` says whether to enter, `visit(t)` takes a triangle. The
/// hierarchy is a median split, at most ~40 levels deep for 2^20 points.
template <class Enter, class Visit>
void walk(const SkeletonMeshIndex& index, Enter&& enter, Visit&& visit) {
  if (index.nodes.empty()) return;
  std::array<uint32_t, 96> stack;
  size_t top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const uint32_t id = stack[--top];
    const Node& node = index.nodes[id];
    if (!enter(node)) continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) visit(index.order[i]);
    } else {
      stack[top++] = node.right;
      stack[top++] = id + 1;  // the left child first
    }
  }
}

int orient_yz(const Vec3& a, const Vec3& b, const Vec3& c) {
  return CGAL::orientation(K::Point_2(a.y, a.z), K::Point_2(b.y, b.z), K::Point_2(c.y, c.z));
}

/// The sign of orient_yz(a, b, q + (0, ε, ε²)) for an infinitesimal ε > 0: with u = y, v = z,
/// orient(a, b, q') = orient(a, b, q) − (b.v − a.v)·ε + (b.u − a.u)·ε².
int perturbed(const Vec3& a, const Vec3& b, const Vec3& q) {
  if (const int s = orient_yz(a, b, q); s != 0) return s;
  if (a.z != b.z) return a.z > b.z ? 1 : -1;
  return b.y > a.y ? 1 : (b.y < a.y ? -1 : 0);
}

/// p on the closed, non-degenerate triangle abc, exactly: coplanar, and inside the triangle's
/// projection on a coordinate plane where it has area (edges included).
bool on_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
  const K::Point_3 A(a.x, a.y, a.z), B(b.x, b.y, b.z), C(c.x, c.y, c.z), P(p.x, p.y, p.z);
  if (CGAL::orientation(A, B, C, P) != CGAL::COPLANAR) return false;
  for (int drop = 0; drop < 3; ++drop) {
    auto project = [drop](const Vec3& v) {
      return drop == 0 ? K::Point_2(v.y, v.z)
                       : (drop == 1 ? K::Point_2(v.z, v.x) : K::Point_2(v.x, v.y));
    };
    const int area = CGAL::orientation(project(a), project(b), project(c));
    if (area == 0) continue;
    return CGAL::orientation(project(a), project(b), project(p)) != -area &&
           CGAL::orientation(project(b), project(c), project(p)) != -area &&
           CGAL::orientation(project(c), project(a), project(p)) != -area;
  }
  return false;  // unreachable for a non-degenerate triangle
}

bool contains(const Bbox& box, const Vec3& p) {
  return box.min.x <= p.x && p.x <= box.max.x && box.min.y <= p.y && p.y <= box.max.y &&
         box.min.z <= p.z && p.z <= box.max.z;
}

/// A lower bound of the squared distance between the boxes [lo, hi] and [b0, b1] (interval
/// arithmetic: the caller protects the rounding mode; lo = hi = p for a point).
double box_gap2(const Vec3& lo, const Vec3& hi, const Vec3& b0, const Vec3& b1) {
  auto gap = [](double a0, double a1, double c0, double c1) {
    return std::max({0.0, (I(a0) - I(c1)).inf(), (I(c0) - I(a1)).inf()});
  };
  return (CGAL::square(I(gap(lo.x, hi.x, b0.x, b1.x))) +
          CGAL::square(I(gap(lo.y, hi.y, b0.y, b1.y))) +
          CGAL::square(I(gap(lo.z, hi.z, b0.z, b1.z))))
      .inf();
}

}  // namespace

I mesh_d2(const FieldPrimitive& prim, const Vec3& lo, const Vec3& hi, double cap2) {
  const IV box{I(lo.x, hi.x), I(lo.y, hi.y), I(lo.z, hi.z)};
  const Vec3* q = prim.points.data();
  const SkeletonMeshIndex& index = *prim.mesh;
  // A lower bound of the squared gap between a box [b0, b1] and the probe box.
  auto gap2 = [&](const Vec3& b0, const Vec3& b1) { return box_gap2(lo, hi, b0, b1); };
  double best_lo = cap2, best_hi = cap2;
  // Nearest child first, so that best_hi falls early and prunes the rest; a node (or a
  // triangle's own box) whose gap exceeds best_hi cannot hold the least d² (module notes).
  std::array<std::pair<uint32_t, double>, 96> stack;
  size_t top = 0;
  if (!index.nodes.empty())
    stack[top++] = {0, gap2(index.nodes[0].box.min, index.nodes[0].box.max)};
  while (top > 0) {
    const auto [id, g] = stack[--top];
    if (g > best_hi) continue;
    const Node& node = index.nodes[id];
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const size_t t = index.order[i];
        const Vec3 &a = q[3 * t], &b = q[3 * t + 1], &c = q[3 * t + 2];
        const Vec3 t0{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}),
                      std::min({a.z, b.z, c.z})};
        const Vec3 t1{std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}),
                      std::max({a.z, b.z, c.z})};
        if (gap2(t0, t1) > best_hi) continue;
        const I d2 = triangle_d2(box, a, b, c);
        best_lo = std::min(best_lo, std::max(0.0, d2.inf()));
        best_hi = std::min(best_hi, d2.sup());
      }
      continue;
    }
    const Node &l = index.nodes[id + 1], &r = index.nodes[node.right];
    const double gl = gap2(l.box.min, l.box.max), gr = gap2(r.box.min, r.box.max);
    if (gl <= gr) {  // pushed last, popped first
      stack[top++] = {node.right, gr};
      stack[top++] = {id + 1, gl};
    } else {
      stack[top++] = {id + 1, gl};
      stack[top++] = {node.right, gr};
    }
  }
  return I(best_lo, best_hi);
}

int mesh_side(const FieldPrimitive& prim, const Vec3& p) {
  // The static filters of CGAL's predicates assume rounding to nearest.
  CGAL::Protect_FPU_rounding<true> nearest(CGAL_FE_TONEAREST);
  const Vec3* q = prim.points.data();
  bool on = false;
  int winding = 0;
  walk(
      *prim.mesh,
      [&](const Node& node) {
        // The perturbed ray meets the box only if min ≤ p < max in y and z (exact).
        return !on && node.box.max.x >= p.x && node.box.min.y <= p.y && p.y <= node.box.max.y &&
               node.box.min.z <= p.z && p.z <= node.box.max.z;
      },
      [&](uint32_t t) {
        if (on) return;
        const Vec3 &a = q[3 * size_t{t}], &b = q[3 * size_t{t} + 1], &c = q[3 * size_t{t} + 2];
        Bbox tb;
        tb.add(a), tb.add(b), tb.add(c);
        if (contains(tb, p) && on_triangle(a, b, c, p)) {
          on = true;
          return;
        }
        const int s = orient_yz(a, b, c);  // the sign of the normal's x-component
        if (s == 0 || perturbed(a, b, p) != s || perturbed(b, c, p) != s || perturbed(c, a, p) != s)
          return;
        // The hit is ahead (x > p.x) iff n·(a − p) has the sign of n.x: orientation(a, b, c, p)
        // is the sign of n·(p − a). Zero would put p on the triangle (found above).
        const int o = CGAL::orientation(K::Point_3(a.x, a.y, a.z), K::Point_3(b.x, b.y, b.z),
                                        K::Point_3(c.x, c.y, c.z), K::Point_3(p.x, p.y, p.z));
        if (-o * s > 0) winding += s;
      });
  if (on) return 0;
  return winding >= 1 ? 1 : -1;
}

CGAL::Gmpq mesh_exact_d2(const FieldPrimitive& prim, const Vec3& p) {
  using Q = CGAL::Gmpq;
  using QV = V3<Q>;
  double bound;
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    bound = mesh_d2(prim, p, p, kInf).sup();  // ≥ the least d²
  }
  const Vec3* q = prim.points.data();
  auto qv = [](const Vec3& v) { return QV{Q(v.x), Q(v.y), Q(v.z)}; };
  const QV P = qv(p);
  Q best;
  bool any = false;
  CGAL::Protect_FPU_rounding<true> rounding;
  const IV box = iv(p);
  walk(
      *prim.mesh,
      [&](const Node& node) { return box_gap2(p, p, node.box.min, node.box.max) <= bound; },
      [&](uint32_t t) {
        const Vec3 &a = q[3 * size_t{t}], &b = q[3 * size_t{t} + 1], &c = q[3 * size_t{t} + 2];
        if (triangle_d2(box, a, b, c).inf() > bound) return;
        const QV v = P - closest_on_triangle(P, qv(a), qv(b), qv(c));
        const Q d2 = dot(v, v);
        if (!any || d2 < best) best = d2, any = true;
      });
  return best;
}

double mesh_closest(const FieldPrimitive& prim, const Vec3& p, Vec3& closest) {
  using D = V3<double>;
  const D P{p.x, p.y, p.z};
  const Vec3* q = prim.points.data();
  auto dv = [](const Vec3& v) { return D{v.x, v.y, v.z}; };
  double best = kInf;
  walk(
      *prim.mesh,
      [&](const Node& node) {
        const double gx = std::max({0.0, node.box.min.x - p.x, p.x - node.box.max.x});
        const double gy = std::max({0.0, node.box.min.y - p.y, p.y - node.box.max.y});
        const double gz = std::max({0.0, node.box.min.z - p.z, p.z - node.box.max.z});
        return gx * gx + gy * gy + gz * gz <= best;
      },
      [&](uint32_t t) {
        const D c = closest_on_triangle(P, dv(q[3 * size_t{t}]), dv(q[3 * size_t{t} + 1]),
                                        dv(q[3 * size_t{t} + 2]));
        const D v = P - c;
        const double d2 = dot(v, v);
        if (d2 < best) best = d2, closest = {c.x, c.y, c.z};
      });
  return best;
}

}  // namespace cover::field::detail
