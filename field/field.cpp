// Kernels of field leaves (field.h): validation, support box, value and gradient (doubles), the
// certified sign (interval filter, then exact rationals) and a sound enclosure over a box.
//
// Conventions of this file
//   potential   g = max(0, 1 − d²/R²)^n, written on d² (the same as solid/field_leaf.h's g for
//               d ≥ 0). Both maps, d² ↦ max(0, 1 − d²/R²) (decreasing) and x ↦ xⁿ on [0, ∞)
//               (increasing), are monotone: an enclosure of d² maps end to end onto one of g,
//               and d ≥ R gives exactly 0.
//   pruning     `far`: the probe (a point, or a box for bound()) is farther than s from a
//               skeleton's box along one axis, in plain doubles. Rounding is monotone and s is a
//               double, so fl(x − y) > s implies x − y > s exactly, in any rounding mode: then
//               d > R, g = 0 exactly, and every path (interval, exact, double) skips the term.
//   intervals   CGAL::Interval_nt<false> under one Protect_FPU_rounding guard per call. Where
//               the closest point's region is not certain, the enclosure is the hull of the
//               candidate formulas; exact quantities known to be ≥ 0 are clamped at 0.
//   exact       CGAL::Gmpq: every double is a rational, and for point, segment, triangle and
//               polyline skeletons d² is a rational function of p, so f − T is decided exactly.
#include "cover/field/field.h"

#include <CGAL/Gmpq.h>
#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include "cover/field/closest.h"
#include "cover/field/detail/exact.h"
#include "cover/field/detail/interval.h"
#include "cover/field/detail/mesh.h"

