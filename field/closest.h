#pragma once
// Closest points of the field skeletons (Ericson, Real-Time Collision Detection §5.1), generic in
// the number type: double (evaluate(), an approximation) and CGAL::Gmpq (the exact path of sign(),
// where every comparison below is exact, so the Voronoi region found is the true one).
// Circles are not here: their closest point needs a square root (field.cpp).

namespace cover::field::detail {

template <class T>
struct V3 {
  T x, y, z;
};
template <class T>
V3<T> operator+(const V3<T>& a, const V3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
V3<T> operator-(const V3<T>& a, const V3<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
V3<T> operator*(const T& s, const V3<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
T dot(const V3<T>& a, const V3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

/// Closest point of the segment [a, b] to p: the projection parameter t = (p − a)·u / |u|²,
/// u = b − a, clamped to [0, 1]. (A NaN t, from |u|² = 0 in doubles, is taken as 0.)
template <class T>
V3<T> closest_on_segment(const V3<T>& p, const V3<T>& a, const V3<T>& b) {
  const V3<T> u = b - a;
  T t = dot(p - a, u) / dot(u, u);
  if (!(t > T(0))) {
    t = T(0);
  } else if (t > T(1)) {
    t = T(1);
  }
  return a + t * u;
}

/// Closest point of the filled triangle abc (not collinear) to p, by its Voronoi regions:
/// vertices, then edges, then the face (Ericson's ClosestPtPointTriangle).
template <class T>
V3<T> closest_on_triangle(const V3<T>& p, const V3<T>& a, const V3<T>& b, const V3<T>& c) {
  const V3<T> ab = b - a, ac = c - a, ap = p - a;
  const T d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= T(0) && d2 <= T(0)) return a;
  const V3<T> bp = p - b;
  const T d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= T(0) && d4 <= d3) return b;
  const T vc = d1 * d4 - d3 * d2;
  if (vc <= T(0) && d1 >= T(0) && d3 <= T(0)) return a + (d1 / (d1 - d3)) * ab;  // edge ab
  const V3<T> cp = p - c;
  const T d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= T(0) && d5 <= d6) return c;
  const T vb = d5 * d2 - d1 * d6;
  if (vb <= T(0) && d2 >= T(0) && d6 <= T(0)) return a + (d2 / (d2 - d6)) * ac;  // edge ac
  const T va = d3 * d6 - d5 * d4;
  if (va <= T(0) && d4 - d3 >= T(0) && d5 - d6 >= T(0)) {  // edge bc
    const T w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return b + w * (c - b);
  }
  const T denom = va + vb + vc;  // the face: barycentric (va, vb, vc) / denom
  return a + (vb / denom) * ab + (vc / denom) * ac;
}

}  // namespace cover::field::detail
