// Kernels of warp leaves (warp.h; the data and the maps are defined in solid/warp_leaf.h).
//
// Conventions of this file
//   frame       local(p) = F·(p − point) with F the stored doubles (rows e0, e1, e2); world(y) =
//               point + F⁻¹·y with F⁻¹ the exact rational inverse (columns r1×r2, r2×r0, r0×r1
//               over det F, in CGAL::Gmpq), kept per thread for the last frame seen, as intervals
//               (CGAL::to_interval of each entry) and as doubles (truncated).
//   intervals   CGAL::Interval_nt<false> under one Protect_FPU_rounding guard per call. sin, cos
//               and atan2 run in round-to-nearest (a nested guard) at the ends of an interval and
//               are widened by 4 ulps (and to ±2⁻¹⁰⁰⁰ near 0). sin and cos of an angle interval
//               [a, b] also take ±1 at each n·π/2 that may lie in it (n over an enclosure of
//               [a, b]/(π/2), π enclosed by the doubles either side), are [−1, 1] when that spans
//               4 or more or reaches 2⁵², and are clamped to [−1, 1]. A box with a NaN end (an
//               overflow) becomes the whole line along that axis.
//   taper       s(y) is monotone in y between the clamp's ends: an interval of y clamps end to
//               end, and s is cut to the hull of the two scales.
//   bend        R = radius = 1/k, (u, v) = (Y − y0, Z − R) and, at θ̂ = θ_min (−) and θ_max (+),
//               d = cos θ̂·u + sin θ̂·v = ρ sin(φ − θ̂), e = −sin θ̂·u + cos θ̂·v = −ρ cos(φ − θ̂).
//               Beyond θ_max: d⁺ ≥ 0, e⁺ < 0, preimage (X, y_max + d⁺, R + e⁺); below θ_min:
//               d⁻ ≤ 0, e⁻ < 0, (X, y_min + d⁻, R + e⁻); the bent sector: d⁺ ≤ 0 ≤ d⁻ (two
//               half-planes that meet in that sector only, as θ_max − θ_min < π: validate()
//               compares it with π rounded down), (X, y_min + R·ψ, R − ρ) with ψ = φ − θ_min =
//               atan2(d⁻, −e⁻) ∈ [0, π]. Not in the image: e⁺ ≥ 0 and e⁻ ≥ 0 (ρ = 0 included).
//               These linear forms never need φ itself, so atan2's branch cut never matters.
//               The forward map over a box is split at y_min and y_max (ŷ is a point outside).
//   exact       taper's w⁻¹ in Gmpq; twist and bend are exactly the identity where their angle is
//               0 (θ = 0 at y = 0; ŷ = y0 with z < R), decided in Gmpq.
#include "cover/field/warp.h"

#include <CGAL/Gmpq.h>
#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>

#include "cover/field/closest.h"
#include "cover/field/detail/exact.h"