namespace cover::field {
namespace {

using detail::I;
using detail::imin;
using detail::IV;
using detail::iv;
using detail::norm2;
using Q = CGAL::Gmpq;
using detail::V3;
constexpr double kInf = std::numeric_limits<double>::infinity();

Vec3 vmin(const Vec3& a, const Vec3& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
Vec3 vmax(const Vec3& a, const Vec3& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}

/// True when the probe box [lo, hi] is farther than s from the box [smin, smax] along one axis
/// (exactly: see "pruning" above). Bitwise `|`: six compares and one well-predicted branch.
bool far(const Vec3& lo, const Vec3& hi, const Vec3& smin, const Vec3& smax, double s) {
  return (lo.x - smax.x > s) | (smin.x - hi.x > s) | (lo.y - smax.y > s) | (smin.y - hi.y > s) |
         (lo.z - smax.z > s) | (smin.z - hi.z > s);
}
/// A circle's support test: its centre's distance, against r + R rounded up.
double circle_reach(const FieldPrimitive& prim) {
  return std::nextafter(prim.circle_radius + prim.influence, kInf);
}
/// A mesh skeleton's support test: its box's distance, against R − r_T rounded up (outside M
/// farther than that, the pseudo-distance r_T + dist exceeds R and g = 0).
double mesh_reach(const FieldPrimitive& prim) {
  return std::nextafter(prim.influence - prim.radius, kInf);
}

// ---- interval enclosures ------------------------------------------------------------------

/// xⁿ, n ≥ 1, by squaring (sound for any x; tight for x ≥ 0).
I power(I x, int n) {
  I r = (n & 1) ? x : I(1);
  for (n >>= 1; n > 0; n >>= 1) {
    x = CGAL::square(x);
    if (n & 1) r *= x;
  }
  return r;
}

/// Enclosure of g from an enclosure of d² (monotone, see "potential").
I potential(const I& d2, double R, int n) {
  const I t = I(1) - I(std::max(0.0, d2.inf()), d2.sup()) / CGAL::square(I(R));
  if (!(t.sup() > 0)) return I(0);
  return power(I(std::max(0.0, t.inf()), t.sup()), n);
}

/// T = (1 − r_T²/R²)^n.
I threshold_interval(const FieldPrimitive& prim) {
  return power(I(1) - CGAL::square(I(prim.radius)) / CGAL::square(I(prim.influence)),
               prim.exponent);
}

/// d² = h² + (ρ − r)² to the circle (centre c, normal m, radius r): h² = (v·m)²/|m|²,
/// ρ² = |v×m|²/|m|², v = p − c.
I circle_d2(const IV& p, const Vec3& c, const Vec3& normal, double r) {
  const IV v = p - iv(c), m = iv(normal);
  const I mm = norm2(m);
  const I h2 = CGAL::square(dot(v, m)) / mm;
  const I rho = CGAL::sqrt(norm2(cross(v, m)) / mm);  // sqrt clamps a negative lower end at 0
  return h2 + CGAL::square(rho - I(r));
}

/// Enclosure of the squared pseudo-distance of a mesh skeleton over the box [lo, hi]
/// (solid/field_leaf.h kMesh). Beyond c = max(R − r_T, r_T) from ∂M the potential no longer
/// changes (0 outside, 1 inside), so dist is capped there. Where the box provably misses ∂M,
/// the whole box is on one side, M's exact side at its corner lo; elsewhere the hull of both.
/// Needs the rounding guard.
I mesh_pseudo_d2(const FieldPrimitive& prim, const Vec3& lo, const Vec3& hi) {
  const I c(std::max(prim.influence - prim.radius, prim.radius));
  const I dist = CGAL::sqrt(detail::mesh_d2(prim, lo, hi, CGAL::square(c).sup()));
  const I r(prim.radius);
  auto clamp0 = [](const I& x) { return I(std::max(0.0, x.inf()), std::max(0.0, x.sup())); };
  I d;
  if (dist.inf() > 0) {
    d = detail::mesh_side(prim, lo) > 0 ? clamp0(r - dist) : r + dist;
  } else {
    d = I(clamp0(r - dist).inf(), (r + dist).sup());
  }
  return CGAL::square(d);
}

/// Enclosure of f − T over the probe box [lo, hi] (a point when lo = hi); *circle is set when
/// a circle primitive's support box meets the probe. Needs the rounding guard.
/// `subset` (not empty): only those primitives (the caller knows the others vanish there).
I enclose(const FieldLeaf& leaf, const Vec3& lo, const Vec3& hi, bool* circle,
          std::span<const uint32_t> subset = {}) {
  const IV p{I(lo.x, hi.x), I(lo.y, hi.y), I(lo.z, hi.z)};
  I f(0);
  const size_t count = subset.empty() ? leaf.primitives.size() : subset.size();
  for (size_t s = 0; s < count; ++s) {
    const FieldPrimitive& prim = leaf.primitives[subset.empty() ? s : subset[s]];
    const double R = prim.influence;
    const Vec3* q = prim.points.data();
    I d2;
    switch (prim.kind) {
      case SkeletonKind::kPoint:
        if (far(lo, hi, q[0], q[0], R)) continue;
        d2 = norm2(p - iv(q[0]));
        break;
      case SkeletonKind::kSegment:
        if (far(lo, hi, vmin(q[0], q[1]), vmax(q[0], q[1]), R)) continue;
        d2 = segment_d2(p, q[0], q[1]);
        break;
      case SkeletonKind::kTriangle:
        if (far(lo, hi, vmin(q[0], vmin(q[1], q[2])), vmax(q[0], vmax(q[1], q[2])), R)) continue;
        d2 = triangle_d2(p, q[0], q[1], q[2]);
        break;
      case SkeletonKind::kPolyline: {
        bool any = false;  // g of the polyline = g of the least d² over its pieces
        for (size_t j = 0; j + 1 < prim.points.size(); ++j) {
          if (far(lo, hi, vmin(q[j], q[j + 1]), vmax(q[j], q[j + 1]), R)) continue;
          const I dj = segment_d2(p, q[j], q[j + 1]);
          d2 = any ? imin(d2, dj) : dj;
          any = true;
        }
        if (!any) continue;
        break;
      }
      case SkeletonKind::kCircle:
        if (far(lo, hi, q[0], q[0], circle_reach(prim))) continue;
        *circle = true;
        d2 = circle_d2(p, q[0], q[1], prim.circle_radius);
        break;
      case SkeletonKind::kMesh: {
        const Bbox& mb = prim.mesh->nodes[0].box;
        if (far(lo, hi, mb.min, mb.max, mesh_reach(prim))) continue;
        d2 = mesh_pseudo_d2(prim, lo, hi);
        break;
      }
    }
    const I g = potential(d2, R, prim.exponent);
    f = prim.weight > 0 ? f + g : f - g;
  }
  return f - threshold_interval(leaf.primitives[0]);
}

// ---- exact rationals ----------------------------------------------------------------------

using QV = V3<Q>;
QV qv(const Vec3& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }
Q qnorm2(const QV& v) { return detail::dot(v, v); }

Q qpower(Q x, int n) {
  Q r = (n & 1) ? x : Q(1);
  for (n >>= 1; n > 0; n >>= 1) {
    x = x * x;
    if (n & 1) r = r * x;
  }
  return r;
}

Q exact_threshold(const FieldPrimitive& prim) {
  const Q r(prim.radius), R(prim.influence);
  return qpower(Q(1) - (r * r) / (R * R), prim.exponent);
}

Q segment_d2(const QV& p, const Vec3& a, const Vec3& b) {
  return qnorm2(p - detail::closest_on_segment(p, qv(a), qv(b)));
}

/// The exact sign of f(P) − T, or kUndecided when a circle primitive's support box holds P;
/// [p, hi] is a box of doubles holding P (the pruning tests are sound for boxes).
Sign exact_sign(const FieldLeaf& leaf, const QV& P, const Vec3& p, const Vec3& hi) {
  Q f(0);
  const FieldPrimitive* pending = nullptr;  // a mesh term with an irrational potential
  int pending_side = 0;
  for (const FieldPrimitive& prim : leaf.primitives) {
    const double R = prim.influence;
    const Vec3* q = prim.points.data();
    Q d2;
    switch (prim.kind) {
      case SkeletonKind::kPoint:
        if (far(p, hi, q[0], q[0], R)) continue;
        d2 = qnorm2(P - qv(q[0]));
        break;
      case SkeletonKind::kSegment:
        if (far(p, hi, vmin(q[0], q[1]), vmax(q[0], q[1]), R)) continue;
        d2 = segment_d2(P, q[0], q[1]);
        break;
      case SkeletonKind::kTriangle:
        if (far(p, hi, vmin(q[0], vmin(q[1], q[2])), vmax(q[0], vmax(q[1], q[2])), R)) continue;
        d2 = qnorm2(P - detail::closest_on_triangle(P, qv(q[0]), qv(q[1]), qv(q[2])));
        break;
      case SkeletonKind::kPolyline: {
        bool any = false;
        for (size_t j = 0; j + 1 < prim.points.size(); ++j) {
          if (far(p, hi, vmin(q[j], q[j + 1]), vmax(q[j], q[j + 1]), R)) continue;
          const Q dj = segment_d2(P, q[j], q[j + 1]);
          if (!any || dj < d2) d2 = dj;
          any = true;
        }
        if (!any) continue;
        break;
      }
      case SkeletonKind::kCircle:
        if (far(p, hi, q[0], q[0], circle_reach(prim))) continue;
        return Sign::kUndecided;
      case SkeletonKind::kMesh: {
        const Bbox& mb = prim.mesh->nodes[0].box;
        if (far(p, hi, mb.min, mb.max, mesh_reach(prim))) continue;
        // The side is decided at double points only (a warp's rational preimage is not one).
        if (!(p == hi) || pending != nullptr) return Sign::kUndecided;
        const int side = detail::mesh_side(prim, p);
        if (side == 0) {  // on ∂M: d = r_T, g = T
          f = prim.weight > 0 ? f + exact_threshold(prim) : f - exact_threshold(prim);
          continue;
        }
        // dist ≥ R − r_T outside: g = 0; dist ≥ r_T inside: d = 0, g = 1. Else g is
        // irrational (a square root): decided below only when it is the lone term.
        const Q D = detail::mesh_exact_d2(prim, p), r(prim.radius);
        const Q reach = Q(R) - r;
        if (side < 0 && D >= reach * reach) continue;
        if (side > 0 && D >= r * r) {
          f = prim.weight > 0 ? f + Q(1) : f - Q(1);
          continue;
        }
        pending = &prim;
        pending_side = side;
        continue;
      }
    }
    const Q R2 = Q(R) * Q(R);
    if (d2 >= R2) continue;  // d ≥ R: g = 0
    const Q g = qpower(Q(1) - d2 / R2, prim.exponent);
    f = prim.weight > 0 ? f + g : f - g;
  }
  const Q T = exact_threshold(leaf.primitives[0]);
  if (pending != nullptr) {
    // 0 < g < 1 with g > T exactly inside M (d < r_T) and g < T outside. Alone (every other
    // term 0), its side decides; a negative term alone leaves f < 0 < T.
    if (f != 0) return Sign::kUndecided;
    if (pending->weight < 0) return Sign::kOutside;  // f = −g < 0 < T
    // Alone, with the leaf's threshold: g > T ⇔ d < r_T ⇔ inside M.
    if (exact_threshold(*pending) != T) return Sign::kUndecided;
    return pending_side > 0 ? Sign::kInside : Sign::kOutside;
  }
  return f > T ? Sign::kInside : (f < T ? Sign::kOutside : Sign::kOn);
}

/// The double nearest to q (ties to even), from mpq_get_d's truncation and its neighbours.
double nearest_double(const Q& q) {
  const double d = q.to_double();
  double best = d;
  Q best_error = CGAL::abs(Q(d) - q);
  for (const double c : {std::nextafter(d, -kInf), std::nextafter(d, kInf)}) {
    const Q error = CGAL::abs(Q(c) - q);
    if (error < best_error || (error == best_error && (std::bit_cast<uint64_t>(c) & 1) == 0)) {
      best = c;
      best_error = error;
    }
  }
  return best;
}

// ---- validation ---------------------------------------------------------------------------

std::string num(double x) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}
bool in_range(double x) { return std::abs(x) <= kMaxCoordinate; }  // false for NaN

/// True when a, b, c are collinear, exactly: (b − a)×(c − a) = 0, an interval filter first.
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    const IV A = iv(a), n = detail::cross(iv(b) - A, iv(c) - A);
    auto nonzero = [](const I& x) { return x.inf() > 0 || x.sup() < 0; };
    if (nonzero(n.x) || nonzero(n.y) || nonzero(n.z)) return false;
  }
  const QV A = qv(a), ab = qv(b) - A, ac = qv(c) - A;
  return ab.y * ac.z == ab.z * ac.y && ab.z * ac.x == ab.x * ac.z && ab.x * ac.y == ab.y * ac.x;
}

