// Warp leaves (field/warp.h): round trips of w and w⁻¹, the sound enclosures against sampled
// points, the inverse's Jacobian against finite differences, the exact inverse against identities
// checked in rationals (CGAL::Gmpq, no inverse matrix), the frame and validation messages.
// Every random test is seeded.
#include "cover/field/warp.h"

#include <CGAL/Gmpq.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace cover::field {
namespace {

using Q = CGAL::Gmpq;
using Rng = std::mt19937_64;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Bbox box(const Vec3& a, const Vec3& b) {
  Bbox r;
  r.add(a);
  r.add(b);
  return r;
}
Vec3 size(const Bbox& b) { return b.max - b.min; }
double norm(const Vec3& v) { return std::sqrt(dot(v, v)); }
double magnitude(const Bbox& b) {
  return std::max({std::abs(b.min.x), std::abs(b.min.y), std::abs(b.min.z), std::abs(b.max.x),
                   std::abs(b.max.y), std::abs(b.max.z)});
}
/// b grown by `slack` on every side.
Bbox grown(const Bbox& b, double slack) {
  return box(b.min - Vec3{slack, slack, slack}, b.max + Vec3{slack, slack, slack});
}
bool contains(const Bbox& b, const Vec3& p, double slack) { return grown(b, slack).contains(p); }

Vec3 sample(Rng& rng, const Bbox& b) {
  std::uniform_real_distribution<double> t(0, 1);
  const Vec3 s = size(b);
  return {b.min.x + t(rng) * s.x, b.min.y + t(rng) * s.y, b.min.z + t(rng) * s.z};
}
/// Sample i of a box: its 8 corners first, then uniform points.
Vec3 sample(Rng& rng, const Bbox& b, int i) {
  if (i >= 8) return sample(rng, b);
  return {(i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y, (i & 4) ? b.max.z : b.min.z};
}
/// A box of half-size up to `half` centred in `region`.
Bbox random_box(Rng& rng, const Bbox& region, double half) {
  std::uniform_real_distribution<double> t(0, 1);
  const Vec3 c = sample(rng, region);
  const Vec3 h{half * t(rng), half * t(rng), half * t(rng)};
  return box(c - h, c + h);
}

WarpLeaf framed(WarpLeaf w) {
  EXPECT_EQ(make_frame(w), "");
  return w;
}
WarpLeaf twist(const Vec3& point, const Vec3& direction, const Vec3& toward, double rate) {
  WarpLeaf w;
  w.kind = WarpKind::kTwist;
  w.point = point, w.direction = direction, w.toward = toward, w.degrees_per_unit = rate;
  return framed(w);
}
WarpLeaf taper(const Vec3& point, const Vec3& direction, const Vec3& toward, double r0, double r1,
               double s0, double s1) {
  WarpLeaf w;
  w.kind = WarpKind::kTaper;
  w.point = point, w.direction = direction, w.toward = toward;
  w.range[0] = r0, w.range[1] = r1, w.scale[0] = s0, w.scale[1] = s1;
  return framed(w);
}
WarpLeaf bend(const Vec3& point, const Vec3& direction, const Vec3& toward, double r0, double r1,
              double center, double radius) {
  WarpLeaf w;
  w.kind = WarpKind::kBend;
  w.point = point, w.direction = direction, w.toward = toward;
  w.range[0] = r0, w.range[1] = r1, w.center = center, w.radius = radius;
  return framed(w);
}

struct Case {
  std::string name;
  WarpLeaf w;
  Bbox child;  ///< validate() accepts it
};
std::vector<Case> cases() {
  const Vec3 d{1, 2, 3}, t{0, 1, -1}, y{0, 1, 0}, z{0, 0, 1};
  return {
      {"twist oblique", twist({0.5, -1, 2}, d, t, 37), box({-1, -3, 0}, {2, 1, 4})},
      {"twist fast, toward on the axis", twist({}, z, {0, 0, 5}, -720),
       box({-1, -1, -1.5}, {1, 1, 1.5})},
      {"taper oblique", taper({1, 0, -1}, d, t, -1, 2, 0.5, 2), box({-1, -2, -3}, {3, 2, 1})},
      {"taper on y", taper({}, y, z, 0, 1, 1, 0.5), box({-1, -1, -1}, {1, 2, 1})},
      {"bend oblique, range around the centre", bend({0.25, 0.5, -0.5}, d, t, -0.5, 0.6, 0.1, 1.2),
       box({-0.35, -0.1, -1.1}, {0.85, 1.1, 0.1})},
      {"bend on y, 3 radians", bend({}, y, z, 0, 3, 0, 1), box({-1, -1, -2}, {1, 4, 0.9})},
      {"bend with the centre outside the range",
       bend({1, 1, 1}, {-1, 0.5, 0.25}, {1, 1, 0}, 1, 2, -5, 3),
       box({-0.5, -0.5, -0.5}, {2.5, 2.5, 2.5})},
  };
}

/// The world point of local coordinates y (approximately: F⁻¹ ≈ Fᵀ).
Vec3 from_local(const WarpLeaf& w, const Vec3& y) {
  return w.point + y.x * w.frame[0] + y.y * w.frame[1] + y.z * w.frame[2];
}

// ---- a reference in long double, by other formulas (φ by atan2 and the sector) ------------

using LD = long double;
struct L3 {
  LD x, y, z;
};
constexpr LD kPi = 3.141592653589793238462643383279502884L;

L3 ld_local(const WarpLeaf& w, const Vec3& p) {
  const LD d[3] = {LD(p.x) - w.point.x, LD(p.y) - w.point.y, LD(p.z) - w.point.z};
  LD r[3];
  for (int i = 0; i < 3; ++i)
    r[i] = w.frame[i].x * d[0] + w.frame[i].y * d[1] + w.frame[i].z * d[2];
  return {r[0], r[1], r[2]};
}
/// point + F⁻¹·y, F⁻¹ by Cramer's rule on the stored frame.
L3 ld_world(const WarpLeaf& w, const L3& y) {
  const auto det = [](const L3& a, const L3& b, const L3& c) {
    return a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) +
           a.z * (b.x * c.y - b.y * c.x);
  };
  const Vec3* f = w.frame;
  const L3 c0{f[0].x, f[1].x, f[2].x}, c1{f[0].y, f[1].y, f[2].y}, c2{f[0].z, f[1].z, f[2].z};
  const LD d = det(c0, c1, c2);
  return {w.point.x + det(y, c1, c2) / d, w.point.y + det(c0, y, c2) / d,
          w.point.z + det(c0, c1, y) / d};
}
Vec3 vec(const L3& v) { return {double(v.x), double(v.y), double(v.z)}; }

Vec3 ld_forward(const WarpLeaf& w, const Vec3& p) {
  const L3 y = ld_local(w, p);
  const LD r0 = w.range[0], r1 = w.range[1], yc = std::clamp(y.y, r0, r1);
  switch (w.kind) {
    case WarpKind::kTwist: {
      const LD t = w.degrees_per_unit * kPi / 180 * y.y;
      return vec(ld_world(w, {y.x * cosl(t) - y.z * sinl(t), y.y, y.x * sinl(t) + y.z * cosl(t)}));
    }
    case WarpKind::kTaper: {
      const LD s = ((r1 - yc) * w.scale[0] + (yc - r0) * w.scale[1]) / (r1 - r0);
      return vec(ld_world(w, {s * y.x, y.y, s * y.z}));
    }
    default: {
      const LD R = w.radius, t = (yc - w.center) / R, d = y.y - yc;
      return vec(ld_world(w, {y.x, -sinl(t) * (y.z - R) + w.center + cosl(t) * d,
                              cosl(t) * (y.z - R) + R + sinl(t) * d}));
    }
  }
}
/// NaN where q has no preimage (bend).
Vec3 ld_inverse(const WarpLeaf& w, const Vec3& q) {
  const L3 y = ld_local(w, q);
  const LD r0 = w.range[0], r1 = w.range[1];
  switch (w.kind) {
    case WarpKind::kTwist: {
      const LD t = w.degrees_per_unit * kPi / 180 * y.y;
      return vec(ld_world(w, {y.x * cosl(t) + y.z * sinl(t), y.y, -y.x * sinl(t) + y.z * cosl(t)}));
    }
    case WarpKind::kTaper: {
      const LD yc = std::clamp(y.y, r0, r1);
      const LD s = ((r1 - yc) * w.scale[0] + (yc - r0) * w.scale[1]) / (r1 - r0);
      return vec(ld_world(w, {y.x / s, y.y, y.z / s}));
    }
    default: {
      const LD R = w.radius, u = y.y - w.center, v = y.z - R;
      const LD lo = (r0 - w.center) / R, hi = (r1 - w.center) / R, mid = (lo + hi) / 2;
      LD phi = atan2l(u, -v);
      phi += 2 * kPi * std::round((mid - phi) / (2 * kPi));  // within π of the sector's middle
      if (phi >= lo && phi <= hi && u * u + v * v > 0) {
        return vec(ld_world(w, {y.x, w.center + phi * R, R - sqrtl(u * u + v * v)}));
      }
      if (phi > hi && phi < hi + kPi / 2) {
        return vec(
            ld_world(w, {y.x, r1 + cosl(hi) * u + sinl(hi) * v, R - sinl(hi) * u + cosl(hi) * v}));
      }
      if (phi < lo && phi > lo - kPi / 2) {
        return vec(
            ld_world(w, {y.x, r0 + cosl(lo) * u + sinl(lo) * v, R - sinl(lo) * u + cosl(lo) * v}));
      }
      return {kNaN, kNaN, kNaN};
    }
  }
}

TEST(Warp, FrameIsOrthonormalAndFollowsTheAxis) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Vec3* e = c.w.frame;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(dot(e[i], e[j]), i == j ? 1 : 0, 1e-15);
    }
    EXPECT_NEAR(norm(cross(e[0], cross(e[1], e[2]))), 0, 1e-15);
    EXPECT_NEAR(dot(e[1], c.w.direction), norm(c.w.direction), 1e-14);
    if (c.w.kind == WarpKind::kBend) {
      EXPECT_GT(dot(e[2], c.w.toward), 0);
    }
  }
  WarpLeaf w;
  w.direction = {0, 0, 0};
  EXPECT_EQ(make_frame(w), "axis direction is zero or not finite");
  w.direction = {kNaN, 1, 0};
  EXPECT_EQ(make_frame(w), "axis direction is zero or not finite");
  w.kind = WarpKind::kBend;
  w.direction = {0, 2, 0};
  w.toward = {0, -3, 0};
  EXPECT_EQ(make_frame(w), "bend: toward is parallel to the axis");
  w.toward = {0, 0, 0};
  EXPECT_EQ(make_frame(w), "bend: toward is zero or not finite");
  w.kind = WarpKind::kTaper;  // twist and taper pick any unit vector ⊥ the axis
  EXPECT_EQ(make_frame(w), "");
  EXPECT_EQ(dot(w.frame[1], w.frame[2]), 0);
}