namespace cover::field {
namespace {

using I = CGAL::Interval_nt<false>;
using Q = CGAL::Gmpq;
using detail::V3;
using DV = V3<double>;
using IV = V3<I>;
using QV = V3<Q>;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPiLo = 0x1.921fb54442d18p+1;  // the doubles either side of π
constexpr double kPiHi = 0x1.921fb54442d19p+1;

DV dv(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 vec(const DV& v) { return {v.x, v.y, v.z}; }
bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// ---- frame --------------------------------------------------------------------------------

/// v/|v|, v scaled by its largest component first (|v|² cannot overflow); false when v is zero or
/// not finite.
bool unit(const Vec3& v, Vec3& out) {
  if (!finite(v)) return false;
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (m == 0) return false;
  const Vec3 s{v.x / m, v.y / m, v.z / m};
  const double n = std::sqrt(dot(s, s));
  out = {s.x / n, s.y / n, s.z / n};
  return true;
}

template <class T>
V3<T> local(const WarpLeaf& w, const V3<T>& p) {
  const V3<T> d{p.x - T(w.point.x), p.y - T(w.point.y), p.z - T(w.point.z)};
  const auto row = [&](const Vec3& e) { return T(e.x) * d.x + T(e.y) * d.y + T(e.z) * d.z; };
  return {row(w.frame[0]), row(w.frame[1]), row(w.frame[2])};
}
template <class T>
V3<T> world(const WarpLeaf& w, const T (&inv)[3][3], const V3<T>& y) {
  const auto row = [&](const T(&r)[3]) { return r[0] * y.x + r[1] * y.y + r[2] * y.z; };
  return {T(w.point.x) + row(inv[0]), T(w.point.y) + row(inv[1]), T(w.point.z) + row(inv[2])};
}

QV qv(const Vec3& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }
QV qcross(const QV& a, const QV& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
void exact_frame_inverse(const WarpLeaf& w, Q (&inv)[3][3]) {
  const QV r0 = qv(w.frame[0]), r1 = qv(w.frame[1]), r2 = qv(w.frame[2]);
  const QV c[3] = {qcross(r1, r2), qcross(r2, r0), qcross(r0, r1)};
  const Q det = detail::dot(r0, c[0]);
  for (int j = 0; j < 3; ++j) {
    inv[0][j] = c[j].x / det;
    inv[1][j] = c[j].y / det;
    inv[2][j] = c[j].z / det;
  }
}

struct FrameInverse {
  double key[9];
  I iv[3][3];
  double d[3][3];
};
/// F⁻¹ of w's frame, cached per thread for the last frame (inverse_box runs per query point).
FrameInverse frame_inverse(const WarpLeaf& w) {
  thread_local FrameInverse cache = [] {
    FrameInverse c{};
    c.key[0] = kNaN;  // equal to no frame
    return c;
  }();
  const double key[9] = {w.frame[0].x, w.frame[0].y, w.frame[0].z, w.frame[1].x, w.frame[1].y,
                         w.frame[1].z, w.frame[2].x, w.frame[2].y, w.frame[2].z};
  if (!std::equal(key, key + 9, cache.key)) {
    Q inv[3][3];
    exact_frame_inverse(w, inv);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const auto [lo, hi] = CGAL::to_interval(inv[i][j]);
        cache.iv[i][j] = I(lo, hi);
        cache.d[i][j] = CGAL::to_double(inv[i][j]);
      }
    }
    std::copy(key, key + 9, cache.key);
  }
  return cache;
}

// ---- intervals ----------------------------------------------------------------------------

I hull(const I& a, const I& b) { return I(std::min(a.inf(), b.inf()), std::max(a.sup(), b.sup())); }
IV hull(const IV& a, const IV& b) { return {hull(a.x, b.x), hull(a.y, b.y), hull(a.z, b.z)}; }
/// a ∩ [lo, hi] in `a`; false (a unchanged) when empty. A −0 lower end becomes +0.
bool clip(I& a, double lo, double hi) {
  const double l = a.inf() > lo ? a.inf() : lo, h = a.sup() < hi ? a.sup() : hi;
  if (!(l <= h)) return false;
  a = I(l, h);
  return true;
}
bool finite(const IV& a) {
  for (const I& c : {a.x, a.y, a.z}) {
    if (!std::isfinite(c.inf()) || !std::isfinite(c.sup())) return false;
  }
  return true;
}
IV box_iv(const Bbox& b) { return {I(b.min.x, b.max.x), I(b.min.y, b.max.y), I(b.min.z, b.max.z)}; }
/// The box of `a`; a coordinate with a NaN end (from an overflow) is the whole line.
Bbox to_box(const IV& a) {
  const auto nan = [](const I& c) { return std::isnan(c.inf()) || std::isnan(c.sup()); };
  const auto lo = [&](const I& c) { return nan(c) ? -kInf : c.inf(); };
  const auto hi = [&](const I& c) { return nan(c) ? kInf : c.sup(); };
  return {{lo(a.x), lo(a.y), lo(a.z)}, {hi(a.x), hi(a.y), hi(a.z)}};
}
Bbox whole() { return {{-kInf, -kInf, -kInf}, {kInf, kInf, kInf}}; }
IV everywhere() { return {I(-kInf, kInf), I(-kInf, kInf), I(-kInf, kInf)}; }

/// [lo, hi] of libm results widened by 4 ulps (glibc documents ≤ 1 ulp), and to ±2⁻¹⁰⁰⁰ near 0.
I widen(double lo, double hi) {
  for (int i = 0; i < 4; ++i) {
    lo = std::nextafter(lo, -kInf);
    hi = std::nextafter(hi, kInf);
  }
  return I(lo < 0x1p-1000 ? std::min(lo, -0x1p-1000) : lo,
           hi > -0x1p-1000 ? std::max(hi, 0x1p-1000) : hi);
}
I unit_clamp(const I& a) { return I(std::max(a.inf(), -1.0), std::min(a.sup(), 1.0)); }

struct SinCos {
  I s, c;
};
/// sin and cos over the angle interval t (see "intervals"). Rounding: upward on entry.
SinCos sincos(const I& t) {
  const I full(-1, 1);
  const I n = t / (I(kPiLo, kPiHi) / I(2));  // holds t/(π/2) for every t of the interval
  if (!(std::abs(n.inf()) < 0x1p52 && std::abs(n.sup()) < 0x1p52) || n.sup() - n.inf() >= 4) {
    return {full, full};
  }
  double sa, sb, ca, cb;
  {
    CGAL::Protect_FPU_rounding<true> nearest(CGAL_FE_TONEAREST);
    sa = std::sin(t.inf());
    sb = std::sin(t.sup());
    ca = std::cos(t.inf());
    cb = std::cos(t.sup());
  }
  I s = widen(std::min(sa, sb), std::max(sa, sb)), c = widen(std::min(ca, cb), std::max(ca, cb));
  for (double k = std::ceil(n.inf()); k <= n.sup(); ++k) {      // sin, cos are monotone in between
    const int r = static_cast<int>(k - 4 * std::floor(k / 4));  // k mod 4 (exact: |k| < 2⁵²)
    if (r % 2 == 0) {
      c = hull(c, I(r == 0 ? 1 : -1));
    } else {
      s = hull(s, I(r == 1 ? 1 : -1));
    }
  }
  return {unit_clamp(s), unit_clamp(c)};
}

/// atan2(d, c) over the box c × d, d ≥ 0, in [0, π]: the box holds the origin (all of [0, π]) or
/// its angles are an interval ending at two corners. Rounding: upward on entry.
I angle(const I& c, const I& d) {
  const double d0 = d.inf() > 0 ? d.inf() : 0.0;
  if (d0 == 0 && c.inf() <= 0 && c.sup() >= 0) return I(0, kPiHi);
  double a[4];
  {
    CGAL::Protect_FPU_rounding<true> nearest(CGAL_FE_TONEAREST);
    a[0] = std::atan2(d0, c.inf());
    a[1] = std::atan2(d0, c.sup());
    a[2] = std::atan2(d.sup(), c.inf());
    a[3] = std::atan2(d.sup(), c.sup());
  }
  const I r = widen(*std::min_element(a, a + 4), *std::max_element(a, a + 4));
  return I(std::max(r.inf(), 0.0), std::min(r.sup(), kPiHi));
}

// ---- the local maps -----------------------------------------------------------------------

double twist_rate(const WarpLeaf& w) { return w.degrees_per_unit * (kPiLo / 180); }
I twist_rate_i(const WarpLeaf& w) { return I(w.degrees_per_unit) * I(kPiLo, kPiHi) / I(180); }

/// s at a clamped y (double, interval or rational).
template <class T>
T taper_scale(const WarpLeaf& w, const T& yc) {
  const T r0(w.range[0]), s0(w.scale[0]);
  return s0 + (T(w.scale[1]) - s0) * (yc - r0) / (T(w.range[1]) - r0);
}
I taper_scale_i(const WarpLeaf& w, const I& y) {
  const double r0 = w.range[0], r1 = w.range[1];
  I s = taper_scale(w, I(std::clamp(y.inf(), r0, r1), std::clamp(y.sup(), r0, r1)));
  clip(s, std::min(w.scale[0], w.scale[1]), std::max(w.scale[0], w.scale[1]));
  return s;
}

DV forward_local(const WarpLeaf& w, const DV& p) {
  switch (w.kind) {
    case WarpKind::kTwist: {
      const double t = twist_rate(w) * p.y, c = std::cos(t), s = std::sin(t);
      return {p.x * c - p.z * s, p.y, p.x * s + p.z * c};
    }
    case WarpKind::kTaper: {
      const double s = taper_scale(w, std::clamp(p.y, w.range[0], w.range[1]));
      return {s * p.x, p.y, s * p.z};
    }
    case WarpKind::kBend: {
      const double R = w.radius, yh = std::clamp(p.y, w.range[0], w.range[1]);
      const double t = (yh - w.center) / R, c = std::cos(t), s = std::sin(t), d = p.y - yh;
      return {p.x, -s * (p.z - R) + w.center + c * d, c * (p.z - R) + R + s * d};
    }
  }
  return {kNaN, kNaN, kNaN};
}

using M3 = std::array<std::array<double, 3>, 3>;

/// L⁻¹(q) in doubles; *J (when given) receives its Jacobian (rows: the gradients of x, y, z).
DV inverse_local(const WarpLeaf& w, const DV& q, M3* J = nullptr) {
  const DV nan{kNaN, kNaN, kNaN};
  switch (w.kind) {
    case WarpKind::kTwist: {  // (x c + z s, y, −x s + z c), θ = a·y
      const double a = twist_rate(w), t = a * q.y, c = std::cos(t), s = std::sin(t);
      if (J) *J = {{{c, a * (q.z * c - q.x * s), s}, {0, 1, 0}, {-s, -a * (q.x * c + q.z * s), c}}};
      return {q.x * c + q.z * s, q.y, -q.x * s + q.z * c};
    }
    case WarpKind::kTaper: {
      const double r0 = w.range[0], r1 = w.range[1];
      const double s = taper_scale(w, std::clamp(q.y, r0, r1));
      const double ds = q.y >= r0 && q.y <= r1 ? (w.scale[1] - w.scale[0]) / (r1 - r0) : 0;
      if (J) *J = {{{1 / s, -q.x * ds / (s * s), 0}, {0, 1, 0}, {0, -q.z * ds / (s * s), 1 / s}}};
      return {q.x / s, q.y, q.z / s};
    }
    case WarpKind::kBend: {
      const double R = w.radius, u = q.y - w.center, v = q.z - R;
      const double tm = (w.range[0] - w.center) / R, tp = (w.range[1] - w.center) / R;
      const double cm = std::cos(tm), sm = std::sin(tm), cp = std::cos(tp), sp = std::sin(tp);
      const double dp = cp * u + sp * v, ep = -sp * u + cp * v;
      const double dm = cm * u + sm * v, em = -sm * u + cm * v;
      if (dp >= 0 && ep < 0) {
        if (J) *J = {{{1, 0, 0}, {0, cp, sp}, {0, -sp, cp}}};
        return {q.x, w.range[1] + dp, R + ep};
      }
      if (dm <= 0 && em < 0) {
        if (J) *J = {{{1, 0, 0}, {0, cm, sm}, {0, -sm, cm}}};
        return {q.x, w.range[0] + dm, R + em};
      }
      const double rho = std::hypot(u, v), r2 = rho * rho;  // y = y0 + R·atan2(u, −v)
      if (!(dp <= 0 && dm >= 0 && rho > 0)) return nan;
      if (J) *J = {{{1, 0, 0}, {0, -R * v / r2, R * u / r2}, {0, -u / rho, -v / rho}}};
      return {q.x, w.range[0] + R * std::atan2(dm, -em), R - rho};
    }
  }
  return nan;
}

IV twist_i(const WarpLeaf& w, const IV& p, bool inverse) {  // rotation by θ (−θ: inverse)
  const SinCos t = sincos(twist_rate_i(w) * p.y);
  const I s = inverse ? -t.s : t.s;
  return {p.x * t.c - p.z * s, p.y, p.x * s + p.z * t.c};
}

/// Bend's L over a box, split at y_min and y_max.
IV bend_forward_i(const WarpLeaf& w, const IV& p) {
  const double lo = w.range[0], hi = w.range[1], a = p.y.inf(), b = p.y.sup();
  const I R(w.radius), y0(w.center), zr = p.z - R;
  std::optional<IV> out;
  const auto piece = [&](const I& yh, const I& d) {  // ŷ and y − ŷ over one piece
    const SinCos t = sincos((yh - y0) / R);
    const IV r{p.x, -(t.s * zr) + y0 + t.c * d, t.c * zr + R + t.s * d};
    out = out ? hull(*out, r) : r;
  };
  if (a < lo) piece(I(lo), I(a, std::min(b, lo)) - I(lo));
  if (b >= lo && a <= hi) piece(I(std::max(a, lo), std::min(b, hi)), I(0));
  if (b > hi) piece(I(hi), I(std::max(a, hi), b) - I(hi));
  return *out;  // a ≤ b: some piece holds it
}

/// Bend's L⁻¹ over a box (see "bend"): the hull over the regions the box may meet; none when it
/// meets none. An overflow gives all of space (partial).
std::optional<IV> bend_inverse_i(const WarpLeaf& w, const IV& q, bool& partial) {
  const I R(w.radius), u = q.y - I(w.center), v = q.z - R;
  const SinCos m = sincos((I(w.range[0]) - I(w.center)) / R);
  const SinCos p = sincos((I(w.range[1]) - I(w.center)) / R);
  I dm = m.c * u + m.s * v, em = m.c * v - m.s * u, dp = p.c * u + p.s * v, ep = p.c * v - p.s * u;
  if (!finite(IV{dm, em, dp}) || !finite(IV{ep, u, v})) {
    partial = true;
    return everywhere();
  }
  partial = ep.sup() >= 0 && em.sup() >= 0;
  std::optional<IV> out;
  const auto add = [&](const IV& r) { out = out ? hull(*out, r) : r; };
  if (dp.inf() <= 0 && dm.sup() >= 0 && (ep.inf() < 0 || em.inf() < 0)) {  // the bent sector
    I d = dm;
    clip(d, 0, kInf);
    I y = I(w.range[0]) + R * angle(-em, d);
    I z = R - CGAL::sqrt(CGAL::square(u) + CGAL::square(v));
    if (clip(y, w.range[0], w.range[1]) && clip(z, -kInf, w.radius)) add({q.x, y, z});
  }
  if (clip(dp, 0, kInf) && clip(ep, -kInf, 0) && ep.inf() < 0) {  // beyond θ_max
    add({q.x, I(w.range[1]) + dp, R + ep});
  }
  if (clip(dm, -kInf, 0) && clip(em, -kInf, 0) && em.inf() < 0) {  // below θ_min
    add({q.x, I(w.range[0]) + dm, R + em});
  }
  return out;
}

IV forward_local_i(const WarpLeaf& w, const IV& p) {
  switch (w.kind) {
    case WarpKind::kTwist:
      return twist_i(w, p, false);
    case WarpKind::kTaper: {
      const I s = taper_scale_i(w, p.y);
      return {s * p.x, p.y, s * p.z};
    }
    case WarpKind::kBend:
      return bend_forward_i(w, p);
  }
  return everywhere();
}

/// L⁻¹ over a box; none (nullopt) and partial as in InverseBox.
std::optional<IV> inverse_local_i(const WarpLeaf& w, const IV& q, bool& partial) {
  switch (w.kind) {
    case WarpKind::kTwist:
      return twist_i(w, q, true);
    case WarpKind::kTaper: {
      const I s = taper_scale_i(w, q.y);
      return IV{q.x / s, q.y, q.z / s};
    }
    case WarpKind::kBend:
      return bend_inverse_i(w, q, partial);
  }
  return everywhere();
}

// ---- validation ---------------------------------------------------------------------------

std::string num(double x) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}
std::string pair(const double (&v)[2]) {
  return std::string("[").append(num(v[0])).append(", ").append(num(v[1])).append("]");
}

std::string range_problem(const std::string& kind, const double (&r)[2]) {
  if (!std::isfinite(r[0]) || !std::isfinite(r[1])) {
    return kind + "range must be finite (got " + pair(r) + ")";
  }
  if (!(r[0] < r[1])) return kind + "range must be increasing (got " + pair(r) + ")";
  return "";
}

std::string bend_problem(const WarpLeaf& w, const Bbox& child_box) {
  if (!std::isfinite(w.center)) return "bend: center must be finite (got " + num(w.center) + ")";
  if (!std::isfinite(w.radius)) return "bend: radius must be finite (got " + num(w.radius) + ")";
  if (!(w.radius > 0)) return "bend: radius must be > 0 (got " + num(w.radius) + ")";
  if (Q(w.range[1]) - Q(w.range[0]) > Q(kPiLo) * Q(w.radius)) {
    return "bend: range spans more than pi radians at this radius";
  }
  if (child_box.empty() || !finite(child_box.min) || !finite(child_box.max)) {
    return "bend: the child's box must be finite and non-empty";
  }
  double z;
  {
    CGAL::Protect_FPU_rounding<true> rounding;
    z = local(w, box_iv(child_box)).z.sup();
  }
  if (!(z < w.radius)) {
    return "bend: the child reaches the centre of curvature (radius " + num(w.radius) +
           ", the child extends to local z = " + num(z) + ")";
  }
  return "";
}

}  // namespace