/// The first problem of one primitive, or "" (everything but the shared threshold).
std::string primitive_problem(const FieldPrimitive& prim) {
  const size_t k = prim.points.size();
  switch (prim.kind) {
    case SkeletonKind::kPoint:
    case SkeletonKind::kSegment:
    case SkeletonKind::kTriangle:
    case SkeletonKind::kCircle: {
      const size_t want = prim.kind == SkeletonKind::kPoint      ? 1
                          : prim.kind == SkeletonKind::kTriangle ? 3
                                                                 : 2;
      if (k != want) {
        return "a " + std::string(to_string(prim.kind)) + " needs " + std::to_string(want) +
               " points (got " + std::to_string(k) + ")";
      }
      break;
    }
    case SkeletonKind::kMesh:
      if (k < 6 || k % 3 != 0 || k > kMaxPolylinePoints) {
        return "a mesh skeleton needs 2 to " + std::to_string(kMaxPolylinePoints / 3) +
               " triangles (got " + std::to_string(k / 3) + (k % 3 ? " and a partial one)" : ")");
      }
      if (!prim.mesh || prim.mesh->order.size() * 3 != k)
        return "mesh skeleton without its index (solid/field_leaf.h index_skeleton_mesh)";
      if (!prim.mesh->open_edge.empty())
        return "the mesh skeleton is not closed: " + prim.mesh->open_edge;
      break;
    case SkeletonKind::kPolyline:
      if (k < 2 || k > kMaxPolylinePoints) {
        return "a polyline needs 2 to " + std::to_string(kMaxPolylinePoints) + " points (got " +
               std::to_string(k) + ")";
      }
      break;
    default:
      return "unknown skeleton kind " + std::to_string(static_cast<int>(prim.kind));
  }
  for (size_t j = 0; j < k; ++j) {
    const Vec3& v = prim.points[j];
    if (!in_range(v.x) || !in_range(v.y) || !in_range(v.z)) {
      return "point " + std::to_string(j) + " must be finite and within ±2^64 (got (" + num(v.x) +
             ", " + num(v.y) + ", " + num(v.z) + "))";
    }
  }
  if (!(prim.radius > 0 && prim.radius < prim.influence)) {
    return "radius must be > 0 and < influence (got " + num(prim.radius) + ", " +
           num(prim.influence) + ")";
  }
  if (!in_range(prim.influence)) {
    return "influence must be finite and at most 2^64 (got " + num(prim.influence) + ")";
  }
  if (prim.exponent < 2 || prim.exponent > kMaxFieldExponent) {
    return "exponent must be in [2, " + std::to_string(kMaxFieldExponent) + "] (got " +
           std::to_string(prim.exponent) + ")";
  }
  if (prim.weight != 1 && prim.weight != -1) {
    return "weight must be +1 or -1 (got " + std::to_string(prim.weight) + ")";
  }
  const Vec3* q = prim.points.data();
  switch (prim.kind) {
    case SkeletonKind::kSegment:
      if (q[0] == q[1]) return "segment has zero length";
      break;
    case SkeletonKind::kPolyline:
      for (size_t j = 0; j + 1 < k; ++j) {
        if (q[j] == q[j + 1]) return "polyline piece " + std::to_string(j) + " has zero length";
      }
      break;
    case SkeletonKind::kTriangle:
      if (collinear(q[0], q[1], q[2])) return "triangle is degenerate (its points are collinear)";
      break;
    case SkeletonKind::kMesh:
      for (size_t t = 0; t < k / 3; ++t)
        if (collinear(q[3 * t], q[3 * t + 1], q[3 * t + 2]))
          return "mesh skeleton triangle " + std::to_string(t) +
                 " is degenerate (its points are collinear)";
      break;
    case SkeletonKind::kCircle:
      if (q[1] == Vec3{}) return "circle normal must not be zero";
      if (!(prim.circle_radius > 0 && in_range(prim.circle_radius))) {
        return "circle radius must be > 0 and at most 2^64 (got " + num(prim.circle_radius) + ")";
      }
      break;
    default:
      break;
  }
  return "";
}

}  // namespace

