// Field leaves along rays (covering/ray.h field_spans): the crossings of each field's surface by
// certified interval bisection.
//
// On a parameter interval [a, b] the ray's points lie in the box of its two end points (padded
// by two ulps per side: the true points o + t·d are within an ulp of their doubles), and
// field::bound over that box encloses f − T on the whole piece. Where the enclosure excludes 0
// the piece holds no crossing and its sign is known; otherwise it is halved, down to pieces of
// 2^-kDepth of the ray's run through the support box. On such a piece a crossing is reported
// where the certified signs at both ends differ (the end points' padded boxes: the intermediate
// value theorem along the true ray puts a root between), at the piece's midpoint: its t is
// within half a piece of a true crossing. The sign state along the ray starts outside (f ≤ 0 on
// the support box's boundary) and every reported crossing flips it, so crossings alternate and
// the sweep's counts stay 0 or 1. What bisection cannot see: a pair of crossings closer than a
// piece (a tangent ray, a film thinner than the piece) leaves the signs at both ends equal; such
// pieces, and pieces whose end signs stay undecided, are counted in RayResult::uncertain.

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "cover/covering/detail/implicit.h"
#include "cover/covering/ray.h"
#include "cover/covering/ray_steps.h"
#include "cover/field/field.h"

namespace cover {

namespace detail {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

/// The box of the ray's points for t in [a, b]. Each coordinate o + t·d is rounded twice (the
/// product, the sum): within 2^-52·(|o| + |t·d|) of the true point, which the padding covers
/// with room (and one more step outward).
Bbox piece_box(const Ray& ray, double a, double b) {
  Bbox box;
  for (int axis = 0; axis < 3; ++axis) {
    const double o = ray.origin[axis], d = ray.dir[axis];
    const double pa = o + a * d, pb = o + b * d;
    const double pad = (std::abs(o) + std::max(std::abs(a * d), std::abs(b * d))) * 0x1p-50;
    const double lo = std::nextafter(std::min(pa, pb) - pad, -kInf);
    const double hi = std::nextafter(std::max(pa, pb) + pad, kInf);
    (axis == 0 ? box.min.x : axis == 1 ? box.min.y : box.min.z) = lo;
    (axis == 0 ? box.max.x : axis == 1 ? box.max.y : box.max.z) = hi;
  }
  return box;
}

/// [t0, t1] of the ray inside the closed box (t ≥ 0), widened by 2^-40 of |t| (the slab
/// divisions' rounding is a few ulps of t); empty (t0 > t1) when it misses.
std::pair<double, double> clip(const Ray& ray, const Bbox& box) {
  double t0 = 0, t1 = kInf;
  for (int a = 0; a < 3; ++a) {
    const double o = ray.origin[a], d = ray.dir[a];
    if (d == 0) {
      if (o < box.min[a] || o > box.max[a]) return {1, 0};
      continue;
    }
    double ta = (box.min[a] - o) / d, tb = (box.max[a] - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  const double pad = (std::abs(t0) + std::abs(t1)) * 0x1p-40 + 1e-300;
  if (t0 - pad > t1 + pad) return {1, 0};
  return {std::max(0.0, t0 - pad), t1 + pad};
}

}  // namespace detail

namespace {

using detail::clip;
using detail::piece_box;

constexpr int kDepth = 20;  // finest piece: 2^-20 of the run through the support box

/// The primitives the ray passes: each one's parameter run through its support box
/// (solid/field_leaf.h primitive_support_box), padded as clip(). Outside its run a primitive's
/// term is exactly 0 on the ray.
struct Active {
  uint32_t primitive;
  double t0, t1;
  bool positive;
};

void active_primitives(const FieldLeaf& f, const Ray& ray, std::vector<Active>& out) {
  out.clear();
  for (uint32_t i = 0; i < f.primitives.size(); ++i) {
    const FieldPrimitive& p = f.primitives[i];
    const Bbox box = primitive_support_box(p);
    const auto [t0, t1] = clip(ray, box);
    if (t0 <= t1) out.push_back({i, t0, t1, p.weight > 0});
  }
}

/// +1 (f > T), −1 (f < T) or 0 (undecided) on the box, summing the `subset` only.
int box_sign(const FieldLeaf& f, std::span<const uint32_t> subset, const Bbox& box) {
  const field::Range r = field::bound(f, subset, box);
  return r.lo > 0 ? 1 : (r.hi < 0 ? -1 : 0);
}

struct Walker {
  const FieldLeaf& f;
  const Ray& ray;
  uint32_t leaf;
  double finest;
  int state;  ///< the sign just before the piece being looked at: +1 inside, −1 outside
  std::vector<RayHit>& hits;
  uint32_t& uncertain;
  const std::vector<Active>& active;
  std::vector<uint32_t> subset;

  /// The primitives whose runs meet [a, b]; false when none is positive (then f ≤ 0 < T there).
  bool select(double a, double b) {
    subset.clear();
    bool positive = false;
    for (const Active& x : active)
      if (x.t0 <= b && x.t1 >= a) {
        subset.push_back(x.primitive);
        positive |= x.positive;
      }
    return positive;
  }

  int sign_at(double t) {
    if (!select(t, t)) return -1;
    return box_sign(f, subset, piece_box(ray, t, t));
  }

  void crossing(double t, int to) {
    if (to == state) return;
    // Leaving the leaf (inside → outside) counts +1, entering −1, as for triangles.
    hits.push_back({t, Span::kNone, leaf, Span::kNone, static_cast<int8_t>(to < 0 ? 1 : -1)});
    state = to;
  }

  void piece(double a, double b) {
    const int s = select(a, b) ? box_sign(f, subset, piece_box(ray, a, b)) : -1;
    if (s != 0) {
      if (s != state) {  // a crossing the finer pieces before missed
        ++uncertain;
        crossing(a, s);
      }
      return;
    }
    const double m = 0.5 * (a + b);
    if (b - a <= finest || !(m > a && m < b)) {
      const int sa = sign_at(a), sb = sign_at(b);
      if (sa != 0 && sb != 0 && sa != sb) {
        if (sa != state) ++uncertain;
        state = sa;
        crossing(m, sb);
      } else {
        ++uncertain;  // a tangency or a film thinner than the piece, or undecided ends
        if (sb != 0 && sb != state) crossing(m, sb);
      }
      return;
    }
    piece(a, m);
    piece(m, b);
  }
};

}  // namespace

uint32_t field_crossings(const Solid& solid, uint32_t leaf, const Ray& ray,
                         std::vector<RayHit>& hits) {
  const Leaf& l = solid.leaves[leaf];
  const auto [t0, t1] = clip(ray, l.bbox);
  if (!(t0 < t1)) return 0;
  const FieldLeaf& f = solid.fields[l.field];
  thread_local std::vector<Active> active;  // per-thread scratch: no allocation per ray
  active_primitives(f, ray, active);
  uint32_t uncertain = 0;
  Walker w{f, ray, leaf, (t1 - t0) * std::ldexp(1.0, -kDepth), -1, hits, uncertain, active, {}};
  // The support box's boundary is outside (every positive term is 0 there); an origin inside
  // the box starts from its own certified sign (inside there: the leaf's hits then sum to +1,
  // its winding at the origin, as for a mesh leaf).
  if (t0 == 0) {
    w.state = w.sign_at(0);
    if (w.state == 0) {
      ++uncertain;
      w.state = field::evaluate(f, ray.origin).value > field::threshold(f) ? 1 : -1;
    }
  }
  // Only where some positive primitive's run reaches can f exceed T: the walk covers the runs'
  // union, each maximal run at once.
  std::vector<std::pair<double, double>> runs;
  for (const Active& x : active)
    if (x.positive) runs.push_back({std::max(x.t0, t0), std::min(x.t1, t1)});
  std::sort(runs.begin(), runs.end());
  for (size_t i = 0; i < runs.size();) {
    double a = runs[i].first, b = runs[i].second;
    for (++i; i < runs.size() && runs[i].first <= b; ++i) b = std::max(b, runs[i].second);
    if (a < b) {
      if (w.state > 0 && a > t0) {  // outside between runs: a crossing missed before
        ++uncertain;
        w.crossing(a, -1);
      }
      w.piece(a, b);
    }
  }
  if (w.state > 0) w.crossing(t1, -1);  // cannot happen for a sound bound: the box's exit
  return uncertain;
}

}  // namespace cover
