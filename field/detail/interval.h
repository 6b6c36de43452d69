#pragma once
// Interval enclosures of squared distances to skeleton pieces (CGAL::Interval_nt<false>, outward
// rounded: callers hold a CGAL::Protect_FPU_rounding<true> guard). Shared by field.cpp and
// mesh.cpp; includes CGAL, internal, not installed.

#include <CGAL/Interval_nt.h>

#include <algorithm>

#include "cover/solid/types.h"

namespace cover::field::detail {

using I = CGAL::Interval_nt<false>;

struct IV {
  I x, y, z;
};
inline IV iv(const Vec3& v) { return {I(v.x), I(v.y), I(v.z)}; }
inline IV operator-(const IV& a, const IV& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline IV operator*(const I& s, const IV& a) { return {s * a.x, s * a.y, s * a.z}; }
inline I dot(const IV& a, const IV& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline I norm2(const IV& a) { return CGAL::square(a.x) + CGAL::square(a.y) + CGAL::square(a.z); }
inline IV cross(const IV& a, const IV& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline I imin(const I& a, const I& b) {
  return I(std::min(a.inf(), b.inf()), std::min(a.sup(), b.sup()));
}
inline I join(const I& a, const I& b) {
  return I(std::min(a.inf(), b.inf()), std::max(a.sup(), b.sup()));
}

/// d² to the segment [a, b]: t = clamp((p − a)·u / |u|², 0, 1) as an interval (clamping is
/// monotone), then |p − a − t·u|² over that t interval, which holds the true t.
inline I segment_d2(const IV& p, const Vec3& a, const Vec3& b) {
  const IV A = iv(a), u = iv(b) - A, v = p - A;
  const I t = dot(v, u) / norm2(u);
  const I tc(std::clamp(t.inf(), 0.0, 1.0), std::clamp(t.sup(), 0.0, 1.0));
  return norm2(v - tc * u);
}

/// d² to the filled triangle abc, n = (b − a)×(c − a). The projection of p lies in the closed
/// triangle iff each edge's ((edge)×(p − its start))·n ≥ 0: then d² = ((p − a)·n)²/|n|², else d²
/// is the least over the edges. Uncertain: the hull of both.
inline I triangle_d2(const IV& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const IV A = iv(a), B = iv(b), C = iv(c);
  const IV ab = B - A, n = cross(ab, C - A);
  const I s1 = dot(cross(ab, p - A), n), s2 = dot(cross(C - B, p - B), n),
          s3 = dot(cross(A - C, p - C), n);
  const bool inside = s1.inf() >= 0 && s2.inf() >= 0 && s3.inf() >= 0;
  const bool outside = s1.sup() < 0 || s2.sup() < 0 || s3.sup() < 0;
  if (inside) return CGAL::square(dot(p - A, n)) / norm2(n);
  const I edges = imin(segment_d2(p, a, b), imin(segment_d2(p, b, c), segment_d2(p, c, a)));
  if (outside) return edges;
  return join(CGAL::square(dot(p - A, n)) / norm2(n), edges);
}

}  // namespace cover::field::detail