std::string validate(const FieldLeaf& leaf) {
  if (leaf.primitives.empty()) return "a field needs at least one primitive";
  Q t0;
  for (size_t i = 0; i < leaf.primitives.size(); ++i) {
    const FieldPrimitive& prim = leaf.primitives[i];
    std::string problem = primitive_problem(prim);
    if (problem.empty()) {
      const Q t = exact_threshold(prim);
      if (i == 0) {
        t0 = t;
      } else if (t != t0) {
        problem =
            "threshold (1 − r_T²/R²)^n differs from primitive 0's; a blend needs one threshold";
      }
    }
    if (!problem.empty()) return "primitive " + std::to_string(i) + ": " + problem;
  }
  return "";
}

std::string validate_placed(const FieldLeaf& leaf) {
  if (leaf.primitives.empty()) return "a field needs at least one primitive";
  for (size_t i = 0; i < leaf.primitives.size(); ++i)
    if (std::string problem = primitive_problem(leaf.primitives[i]); !problem.empty())
      return "primitive " + std::to_string(i) + ": " + problem;
  return "";
}

Bbox support_box(const FieldLeaf& leaf) { return field_support_box(leaf); }

double threshold(const FieldLeaf& leaf) {
  return nearest_double(exact_threshold(leaf.primitives.at(0)));
}