std::string make_frame(WarpLeaf& w) {
  Vec3 e1, t, e2;
  if (!unit(w.direction, e1)) return "axis direction is zero or not finite";
  const bool bend = w.kind == WarpKind::kBend;
  if (!unit(w.toward, t)) {
    if (bend) return "bend: toward is zero or not finite";
    t = {0, 0, 0};
  }
  Vec3 perp = t - dot(t, e1) * e1;
  // Parallel: the part of unit `toward` ⊥ e1 is under 1e-9 long. Twist and taper then take the
  // coordinate axis least aligned with e1.
  if (!(std::sqrt(dot(perp, perp)) > 1e-9)) {
    if (bend) return "bend: toward is parallel to the axis";
    const double ax = std::abs(e1.x), ay = std::abs(e1.y), az = std::abs(e1.z);
    t = ax <= ay && ax <= az ? Vec3{1, 0, 0} : (ay <= az ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
    perp = t - dot(t, e1) * e1;
  }
  unit(perp, e2);
  unit(e2 - dot(e2, e1) * e1, e2);  // Gram–Schmidt twice: e2 ⊥ e1 to rounding
  Vec3 e0;
  unit(cross(e2, e1), e0);  // e0 = e2 × e1: L turns e0 toward e2, a right-hand turn about e1
  w.frame[0] = e0, w.frame[1] = e1, w.frame[2] = e2;
  return "";
}

std::string validate(const WarpLeaf& w, const Bbox& child_box) {
  const std::string kind = std::string(to_string(w.kind)) + ": ";
  if (!finite(w.point)) return kind + "point must be finite";
  switch (w.kind) {
    case WarpKind::kTwist: {
      const double a = w.degrees_per_unit;
      if (!std::isfinite(a)) return "twist: degrees_per_unit must be finite (got " + num(a) + ")";
      if (std::abs(a) > 1e6) {
        return "twist: degrees_per_unit must be within [-1e6, 1e6] (got " + num(a) + ")";
      }
      return "";
    }
    case WarpKind::kTaper: {
      if (std::string r = range_problem(kind, w.range); !r.empty()) return r;
      for (const double s : w.scale) {
        if (!std::isfinite(s)) return "taper: scale must be finite (got " + num(s) + ")";
        if (!(s > 0)) return "taper: scale must be > 0 (got " + num(s) + ")";
        if (s > 1e6) return "taper: scale must be <= 1e6 (got " + num(s) + ")";
      }
      return "";
    }
    case WarpKind::kBend:
      if (std::string r = range_problem(kind, w.range); !r.empty()) return r;
      return bend_problem(w, child_box);
  }
  return "unknown warp kind " + std::to_string(static_cast<int>(w.kind));
}

Vec3 forward(const WarpLeaf& w, const Vec3& p) {
  return vec(world(w, frame_inverse(w).d, forward_local(w, local(w, dv(p)))));
}

Vec3 inverse(const WarpLeaf& w, const Vec3& q) {
  return vec(world(w, frame_inverse(w).d, inverse_local(w, local(w, dv(q)))));
}

Mat3 inverse_jacobian(const WarpLeaf& w, const Vec3& q) {
  const FrameInverse fi = frame_inverse(w);
  M3 J;
  if (std::isnan(inverse_local(w, local(w, dv(q)), &J).x)) {
    const Vec3 nan{kNaN, kNaN, kNaN};
    return {{nan, nan, nan}};
  }
  Mat3 out;
  for (int i = 0; i < 3; ++i) {  // row i of F⁻¹·J·F
    double r[3];
    for (int j = 0; j < 3; ++j) {
      r[j] = 0;
      for (int k = 0; k < 3; ++k) {
        r[j] += fi.d[i][k] *
                (J[k][0] * w.frame[0][j] + J[k][1] * w.frame[1][j] + J[k][2] * w.frame[2][j]);
      }
    }
    out.row[i] = {r[0], r[1], r[2]};
  }
  return out;
}

Bbox forward_box(const WarpLeaf& w, const Bbox& box) {
  if (box.empty()) return box;
  const FrameInverse fi = frame_inverse(w);
  CGAL::Protect_FPU_rounding<true> rounding;
  const IV p = local(w, box_iv(box));
  if (!finite(p)) return whole();
  return to_box(world(w, fi.iv, forward_local_i(w, p)));
}

InverseBox inverse_box(const WarpLeaf& w, const Bbox& world_box) {
  InverseBox out;
  out.none = world_box.empty();
  if (out.none) return out;
  const FrameInverse fi = frame_inverse(w);
  CGAL::Protect_FPU_rounding<true> rounding;
  const IV q = local(w, box_iv(world_box));
  if (!finite(q)) {
    out.box = whole();
    out.partial = w.kind == WarpKind::kBend;
    return out;
  }
  const std::optional<IV> p = inverse_local_i(w, q, out.partial);
  out.none = !p;
  if (p) out.box = to_box(world(w, fi.iv, *p));
  return out;
}

bool exact_inverse(const WarpLeaf& w, const Vec3& q, Vec3& out) {
  QV p;
  if (!detail::rational_inverse(w, qv(q), p)) return false;
  const Q* c[3] = {&p.x, &p.y, &p.z};
  double d[3];
  for (int i = 0; i < 3; ++i) {
    d[i] = CGAL::to_double(*c[i]);  // exact when *c[i] is a double
    if (!std::isfinite(d[i]) || Q(d[i]) != *c[i]) return false;
  }
  out = {d[0], d[1], d[2]};
  return true;
}

namespace detail {

bool rational_inverse(const WarpLeaf& w, const QPoint& q, QPoint& out) {
  const QV y = local(w, q);
  if (w.kind == WarpKind::kTwist || w.kind == WarpKind::kBend) {  // L = identity where θ = 0
    const bool flat =
        w.kind == WarpKind::kTwist
            ? y.y == 0
            : std::clamp(y.y, Q(w.range[0]), Q(w.range[1])) == Q(w.center) && y.z < Q(w.radius);
    if (flat) out = q;
    return flat;
  }
  if (w.kind != WarpKind::kTaper) return false;
  const Q s = taper_scale(w, std::clamp(y.y, Q(w.range[0]), Q(w.range[1])));
  Q inv[3][3];
  exact_frame_inverse(w, inv);
  out = world(w, inv, QV{y.x / s, y.y, y.z / s});
  return true;
}

}  // namespace detail

}  // namespace cover::field