TEST(Warp, RoundTrips) {
  Rng rng(1);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    ASSERT_EQ(validate(c.w, c.child), "");
    const Bbox image = forward_box(c.w, c.child);
    const double scale = 1 + magnitude(image) + magnitude(c.child) + c.w.radius;
    int back = 0;
    for (int i = 0; i < 10000; ++i) {
      const Vec3 p = sample(rng, c.child);
      const Vec3 q = forward(c.w, p);
      ASSERT_TRUE(image.contains(q));
      ASSERT_LE(norm(inverse(c.w, q) - p), 1e-9 * scale) << p.x << " " << p.y << " " << p.z;
      ASSERT_LE(norm(ld_forward(c.w, p) - q), 1e-12 * scale);
      const Vec3 r = sample(rng, image), pre = inverse(c.w, r), ld = ld_inverse(c.w, r);
      ASSERT_EQ(std::isnan(pre.x), std::isnan(ld.x));
      if (std::isnan(pre.x)) continue;
      ASSERT_LE(norm(ld - pre), 1e-12 * scale);
      ++back;
      ASSERT_LE(norm(forward(c.w, pre) - r), 1e-9 * scale) << r.x << " " << r.y << " " << r.z;
    }
    EXPECT_GT(back, 5000);
  }
}

TEST(Warp, EnclosuresHoldEverySample) {
  Rng rng(2);
  int all_nones = 0;
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Bbox near = grown(c.child, norm(size(c.child)) / 4);
    Bbox world = grown(forward_box(c.w, c.child), norm(size(c.child)) / 4);
    if (c.w.kind == WarpKind::kBend) {  // and the centre of curvature with the far side
      const Vec3 centre = from_local(c.w, {0, c.w.center, c.w.radius});
      world.add(box(centre - Vec3{2, 2, 2}, centre + Vec3{2, 2, 2}));
    }
    const double slack = 1e-17 * (1 + magnitude(world) + magnitude(near));  // the reference's
    int nones = 0, partials = 0, holes = 0;
    for (int b = 0; b < 400; ++b) {
      const double half = (b % 2 ? 1e-6 : 0.5) * norm(size(c.child));
      const Bbox from = random_box(rng, near, half);
      const Bbox image = forward_box(c.w, from);
      const Bbox to = random_box(rng, world, half);
      const InverseBox pre = inverse_box(c.w, to);
      if (c.w.kind != WarpKind::kBend) {
        ASSERT_FALSE(pre.none || pre.partial);
      }
      nones += pre.none;
      partials += pre.partial;
      for (int i = 0; i < 200; ++i) {
        const Vec3 p = sample(rng, from, i);
        ASSERT_TRUE(contains(image, ld_forward(c.w, p), slack)) << b << " " << i;
        const Vec3 q = sample(rng, to, i), back = ld_inverse(c.w, q);
        if (std::isnan(back.x)) {
          ++holes;
          ASSERT_TRUE(pre.none || pre.partial) << b << " " << i;
        } else {
          ASSERT_FALSE(pre.none) << b << " " << i;
          ASSERT_TRUE(contains(pre.box, back, slack)) << b << " " << i;
        }
      }
    }
    if (c.w.kind == WarpKind::kBend) {
      EXPECT_GT(partials, 0);
      EXPECT_GT(holes, 0);
    }
    all_nones += nones;
  }
  EXPECT_GT(all_nones, 0);
}