FieldValue evaluate(const FieldLeaf& leaf, const Vec3& p) {
  using D = V3<double>;
  const auto dv = [](const Vec3& v) { return D{v.x, v.y, v.z}; };
  const D P = dv(p);
  FieldValue out;
  for (const FieldPrimitive& prim : leaf.primitives) {
    const double R = prim.influence;
    const Vec3* q = prim.points.data();
    D c{};                // the closest skeleton point: ∇(d²) = 2(p − c)
    double axis = 0;      // a circle's r² when p is on its axis (d² = |p − c|² + r² there)
    bool pseudo = false;  // a mesh skeleton: d² and ½∇(d²) set directly
    double d2 = 0;
    D half{};
    switch (prim.kind) {
      case SkeletonKind::kPoint:
        c = dv(q[0]);
        break;
      case SkeletonKind::kSegment:
        c = detail::closest_on_segment(P, dv(q[0]), dv(q[1]));
        break;
      case SkeletonKind::kTriangle:
        c = detail::closest_on_triangle(P, dv(q[0]), dv(q[1]), dv(q[2]));
        break;
      case SkeletonKind::kPolyline: {
        double best = kInf;
        for (size_t j = 0; j + 1 < prim.points.size(); ++j) {
          if (far(p, p, vmin(q[j], q[j + 1]), vmax(q[j], q[j + 1]), R)) continue;
          const D cj = detail::closest_on_segment(P, dv(q[j]), dv(q[j + 1]));
          const double dj = detail::dot(P - cj, P - cj);
          if (dj < best) best = dj, c = cj;
        }
        if (best == kInf) continue;
        break;
      }
      case SkeletonKind::kMesh: {
        // d = r_T ± dist with ∇d = ±(p − c)/dist: ½∇(d²) = d·∇d.
        const Bbox& mb = prim.mesh->nodes[0].box;
        if (far(p, p, mb.min, mb.max, mesh_reach(prim))) continue;
        Vec3 closest;
        const double dist = std::sqrt(detail::mesh_closest(prim, p, closest));
        const bool inside = detail::mesh_side(prim, p) > 0;
        const double d = inside ? std::max(0.0, prim.radius - dist) : prim.radius + dist;
        const D u = dist > 0 ? (1 / dist) * (P - dv(closest)) : D{0, 0, 0};
        pseudo = true;
        d2 = d * d;
        half = (inside ? -d : d) * u;
        break;
      }
      case SkeletonKind::kCircle: {
        // c = centre + r·(in-plane direction of v). On the axis every circle point is closest:
        // c is taken as the centre there, ∇(d²) = 2v (the mean of the one-sided gradients).
        const D v = P - dv(q[0]), m = dv(q[1]);
        const D in_plane = v - (detail::dot(v, m) / detail::dot(m, m)) * m;
        const double rho = std::sqrt(detail::dot(in_plane, in_plane));
        if (rho > 0) {
          c = dv(q[0]) + (prim.circle_radius / rho) * in_plane;
        } else {
          c = dv(q[0]);
          axis = prim.circle_radius * prim.circle_radius;
        }
        break;
      }
    }
    if (!pseudo) {
      half = P - c;
      d2 = detail::dot(half, half) + axis;
    }
    const D v = half;
    const double R2 = R * R;
    if (!(d2 < R2)) continue;
    const double s = 1 - d2 / R2;
    double sn1 = 1;  // s^(n−1)
    for (int k = 1; k < prim.exponent; ++k) sn1 *= s;
    const double w = prim.weight;
    const double slope = -prim.exponent / R2 * sn1;  // g'(d²)
    out.value += w * sn1 * s;
    out.gradient = out.gradient + (2 * w * slope) * Vec3{v.x, v.y, v.z};
  }
  return out;
}

