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

#include <cmath>
#include <limits>

#include "cover/covering/ray.h"
#include "cover/covering/ray_steps.h"
#include "cover/field/field.h"

namespace cover {
namespace {

constexpr int kDepth = 20;  // finest piece: 2^-20 of the run through the support box
constexpr double kInf = std::numeric_limits<double>::infinity();

double down2(double x) { return std::nextafter(std::nextafter(x, -kInf), -kInf); }
double up2(double x) { return std::nextafter(std::nextafter(x, kInf), kInf); }

/// The box of the ray's points for t in [a, b], padded (see above).
Bbox piece_box(const Ray& ray, double a, double b) {
  const Vec3 p = ray.origin + a * ray.dir, q = ray.origin + b * ray.dir;
  Bbox box;
  box.min = {down2(std::min(p.x, q.x)), down2(std::min(p.y, q.y)), down2(std::min(p.z, q.z))};
  box.max = {up2(std::max(p.x, q.x)), up2(std::max(p.y, q.y)), up2(std::max(p.z, q.z))};
  return box;
}

/// +1 (f > T), −1 (f < T) or 0 (undecided) on the box.
int box_sign(const FieldLeaf& f, const Bbox& box) {
  const field::Range r = field::bound(f, box);
  return r.lo > 0 ? 1 : (r.hi < 0 ? -1 : 0);
}

/// [t0, t1] of the ray inside the closed box (t ≥ 0), widened by a relative 2^-40 (the slab
/// divisions' rounding); empty (t0 > t1) when it misses.
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
  if (t0 > t1) return {1, 0};
  const double pad = (t1 - t0) * 0x1p-40 + 1e-300;
  return {std::max(0.0, t0 - pad), t1 + pad};
}

struct Walker {
  const FieldLeaf& f;
  const Ray& ray;
  uint32_t leaf;
  double finest;
  int state;  ///< the sign just before the piece being looked at: +1 inside, −1 outside
  std::vector<RayHit>& hits;
  uint32_t& uncertain;

  void crossing(double t, int to) {
    if (to == state) return;
    // Leaving the leaf (inside → outside) counts +1, entering −1, as for triangles.
    hits.push_back({t, Span::kNone, leaf, Span::kNone, static_cast<int8_t>(to < 0 ? 1 : -1)});
    state = to;
  }

  void piece(double a, double b) {
    const int s = box_sign(f, piece_box(ray, a, b));
    if (s != 0) {
      if (s != state) {  // a crossing the finer pieces before missed
        ++uncertain;
        crossing(a, s);
      }
      return;
    }
    if (b - a <= finest) {
      const int sa = box_sign(f, piece_box(ray, a, a)), sb = box_sign(f, piece_box(ray, b, b));
      if (sa != 0 && sb != 0 && sa != sb) {
        if (sa != state) ++uncertain;
        state = sa;
        crossing(0.5 * (a + b), sb);
      } else {
        ++uncertain;  // a tangency or a film thinner than the piece, or undecided ends
        if (sb != 0 && sb != state) crossing(0.5 * (a + b), sb);
      }
      return;
    }
    const double m = 0.5 * (a + b);
    if (!(m > a && m < b)) {  // no double between: treat as finest
      const int sb = box_sign(f, piece_box(ray, b, b));
      ++uncertain;
      if (sb != 0 && sb != state) crossing(m, sb);
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
  uint32_t uncertain = 0;
  // The support box's boundary is outside (every positive term is 0 there); an origin inside
  // the box starts from its own certified sign (inside there: the leaf's hits then sum to +1,
  // its winding at the origin, as for a mesh leaf).
  int start = -1;
  if (t0 == 0) {
    start = box_sign(solid.fields[l.field], piece_box(ray, 0, 0));
    if (start == 0) {
      ++uncertain;
      start = field::evaluate(solid.fields[l.field], ray.origin).value >
                      field::threshold(solid.fields[l.field])
                  ? 1
                  : -1;
    }
  }
  Walker w{solid.fields[l.field],
           ray,
           leaf,
           (t1 - t0) * std::ldexp(1.0, -kDepth),
           start,
           hits,
           uncertain};
  w.piece(t0, t1);
  if (w.state > 0) w.crossing(t1, -1);  // cannot happen for a sound bound: the box's exit
  return uncertain;
}

}  // namespace cover