TEST(Warp, PointBoxesAreTight) {
  Rng rng(3);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    for (int i = 0; i < 1000; ++i) {
      const Vec3 q = forward(c.w, sample(rng, c.child));
      const InverseBox pre = inverse_box(c.w, box(q, q));
      ASSERT_FALSE(pre.none);
      const double scale = 1 + norm(q);
      ASSERT_TRUE(contains(pre.box, inverse(c.w, q), 1e-13 * scale));
      ASSERT_TRUE(contains(pre.box, ld_inverse(c.w, q), 1e-17 * scale));
      const Vec3 p = inverse(c.w, q);
      const Bbox image = forward_box(c.w, box(p, p));
      ASSERT_TRUE(contains(image, ld_forward(c.w, p), 1e-17 * scale));
      ASSERT_LE(norm(size(image)), 1e-12 * scale);
      if (c.w.kind == WarpKind::kBend) continue;
      ASSERT_FALSE(pre.partial);
      ASSERT_LE(norm(size(pre.box)), 1e-12 * scale);
    }
  }
}

TEST(Warp, BendImageEdges) {
  const WarpLeaf w = bend({}, {0, 1, 0}, {0, 0, 1}, 0, 3, 0, 1);  // centre of curvature (x, 0, 1)
  // φ = 3 + π/2 + 0.07 (the gap between the ends of the image): (u, −v) = ρ (sin φ, cos φ).
  const double phi = 3 + std::numbers::pi / 2 + 0.07;
  const Vec3 gap{0, 10 * std::sin(phi), 1 - 10 * std::cos(phi)};
  EXPECT_TRUE(std::isnan(inverse(w, gap).x));
  EXPECT_TRUE(inverse_box(w, grown(box(gap, gap), 0.01)).none);
  const InverseBox wide = inverse_box(w, grown(box(gap, gap), 1));
  EXPECT_TRUE(wide.partial && !wide.none);
  const InverseBox centre = inverse_box(w, grown(box({0, 0, 1}, {0, 0, 1}), 0.01));
  EXPECT_TRUE(centre.partial && !centre.none);
  const InverseBox inside = inverse_box(w, grown(box({0, -1, 0}, {0, -1, 0}), 0.01));
  EXPECT_FALSE(inside.partial || inside.none);
  EXPECT_TRUE(inside.box.contains({0, -1, 0}));
}

