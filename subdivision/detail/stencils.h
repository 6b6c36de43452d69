#pragma once
// The masks of the four schemes as templates over the number type T (double for the default
// evaluation, exact rationals for SubdivideOptions::exact_rounding). Each mask is written with
// the operations, operand order and double weights of CGAL 5.5's subdivision_masks_3.h.
// Notation (detail/topology.h): h a corner (the half-edge vertex(h) -> vertex(next(h))), o its
// opposite, ring(v) the outgoing corners of v in rotation order; on a border vertex v, the ring
// starts at the outgoing border corner (to u) and ends at a corner whose prev arrives from s, so
// u and s are v's two border neighbours.
//   centroid(f)              Σ p_k / n over the corners of f in order
//   CC edge (h, o)           (p(next h) + p(h) + c(face h) + c(face o)) / 4
//   CC vertex (n faces)      R = Σ (S + p_i)/2 / n, Q = Σ c(f_i) / n, (Q + 2R + (n−3)S) / n
//   Loop edge (h, o)         (3(p(next h) + p(h)) + p(prev h) + p(prev o)) / 8
//   Loop vertex (n nbrs)     n = 6: (10S + Σp_i)/16; else (Sw S + Σp_i)/W, Cn = 5/8 −
//                            (3 + 2cos(2π/n))²/64, Sw = n(1−Cn)/Cn, W = n/Cn
//   border edge, vertex      (p(next h) + p(h))/2, (u + 6v + s)/8 (CC and Loop)
//   Doo–Sabin corner         n = 4: (9p0 + 3p1 + p2 + 3p3)/16; else Σ a_k p_k / 4, a_0 =
//                            5/n + 1, a_k = (3 + 2cos(2kπ/n))/n (p_k: k corners after h)
//   √3 vertex                a = (4 − 2cos(2π/n))/9, (1−a)S + Σ (a/n) p_i
//   √3 border (edge a->b)    w1 = (10b + 16a + a')/27, w2 = (b' + 16b + 10a)/27, b moves to
//                            (4b' + 19b + 4a)/27 (a', b': the other border neighbours)

#include <cmath>
#include <cstdint>
#include <numbers>

#include "cover/subdivision/detail/topology.h"