Sign sign(const FieldLeaf& leaf, const Vec3& p) {
  bool circle = false;
  {
    // Interval_nt<false> needs rounding toward +∞; the mode is per thread, restored on exit.
    CGAL::Protect_FPU_rounding<true> rounding;
    const I e = enclose(leaf, p, p, &circle);
    if (e.inf() > 0) return Sign::kInside;
    if (e.sup() < 0) return Sign::kOutside;
  }
  // Rationals, unless a circle primitive's support box holds p (its d needs a square root); a
  // circle elsewhere is pruned alike in both paths and does not stop the exact decision.
  return circle ? Sign::kUndecided : exact_sign(leaf, qv(p), p, p);
}

Sign sign_exact(const FieldLeaf& leaf, const Vec3& p) { return exact_sign(leaf, qv(p), p, p); }

namespace detail {

Bbox enclosure(const QPoint& p) {
  const auto [x0, x1] = CGAL::to_interval(p.x);
  const auto [y0, y1] = CGAL::to_interval(p.y);
  const auto [z0, z1] = CGAL::to_interval(p.z);
  return {{x0, y0, z0}, {x1, y1, z1}};
}

Sign sign_at(const FieldLeaf& leaf, const QPoint& p) {
  const Bbox box = enclosure(p);
  bool circle = false;
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    const I e = enclose(leaf, box.min, box.max, &circle);
    if (e.inf() > 0) return Sign::kInside;
    if (e.sup() < 0) return Sign::kOutside;
  }
  return circle ? Sign::kUndecided : exact_sign(leaf, p, box.min, box.max);
}

}  // namespace detail