TEST(Warp, JacobianMatchesFiniteDifferences) {
  Rng rng(4);
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    int checked = 0;
    for (int n = 0; n < 300; ++n) {
      const Vec3 p = sample(rng, c.child);
      const double y = dot(c.w.frame[1], p - c.w.point);  // away from the kinks at the range ends
      if (c.w.kind != WarpKind::kTwist &&
          std::min(std::abs(y - c.w.range[0]), std::abs(y - c.w.range[1])) < 1e-3) {
        continue;
      }
      const Vec3 q = forward(c.w, p);
      const Mat3 J = inverse_jacobian(c.w, q);
      double big = 1;
      for (const Vec3& r : J.row)
        big = std::max({big, std::abs(r.x), std::abs(r.y), std::abs(r.z)});
      const double h = 1e-5;
      for (int j = 0; j < 3; ++j) {
        const Vec3 e{j == 0 ? h : 0, j == 1 ? h : 0, j == 2 ? h : 0};
        const Vec3 fd = (0.5 / h) * (inverse(c.w, q + e) - inverse(c.w, q - e));
        for (int i = 0; i < 3; ++i) ASSERT_NEAR(J.row[i][j], fd[i], 1e-5 * big) << i << j;
      }
      ++checked;
    }
    EXPECT_GT(checked, 250);
  }
}