namespace cover::subdivision_detail {

/// A point with coordinates of type T.
template <class T>
struct P3 {
  T x, y, z;
};
template <class T>
P3<T> operator+(const P3<T>& a, const P3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
P3<T> operator*(const P3<T>& a, const T& s) {
  return {a.x * s, a.y * s, a.z * s};
}
template <class T>
P3<T> operator*(const T& s, const P3<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
P3<T> operator/(const P3<T>& a, const T& s) {
  return {a.x / s, a.y / s, a.z / s};
}

/// The order in which an interior vertex's ring terms are summed: CGAL's. A CGAL Surface_mesh
/// built face by face (Euler::add_face) keeps, for each interior vertex, the half-edge entering
/// it in the last face that uses it, and its masks circulate from there. So the ring is read
/// from the corner with the largest index (the last face's): at(k) is the entry k steps after
/// it, for k in (−n, 2n). With the same operands in the same order, one step from the same mesh
/// gives CGAL's doubles bit for bit (tests/subdivision).
struct RingOrder {
  const uint32_t* ring;  ///< the vertex's ring slice
  uint32_t n, last;      ///< its size, the offset of the last face's corner in it
  uint32_t at(int64_t k) const {
    int64_t i = last + k;
    if (i < 0) i += n;
    if (i >= n) i -= n;
    return ring[i];
  }
};
inline RingOrder ring_order(const Topology& t, uint32_t v) {
  const uint32_t lo = t.ring_start[v], n = t.ring_start[v + 1] - lo;
  uint32_t last = 0;
  for (uint32_t k = 1; k < n; ++k)
    if (t.ring[lo + k] > t.ring[lo + last]) last = k;
  return {t.ring.data() + lo, n, last};
}

template <class T>
P3<T> pos(const Topology& t, uint32_t v) {
  const Vec3& q = t.mesh->vertices[v];
  return {T(q.x), T(q.y), T(q.z)};
}
template <class T>
P3<T> zero() {
  return {T(0.0), T(0.0), T(0.0)};
}

/// The border neighbours (u, s) of border vertex v (see the notation above).
inline uint32_t border_u(const Topology& t, uint32_t v) {
  return t.vertex(t.next(t.ring[t.ring_start[v]]));
}
inline uint32_t border_s(const Topology& t, uint32_t v) {
  return t.vertex(t.prev(t.ring[t.ring_start[v + 1] - 1]));
}

template <class T>
P3<T> centroid(const Topology& t, uint32_t f) {
  P3<T> s = zero<T>();
  const auto& m = *t.mesh;
  for (uint32_t h = m.face_start[f]; h < m.face_start[f + 1]; ++h) s = s + pos<T>(t, t.vertex(h));
  return s / T(static_cast<double>(t.face_size(f)));
}

/// Border edge point of the edge of border corner h (CC and Loop).
template <class T>
P3<T> border_edge_point(const Topology& t, uint32_t h) {
  return (pos<T>(t, t.vertex(t.next(h))) + pos<T>(t, t.vertex(h))) / T(2.0);
}

/// Border vertex point of border vertex v (CC and Loop).
template <class T>
P3<T> border_vertex_point(const Topology& t, uint32_t v) {
  return (pos<T>(t, border_u(t, v)) + T(6.0) * pos<T>(t, v) + pos<T>(t, border_s(t, v))) / T(8.0);
}

/// Catmull–Clark edge point of edge e; face_point(f) gives the face points.
template <class T, class FacePoint>
P3<T> cc_edge_point(const Topology& t, uint32_t e, const FacePoint& face_point) {
  const uint32_t h = t.edge_half[e], o = t.opposite[h];
  if (o == kNone) return border_edge_point<T>(t, h);
  return (pos<T>(t, t.vertex(t.next(h))) + pos<T>(t, t.vertex(h)) + face_point(t.face_of[h]) +
          face_point(t.face_of[o])) /
         T(4.0);
}

/// Catmull–Clark vertex point of a referenced vertex v.
template <class T, class FacePoint>
P3<T> cc_vertex_point(const Topology& t, uint32_t v, const FacePoint& face_point) {
  if (t.border[v]) return border_vertex_point<T>(t, v);
  const P3<T> s = pos<T>(t, v);
  P3<T> r = zero<T>(), q = zero<T>();
  // CGAL's circulator: the faces from the last face's corner backwards through the ring, each
  // with the neighbour before v in it (the ring entry one step later).
  const RingOrder o = ring_order(t, v);
  for (int64_t j = 0; j < o.n; ++j) {
    r = r + (s + pos<T>(t, t.vertex(t.next(o.at(1 - j))))) / T(2.0);
    q = q + face_point(t.face_of[o.at(-j)]);
  }
  const int n = static_cast<int>(o.n);
  const T tn(static_cast<double>(n));
  r = r / tn;
  q = q / tn;
  return (q + T(2.0) * r + s * T(static_cast<double>(n - 3))) / tn;
}

/// Loop edge point of edge e (triangles).
template <class T>
P3<T> loop_edge_point(const Topology& t, uint32_t e) {
  const uint32_t h = t.edge_half[e], o = t.opposite[h];
  if (o == kNone) return border_edge_point<T>(t, h);
  return (T(3.0) * (pos<T>(t, t.vertex(t.next(h))) + pos<T>(t, t.vertex(h))) +
          pos<T>(t, t.vertex(t.prev(h))) + pos<T>(t, t.vertex(t.prev(o)))) /
         T(8.0);
}

/// Loop vertex point of a referenced vertex v.
template <class T>
P3<T> loop_vertex_point(const Topology& t, uint32_t v) {
  if (t.border[v]) return border_vertex_point<T>(t, v);
  P3<T> r = zero<T>();
  const RingOrder o = ring_order(t, v);  // CGAL's order, as in cc_vertex_point
  for (int64_t j = 0; j < o.n; ++j) r = r + pos<T>(t, t.vertex(t.next(o.at(1 - j))));
  const uint32_t n = o.n;
  const P3<T> s = pos<T>(t, v);
  if (n == 6) return (T(10.0) * s + r) / T(16.0);
  const double c = std::cos(2 * std::numbers::pi / static_cast<double>(n));
  const double cn = 5.0 / 8.0 - (3 + 2 * c) * (3 + 2 * c) / 64.0;
  const double sw = static_cast<double>(n) * (1 - cn) / cn;
  const double w = static_cast<double>(n) / cn;
  return (T(sw) * s + r) / T(w);
}

/// Doo–Sabin point of corner h (the new vertex of face_of[h] at vertex(h)).
template <class T>
P3<T> doo_sabin_point(const Topology& t, uint32_t h) {
  const uint32_t n = t.face_size(t.face_of[h]);
  P3<T> cv = zero<T>();
  if (n == 4) {
    const uint32_t h1 = t.next(h), h2 = t.next(h1), h3 = t.next(h2);
    cv = cv + pos<T>(t, t.vertex(h)) * T(9.0);
    cv = cv + pos<T>(t, t.vertex(h1)) * T(3.0);
    cv = cv + pos<T>(t, t.vertex(h2));
    cv = cv + pos<T>(t, t.vertex(h3)) * T(3.0);
    return cv / T(16.0);
  }
  const int ni = static_cast<int>(n);
  for (int k = 0; k < ni; ++k, h = t.next(h)) {
    const double a =
        k == 0 ? (5.0 / ni) + 1 : (3 + 2 * std::cos(2 * k * std::numbers::pi / ni)) / ni;
    cv = cv + pos<T>(t, t.vertex(h)) * T(a);
  }
  return cv / T(4.0);
}

/// √3 vertex point of an interior vertex v.
template <class T>
P3<T> sqrt3_vertex_point(const Topology& t, uint32_t v) {
  const uint32_t n = t.ring_start[v + 1] - t.ring_start[v];
  const double a = (4.0 - 2.0 * std::cos(2.0 * std::numbers::pi / static_cast<double>(n))) / 9.0;
  P3<T> cv = T(1.0 - a) * pos<T>(t, v);
  const T w(a / static_cast<double>(n));
  // CGAL circulates the other way here (--vcir): forwards from the neighbour after the start.
  const RingOrder o = ring_order(t, v);
  for (int64_t j = 1; j <= o.n; ++j) cv = cv + w * pos<T>(t, t.vertex(t.next(o.at(j))));
  return cv;
}

/// √3 border points of the refined border corner h (a -> b): which 0 gives w1 (near a),
/// 1 gives w2 (near b), 2 the new position of b.
template <class T>
P3<T> sqrt3_border_point(const Topology& t, uint32_t h, int which) {
  const uint32_t a = t.vertex(h), b = t.vertex(t.next(h));
  const P3<T> pa = pos<T>(t, a), pb = pos<T>(t, b);
  const T third(1. / 27.);
  if (which == 0) return third * (T(10.) * pb + T(16.) * pa + pos<T>(t, border_s(t, a)));
  const P3<T> pb_out = pos<T>(t, border_u(t, b));
  if (which == 1) return third * (pb_out + T(16.) * pb + T(10.) * pa);
  return third * (T(4.0) * pb_out + T(19.0) * pb + T(4.0) * pa);
}

}  // namespace cover::subdivision_detail