bool exact(const FieldLeaf& leaf) {
  return std::none_of(leaf.primitives.begin(), leaf.primitives.end(),
                      [&](const FieldPrimitive& prim) {
                        return prim.kind == SkeletonKind::kCircle ||
                               (prim.kind == SkeletonKind::kMesh && leaf.primitives.size() > 1);
                      });
}

Range bound(const FieldLeaf& leaf, const Bbox& box) {
  bool circle = false;
  CGAL::Protect_FPU_rounding<true> rounding;
  const I e = enclose(leaf, box.min, box.max, &circle);
  if (std::isnan(e.inf()) || std::isnan(e.sup())) return {-kInf, kInf};
  return {e.inf(), e.sup()};
}

Range bound(const FieldLeaf& leaf, std::span<const uint32_t> primitives, const Bbox& box) {
  if (primitives.empty()) {  // f = 0 on the box
    CGAL::Protect_FPU_rounding<true> rounding;
    const I e = I(0) - threshold_interval(leaf.primitives[0]);
    return {e.inf(), e.sup()};
  }
  bool circle = false;
  CGAL::Protect_FPU_rounding<true> rounding;
  const I e = enclose(leaf, box.min, box.max, &circle, primitives);
  if (std::isnan(e.inf()) || std::isnan(e.sup())) return {-kInf, kInf};
  return {e.inf(), e.sup()};
}

}  // namespace cover::field