// ---- exact inverses -------------------------------------------------------------------------

struct QV {
  Q x, y, z;
};
/// F·(p − point) in rationals.
QV exact_local(const WarpLeaf& w, const Vec3& p) {
  const Q d[3] = {Q(p.x) - Q(w.point.x), Q(p.y) - Q(w.point.y), Q(p.z) - Q(w.point.z)};
  Q r[3];
  for (int i = 0; i < 3; ++i) {
    r[i] = Q(w.frame[i].x) * d[0] + Q(w.frame[i].y) * d[1] + Q(w.frame[i].z) * d[2];
  }
  return {r[0], r[1], r[2]};
}
/// Taper's L in rationals, s by the weights of the two ends.
QV exact_taper(const WarpLeaf& w, const QV& p) {
  const Q r0(w.range[0]), r1(w.range[1]);
  const Q y = std::clamp(p.y, r0, r1);
  const Q s = ((r1 - y) * Q(w.scale[0]) + (y - r0) * Q(w.scale[1])) / (r1 - r0);
  return {s * p.x, p.y, s * p.z};
}
bool same(const QV& a, const QV& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

TEST(Warp, TaperExactInverse) {
  const WarpLeaf w = taper({}, {0, 1, 0}, {0, 0, 1}, 0, 1, 1, 0.5);
  Vec3 out;
  ASSERT_TRUE(exact_inverse(w, {0.75, 0.5, 0}, out));  // s(0.5) = 0.75
  EXPECT_EQ(out, (Vec3{1, 0.5, 0}));
  EXPECT_FALSE(exact_inverse(w, {1, 0.5, 0}, out));  // x = 4/3
  EXPECT_TRUE(exact_inverse(w, {1, 3, -2}, out));    // beyond the range: s = 0.5
  EXPECT_EQ(out, (Vec3{2, 3, -4}));
  // Every true answer p satisfies E(q) = L(E(p)) exactly; on this frame (F = I) a false one has a
  // coordinate of (x/s, y, z/s) that is not a double.
  Rng rng(5);
  std::uniform_real_distribution<double> t(-2, 3);
  for (const Case& c : {Case{"on y", w, {}}, cases()[2]}) {
    SCOPED_TRACE(c.name);
    int trues = 0;
    for (int i = 0; i < 1000; ++i) {
      Vec3 q{t(rng), t(rng), t(rng)};
      if (i % 2) q = {std::ldexp(std::round(q.x * 64), -6), std::round(q.y * 4) / 4, q.z};
      if (exact_inverse(c.w, q, out)) {
        ++trues;
        ASSERT_TRUE(same(exact_local(c.w, q), exact_taper(c.w, exact_local(c.w, out))));
      } else if (c.name == "on y") {
        const QV y = exact_local(c.w, q), l = exact_taper(c.w, {Q(1), y.y, Q(1)});  // s twice
        const Q x = y.x / l.x, z = y.z / l.z;
        EXPECT_TRUE(Q(CGAL::to_double(x)) != x || Q(CGAL::to_double(z)) != z);
      }
    }
    if (c.name == "on y") {
      EXPECT_GT(trues, 100);
    }
  }
  ASSERT_TRUE(exact_inverse(cases()[2].w, cases()[2].w.point, out));  // local 0 ↦ 0
  EXPECT_EQ(out, cases()[2].w.point);
}

TEST(Warp, TwistAndBendExactWhereTheAngleIsZero) {
  Vec3 out;
  const WarpLeaf t = twist({}, {0, 1, 0}, {0, 0, 1}, 30);
  ASSERT_TRUE(exact_inverse(t, {0.3, 0, -7}, out));
  EXPECT_EQ(out, (Vec3{0.3, 0, -7}));
  EXPECT_FALSE(exact_inverse(t, {0.3, 1e-300, -7}, out));
  const WarpLeaf oblique = cases()[0].w;
  ASSERT_TRUE(exact_inverse(oblique, oblique.point, out));
  EXPECT_EQ(out, oblique.point);
  Rng rng(6);
  for (int i = 0; i < 100; ++i) {
    const Vec3 q = sample(rng, cases()[0].child);
    if (exact_inverse(oblique, q, out)) {
      EXPECT_EQ(exact_local(oblique, q).y, Q(0));
      EXPECT_EQ(out, q);
    }
  }
  const WarpLeaf b = bend({}, {0, 1, 0}, {0, 0, 1}, 0, 3, 0, 1);  // unbent below y = 0
  ASSERT_TRUE(exact_inverse(b, {0.3, -2, 0.5}, out));
  EXPECT_EQ(out, (Vec3{0.3, -2, 0.5}));
  EXPECT_TRUE(exact_inverse(b, {0.3, 0, -4}, out));
  EXPECT_FALSE(exact_inverse(b, {0.3, -2, 1}, out));  // z = 1/k: not in the image
  EXPECT_FALSE(exact_inverse(b, {0.3, 0.5, 0.5}, out));
  const WarpLeaf above = bend({}, {0, 1, 0}, {0, 0, 1}, -3, 0, 0, 1);  // unbent above y = 0
  EXPECT_TRUE(exact_inverse(above, {0.3, 5, 0.5}, out));
  EXPECT_FALSE(exact_inverse(above, {0.3, -2, 0.5}, out));
  const WarpLeaf off = bend({}, {0, 1, 0}, {0, 0, 1}, 1, 3, 0, 1);  // θ_min ≠ 0: bent everywhere
  EXPECT_FALSE(exact_inverse(off, {0.3, -2, 0.5}, out));
  EXPECT_FALSE(exact_inverse(cases()[3].w, {1, 0.5, 0}, out));
}

// ---- validation ---------------------------------------------------------------------------

std::string problem(WarpLeaf w, const Bbox& child = box({-1, -1, -1}, {1, 1, 0.5})) {
  EXPECT_EQ(make_frame(w), "");
  return validate(w, child);
}

TEST(Warp, ValidateNamesEachRule) {
  const WarpLeaf t = twist({}, {0, 1, 0}, {0, 0, 1}, 10),
                 p = taper({}, {0, 1, 0}, {0, 0, 1}, 0, 1, 1, 2),
                 b = bend({}, {0, 1, 0}, {0, 0, 1}, 0, 1, 0, 2);
  EXPECT_EQ(problem(t), "");
  EXPECT_EQ(problem(p), "");
  EXPECT_EQ(problem(b), "");
  WarpLeaf w = t;
  w.point.y = kInf;
  EXPECT_EQ(problem(w), "twist: point must be finite");
  w = t, w.degrees_per_unit = kNaN;
  EXPECT_EQ(problem(w), "twist: degrees_per_unit must be finite (got nan)");
  w = t, w.degrees_per_unit = -2e6;
  EXPECT_EQ(problem(w), "twist: degrees_per_unit must be within [-1e6, 1e6] (got -2e+06)");
  w = p, w.range[0] = 2;
  EXPECT_EQ(problem(w), "taper: range must be increasing (got [2, 1])");
  w = p, w.range[1] = kInf;
  EXPECT_EQ(problem(w), "taper: range must be finite (got [0, inf])");
  w = p, w.scale[1] = -1;
  EXPECT_EQ(problem(w), "taper: scale must be > 0 (got -1)");
  w = p, w.scale[0] = kNaN;
  EXPECT_EQ(problem(w), "taper: scale must be finite (got nan)");
  w = p, w.scale[0] = 2e6;
  EXPECT_EQ(problem(w), "taper: scale must be <= 1e6 (got 2e+06)");
  w = b, w.range[1] = -1;
  EXPECT_EQ(problem(w), "bend: range must be increasing (got [0, -1])");
  w = b, w.radius = 0;
  EXPECT_EQ(problem(w), "bend: radius must be > 0 (got 0)");
  w = b, w.radius = kInf;
  EXPECT_EQ(problem(w), "bend: radius must be finite (got inf)");
  w = b, w.center = kNaN;
  EXPECT_EQ(problem(w), "bend: center must be finite (got nan)");
  w = b, w.radius = 1, w.range[1] = 0x1.921fb54442d18p+1;  // π rounded down: accepted
  EXPECT_EQ(problem(w), "");
  w.range[1] = 0x1.921fb54442d19p+1;
  EXPECT_EQ(problem(w), "bend: range spans more than pi radians at this radius");
  w = b;
  EXPECT_EQ(problem(w, box({-1, -1, -1}, {1, 1, 2.5})),
            "bend: the child reaches the centre of curvature (radius 2, the child extends to local "
            "z = 2.5)");
  EXPECT_NE(problem(w, box({-1, -1, -1}, {1, 1, 2})), "");
  EXPECT_EQ(problem(w, box({-1, -1, -1}, {1, 1, 1.999})), "");
  EXPECT_EQ(problem(w, Bbox{}), "bend: the child's box must be finite and non-empty");
}

}  // namespace
}  // namespace cover::field
