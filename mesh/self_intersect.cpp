// Exact self-intersection test (validate.h). All predicates are CGAL's Epick filtered predicates
// on the input doubles (exact); no point is ever constructed. Notation:
//   triangle   three vertex indices and the face it covers; collinear triangles are dropped
//   tiling     the triangles of one face (mesh/triangulate.h) cover exactly the face's region,
//              every loop vertex a tile corner; a face whose boundary crosses itself or winds
//              more than once is an intersection by itself
// Two triangles of the same face never count as intersecting. For other pairs the tests follow
// CGAL::Polygon_mesh_processing::self_intersections (internal::do_faces_intersect), with shared
// vertices decided by index:
//   3 shared  the same triangle twice: intersecting
//   2 shared  intersecting iff coplanar and both third vertices on the same side of the edge
//   1 shared  intersecting iff the edge opposite the shared vertex in one meets the other triangle
//   0 shared  CGAL::do_intersect (touching counts)

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <vector>

#include "cover/mesh/box_pairs.h"
#include "cover/mesh/triangulate.h"
#include "cover/mesh/validate.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"

namespace cover {
namespace {

using K = CGAL::Epick;
using Point3 = K::Point_3;

Point3 to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

struct Triangle {
  std::array<uint32_t, 3> v;
  uint32_t face;
  int axis;  ///< normal_axis of its corners: the projection filters' first choice
};

Triangle make_triangle(const std::array<uint32_t, 3>& t, uint32_t face, std::span<const Vec3> v) {
  return {t, face, normal_axis(v[t[0]], v[t[1]], v[t[2]])};
}

/// Whether the corners of `b` not in `skip` lie strictly on one side of the plane of `a`
/// (exact orient3d on the doubles): then b meets a's plane at most in the skipped corners.
bool strictly_aside(const Triangle& a, const Triangle& b, std::span<const Vec3> v, uint32_t skip) {
  int side = 0;
  for (uint32_t c : b.v) {
    if (c == skip) continue;
    const int s = orient3d(v[a.v[0]], v[a.v[1]], v[a.v[2]], v[c]);
    if (s == 0 || (side != 0 && s != side)) return false;
    side = s;
  }
  return true;
}

/// Corners two triangles share by vertex index: how many, the positions in a and in b of the
/// last shared pair, and the position in each of its first unshared corner (3 if none).
struct SharedCorners {
  int count = 0, ia = 0, ib = 0, ra = 3, rb = 3;
};
SharedCorners shared_corners(const Triangle& a, const Triangle& b) {
  SharedCorners c;
  std::array<bool, 3> a_shared{}, b_shared{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a.v[i] == b.v[j]) {
        ++c.count;
        a_shared[i] = b_shared[j] = true;
        c.ia = i;
        c.ib = j;
      }
  for (int i = 2; i >= 0; --i) {
    if (!a_shared[i]) c.ra = i;
    if (!b_shared[i]) c.rb = i;
  }
  return c;
}

/// An axis the plane of triangle t is not parallel to: its normal_axis, confirmed by an exact
/// orient2d (another axis if that is 0: t is never collinear).
int projection_axis(const Triangle& t, std::span<const Vec3> v) {
  const int first = t.axis;
  for (int i = 0; i < 3; ++i) {
    const int k = (first + i) % 3;
    if (orient2d(v[t.v[0]], v[t.v[1]], v[t.v[2]], k) != 0) return k;
  }
  return first;  // unreachable for a non-collinear triangle
}

/// Whether every corner of b lies in the plane of a (exact orient3d).
bool coplanar(const Triangle& a, const Triangle& b, std::span<const Vec3> v) {
  for (uint32_t c : b.v)
    if (c != a.v[0] && c != a.v[1] && c != a.v[2] &&
        orient3d(v[a.v[0]], v[a.v[1]], v[a.v[2]], v[c]) != 0)
      return false;
  return true;
}

/// triangles_meet for two COPLANAR triangles, decided by exact orient2d on the doubles in the
/// projection that drops axis k — any axis the plane is not parallel to (the projection is then
/// an affine bijection of the plane, which keeps incidences, orientations up to one sign, and
/// order along lines): the same rules, much cheaper than CGAL's 3D coplanar tests, whose filters
/// fail on exactly coplanar input and fall back to exact arithmetic at every step. Tiles are
/// never collinear.
bool planar_triangles_meet(const Triangle& a, const Triangle& b, std::span<const Vec3> v, int k) {
  const int u = (k + 1) % 3, w = (k + 2) % 3;
  auto o = [&](uint32_t x, uint32_t y, uint32_t z) { return orient2d(v[x], v[y], v[z], k); };
  auto between = [&](uint32_t p, uint32_t q, uint32_t c) {  // c on line pq: within the segment?
    return std::min(v[p][u], v[q][u]) <= v[c][u] && v[c][u] <= std::max(v[p][u], v[q][u]) &&
           std::min(v[p][w], v[q][w]) <= v[c][w] && v[c][w] <= std::max(v[p][w], v[q][w]);
  };
  auto segments_meet = [&](uint32_t p, uint32_t q, uint32_t c, uint32_t d) {  // closed
    const int d1 = o(p, q, c), d2 = o(p, q, d), d3 = o(c, d, p), d4 = o(c, d, q);
    if (d1 * d2 < 0 && d3 * d4 < 0) return true;
    return (d1 == 0 && between(p, q, c)) || (d2 == 0 && between(p, q, d)) ||
           (d3 == 0 && between(c, d, p)) || (d4 == 0 && between(c, d, q));
  };
  auto inside = [&](uint32_t x, const Triangle& t) {  // closed
    const int s = o(t.v[0], t.v[1], t.v[2]);
    return s * o(t.v[0], t.v[1], x) >= 0 && s * o(t.v[1], t.v[2], x) >= 0 &&
           s * o(t.v[2], t.v[0], x) >= 0;
  };
  auto segment_meets_triangle = [&](uint32_t p, uint32_t q, const Triangle& t) {
    if (inside(p, t) || inside(q, t)) return true;
    for (int i = 0; i < 3; ++i)
      if (segments_meet(p, q, t.v[i], t.v[(i + 1) % 3])) return true;
    return false;
  };
  const auto [shared, ia, ib, ra, rb] = shared_corners(a, b);
  if (shared == 3) return true;
  if (shared == 2) {  // third corners strictly on one side of the shared edge
    const uint32_t q0 = a.v[(ra + 1) % 3], q1 = a.v[(ra + 2) % 3];
    return o(q0, q1, a.v[ra]) * o(q0, q1, b.v[rb]) > 0;
  }
  if (shared == 1)
    return segment_meets_triangle(a.v[(ia + 1) % 3], a.v[(ia + 2) % 3], b) ||
           segment_meets_triangle(b.v[(ib + 1) % 3], b.v[(ib + 2) % 3], a);
  for (int i = 0; i < 3; ++i)
    if (segment_meets_triangle(a.v[i], a.v[(i + 1) % 3], b)) return true;
  return inside(b.v[0], a);
}

/// The axis k on which all corners of both triangles share one coordinate, or −1.
int common_axis_plane(const Triangle& a, const Triangle& b, std::span<const Vec3> v) {
  for (int k = 0; k < 3; ++k) {
    const double c = v[a.v[0]][k];
    if (v[a.v[1]][k] == c && v[a.v[2]][k] == c && v[b.v[0]][k] == c && v[b.v[1]][k] == c &&
        v[b.v[2]][k] == c)
      return k;
  }
  return -1;
}

/// A filter for triangles that share one or two corners: whether, in the projection along
/// axis k (any axis is sound), some line through their shared part has one triangle strictly on
/// one side (but for that part) and the other strictly on the other side, the first one not
/// flat in the projection. Then they meet only in the shared part: the projections meet only in
/// the shared part's projection, and a projection that does not flatten a triangle is one to
/// one on it. Signs are those orient2d's floating-point filter decides (exact); an undecided
/// one counts as 0 and fails the filter. Adjacent triangles of a mesh (a mesh's self-check
/// tests about seven such pairs per triangle: 225k on cheese ∪ fandisk) mostly pass it,
/// coplanar ones included, which otherwise took up to four exact orient3d that are zero.
bool apart_in_projection(const Triangle& a, const Triangle& b, const SharedCorners& c,
                         std::span<const Vec3> v, int k) {
  // Strict signs only (orient2d_strict: 0 when the filter cannot decide): a 0 fails the test.
  auto o = [&](uint32_t x, uint32_t y, uint32_t z) { return orient2d_strict(v[x], v[y], v[z], k); };
  if (c.count == 2) {  // the shared edge's line: the third corners strictly on opposite sides
    const uint32_t q0 = a.v[(c.ra + 1) % 3], q1 = a.v[(c.ra + 2) % 3];
    return o(q0, q1, a.v[c.ra]) * o(q0, q1, b.v[c.rb]) < 0;
  }
  // One shared corner s: a line through s and another corner d of one triangle, its third
  // corner `own` strictly on one side, both other corners of the other triangle strictly on
  // the other side (two convex angles at s apart have such a line among their four sides).
  const uint32_t s = a.v[c.ia];
  const uint32_t a1 = a.v[(c.ia + 1) % 3], a2 = a.v[(c.ia + 2) % 3];
  const uint32_t b1 = b.v[(c.ib + 1) % 3], b2 = b.v[(c.ib + 2) % 3];
  auto separates = [&](uint32_t d, uint32_t own, uint32_t x, uint32_t y) {
    const int side = o(s, d, own);
    return side != 0 && o(s, d, x) == -side && o(s, d, y) == -side;
  };
  return separates(a1, a2, b1, b2) || separates(a2, a1, b1, b2) || separates(b1, b2, a1, a2) ||
         separates(b2, b1, a1, a2);
}

/// Whether the projections along axis k of two triangles without shared corners are apart: an
/// edge line of one has its third corner strictly on one side and the other triangle strictly
/// on the other (two disjoint convex polygons have such an edge). Disjoint projections, disjoint
/// triangles.
bool disjoint_in_projection(const Triangle& a, const Triangle& b, std::span<const Vec3> v, int k) {
  // Strict signs only (orient2d_strict: 0 when the filter cannot decide): a 0 fails the test.
  auto o = [&](uint32_t x, uint32_t y, uint32_t z) { return orient2d_strict(v[x], v[y], v[z], k); };
  auto separates = [&](const Triangle& t, const Triangle& u) {
    for (int i = 0; i < 3; ++i) {
      const uint32_t p = t.v[i], q = t.v[(i + 1) % 3];
      const int side = o(p, q, t.v[(i + 2) % 3]);
      if (side != 0 && o(p, q, u.v[0]) == -side && o(p, q, u.v[1]) == -side &&
          o(p, q, u.v[2]) == -side)
        return true;
    }
    return false;
  };
  return separates(a, b) || separates(b, a);
}

/// apart_in_projection along the dominant axis of a's normal, then of b's (pairs across a
/// sharp edge or corner, where one of them is flat in the other's projection).
bool apart_in_projection(const Triangle& a, const Triangle& b, const SharedCorners& c,
                         std::span<const Vec3> v) {
  if (apart_in_projection(a, b, c, v, a.axis)) return true;
  return b.axis != a.axis && apart_in_projection(a, b, c, v, b.axis);
}

/// Whether two triangles of different faces meet anywhere beyond their shared vertices.
/// Projection filters first (orient2d only): apart_in_projection for triangles with shared
/// corners, disjoint_in_projection for the others. Before CGAL's tests, a filter of at most six
/// exact orient3d: when the unshared corners of one triangle lie strictly on one side of the
/// other's plane, they meet at most in the shared vertex.
/// `p[i]` is vertex i as a CGAL point (a vector of them, or PointsOf below).
template <class Points>
bool triangles_meet(const Triangle& a, const Triangle& b, const Points& p,
                    std::span<const Vec3> v) {
  const SharedCorners corners = shared_corners(a, b);
  const auto [shared, ia, ib, ra, rb] = corners;
  if (shared == 3) return true;
  if (shared > 0 && apart_in_projection(a, b, corners, v)) return false;
  // One axis plane (as the caps on cell walls): the planar test at once, without orient3d.
  if (const int k = common_axis_plane(a, b, v); k >= 0) return planar_triangles_meet(a, b, v, k);
  if (shared == 2) {  // coplanar, and both third corners on one side of the shared edge
    if (orient3d(v[a.v[0]], v[a.v[1]], v[a.v[2]], v[b.v[rb]]) != 0) return false;
    const int k = projection_axis(a, v);
    const uint32_t q0 = a.v[(ra + 1) % 3], q1 = a.v[(ra + 2) % 3];
    return orient2d(v[q0], v[q1], v[a.v[ra]], k) * orient2d(v[q0], v[q1], v[b.v[rb]], k) > 0;
  }
  const uint32_t skip = shared == 1 ? a.v[ia] : UINT32_MAX;
  if (shared == 0) {  // the projections along the dominant axes of both normals
    const int ka = a.axis, kb = b.axis;
    if (disjoint_in_projection(a, b, v, ka) || (kb != ka && disjoint_in_projection(a, b, v, kb)))
      return false;
  }
  if (strictly_aside(a, b, v, skip) || strictly_aside(b, a, v, skip)) return false;
  if (coplanar(a, b, v)) return planar_triangles_meet(a, b, v, projection_axis(a, v));
  const K::Triangle_3 ta(p[a.v[0]], p[a.v[1]], p[a.v[2]]);
  const K::Triangle_3 tb(p[b.v[0]], p[b.v[1]], p[b.v[2]]);
  if (shared == 1) {
    const K::Segment_3 sa(p[a.v[(ia + 1) % 3]], p[a.v[(ia + 2) % 3]]);
    const K::Segment_3 sb(p[b.v[(ib + 1) % 3]], p[b.v[(ib + 2) % 3]]);
    return CGAL::do_intersect(ta, sb) || CGAL::do_intersect(tb, sa);
  }
  return CGAL::do_intersect(ta, tb);
}

/// Vertices as CGAL points on demand (an Epick point is its three doubles).
struct PointsOf {
  std::span<const Vec3> v;
  Point3 operator[](uint32_t i) const { return to_point(v[i]); }
};

/// The axis of n's largest component in magnitude (the first on ties).
int largest_axis(const Vec3& n) {
  const double m[3] = {std::abs(n.x), std::abs(n.y), std::abs(n.z)};
  return m[0] >= m[1] && m[0] >= m[2] ? 0 : (m[1] >= m[2] ? 1 : 2);
}

/// Whether a and b share a vertex whose fan is a flat star (star_vertices): then they meet
/// only at shared vertices or along a shared edge.
bool share_star(const Triangle& a, const Triangle& b, std::span<const uint8_t> star) {
  for (uint32_t c : a.v)
    if (star[c] && (c == b.v[0] || c == b.v[1] || c == b.v[2])) return true;
  return false;
}

/// The triangles' corner ids.
std::vector<std::array<uint32_t, 3>> corners_of(const std::vector<Triangle>& triangles) {
  std::vector<std::array<uint32_t, 3>> corners(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) corners[t] = triangles[t].v;
  return corners;
}

/// star_vertices of the triangles' fans.
std::vector<uint8_t> stars_of(const std::vector<Triangle>& triangles, std::span<const Vec3> v) {
  return star_vertices(corners_of(triangles), {}, v);
}

}  // namespace

bool tiles_meet(const std::array<uint32_t, 3>& a, const std::array<uint32_t, 3>& b,
                std::span<const Vec3> v) {
  return tiles_meet(a, b, v, normal_axis(v[a[0]], v[a[1]], v[a[2]]),
                    normal_axis(v[b[0]], v[b[1]], v[b[2]]));
}

bool tiles_meet(const std::array<uint32_t, 3>& a, const std::array<uint32_t, 3>& b,
                std::span<const Vec3> v, int axis_a, int axis_b) {
  return triangles_meet(Triangle{a, 0, axis_a}, Triangle{b, 1, axis_b}, PointsOf{v}, v);
}

int normal_axis(const Vec3& a, const Vec3& b, const Vec3& c) {
  return largest_axis(cross(b - a, c - a));
}

std::vector<uint8_t> star_vertices(std::span<const std::array<uint32_t, 3>> tris,
                                   std::span<const uint32_t> group, std::span<const Vec3> v) {
  // The triangles of each vertex (compressed rows, triangle order).
  std::vector<uint32_t> start(v.size() + 1, 0);
  for (const auto& t : tris)
    for (uint32_t c : t) ++start[c + 1];
  for (size_t x = 0; x < v.size(); ++x) start[x + 1] += start[x];
  std::vector<uint32_t> around(start.back());
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (uint32_t t = 0; t < tris.size(); ++t)
      for (uint32_t c : tris[t]) around[fill[c]++] = t;
  }
  constexpr size_t kMaxFan = 64;  // larger fans (poles) are left to the pair tests
  std::vector<uint8_t> star(v.size(), 0);
  parallel_for(v.size(), 1024, [&](size_t begin, size_t end) {
    std::array<uint32_t, kMaxFan> x, y, next;  // per fan triangle: the corners after s; cycle
    std::array<int, kMaxFan> side;
    std::array<std::pair<uint32_t, uint32_t>, kMaxFan> by_x;  // (x, triangle), sorted by x
    for (size_t s = begin; s < end; ++s) {
      const size_t d = start[s + 1] - start[s];
      if (d < 3 || d > kMaxFan) continue;
      const uint32_t* fan = around.data() + start[s];
      bool ok = true;
      Vec3 normal{0, 0, 0};
      for (size_t i = 0; i < d && ok; ++i) {
        const auto& t = tris[fan[i]];
        const int at = t[0] == s ? 0 : (t[1] == s ? 1 : 2);
        x[i] = t[(at + 1) % 3];
        y[i] = t[(at + 2) % 3];
        ok = group.empty() || group[fan[i]] == group[fan[0]];
        normal = normal + cross(v[x[i]] - v[s], v[y[i]] - v[s]);
      }
      // One cycle: each triangle's y is exactly one triangle's x, and following the links from
      // the first triangle visits all d. (Large fans, as the fans of flat CAD faces, look the
      // x up in a sorted copy.)
      if (d <= 8) {
        for (size_t i = 0; i < d && ok; ++i) {
          size_t found = 0;
          for (size_t j = 0; j < d; ++j)
            if (x[j] == y[i]) next[i] = static_cast<uint32_t>(j), ++found;
          ok = found == 1;
        }
      } else if (ok) {
        for (size_t j = 0; j < d; ++j) by_x[j] = {x[j], static_cast<uint32_t>(j)};
        std::sort(by_x.begin(), by_x.begin() + d);
        for (size_t j = 1; j < d && ok; ++j) ok = by_x[j].first != by_x[j - 1].first;
        for (size_t i = 0; i < d && ok; ++i) {
          const auto it = std::lower_bound(by_x.begin(), by_x.begin() + d,
                                           std::pair<uint32_t, uint32_t>{y[i], 0});
          ok = it != by_x.begin() + d && it->first == y[i];
          if (ok) next[i] = it->second;
        }
      }
      if (!ok) continue;
      // Back at the first triangle after exactly d links, not before: all d in one cycle.
      size_t at = 0, length = 0;
      do {
        at = next[at];
        ++length;
      } while (at != 0 && length < d);
      if (at != 0 || length != d) continue;
      // In a projection (along an axis, or along the fan's normal when every axis flattens
      // some triangle, as at the corners and sharp edges of CAD models): every triangle turns
      // the same way (sigma) around s, strictly, so each spans an angle in (0, π) from ray x[i]
      // to ray y[i] = x[next[i]], and the rays sweep monotonically from r = s → x[0] back to
      // r, winding w ≥ 1 times. The sweep passes r's direction strictly inside some triangle
      // w − 1 times: w = 1 when no triangle contains r strictly (r strictly after x[i] and
      // strictly before y[i]). A ray collinear with r must point the other way (a vertex on a
      // straight edge, inside a planar grid), so that it bounds no triangle containing r;
      // `opposite` decides that for rays the projection makes collinear with r.
      const Vec3& p = v[s];
      const Vec3& r = v[x[0]];
      auto way = [&](const Vec3& e, int a) { return (e[a] > p[a]) - (e[a] < p[a]); };
      // turn(a, b): the sign of s → a → b in the projection (0 may mean undecided); exact(q):
      // that of s → r → q, exact.
      auto certify = [&](auto turn, auto exact, auto opposite) {
        const int sigma = turn(r, v[y[0]]);
        if (sigma == 0) return false;
        for (size_t i = 1; i < d; ++i)
          if (turn(v[x[i]], v[y[i]]) != sigma) return false;
        side[0] = 0;
        for (size_t j = 1; j < d; ++j) {
          side[j] = exact(v[x[j]]);
          if (side[j] == 0 && !opposite(v[x[j]])) return false;
        }
        for (size_t i = 1; i < d; ++i)
          if (next[i] != 0 && side[i] == -sigma && side[next[i]] == sigma) return false;
        return true;
      };
      const int k = largest_axis(normal);
      const int u = (k + 1) % 3, w = (k + 2) % 3;
      // Along axis k (orient2d's filter alone for the turns: an undecided one fails).
      ok = certify([&](const Vec3& a, const Vec3& b) { return orient2d_strict(p, a, b, k); },
                   [&](const Vec3& q) { return orient2d(p, r, q, k); },
                   [&](const Vec3& q) { return way(q, u) != way(r, u) || way(q, w) != way(r, w); });
      // Along the fan's normal, slightly tilted off the symmetric directions of CAD models (at
      // a cube's corner, along (1, 1, 1), opposite edges of the corner would look collinear;
      // any direction is sound): exact triple products. Rays collinear in it are taken only
      // when they are collinear in space, pointing apart.
      const double tilt = 0x1p-7 * (std::abs(normal.x) + std::abs(normal.y) + std::abs(normal.z));
      const Vec3 dir{normal.x + tilt, normal.y + tilt / 3, normal.z + tilt / 7};
      if (!ok)
        ok = certify([&](const Vec3& a, const Vec3& b) { return triple_sign(p, a, b, dir); },
                     [&](const Vec3& q) { return triple_sign(p, r, q, dir); },
                     [&](const Vec3& q) {
                       for (int a = 0; a < 3; ++a)
                         if (orient2d(p, r, q, a) != 0) return false;
                       return way(q, 0) != way(r, 0) || way(q, 1) != way(r, 1) ||
                              way(q, 2) != way(r, 2);
                     });
      star[s] = ok;
    }
  });
  return star;
}

bool self_intersects(const PolygonMesh& mesh) {
  std::vector<Point3> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.push_back(to_point(v));

  std::vector<Triangle> triangles;
  triangles.reserve(mesh.face_vertices.size());
  std::vector<std::array<uint32_t, 3>> tiles;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    tiles.clear();
    if (triangulate_face(mesh.vertices, mesh.face(f), tiles) != FaceTiling::kSimple) return true;
    for (const auto& t : tiles)
      triangles.push_back(make_triangle(t, static_cast<uint32_t>(f), mesh.vertices));
  }

  // Every pair of meeting triangle boxes (mesh/box_pairs.h: a grid, in parallel); the answer
  // does not depend on the order, and a found intersection stops the search.
  std::vector<Bbox> boxes(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    for (uint32_t v : triangles[t].v) boxes[t].add(mesh.vertices[v]);
  const std::vector<uint8_t> star = stars_of(triangles, mesh.vertices);
  std::atomic<bool> found{false};
  box_pairs(boxes, [&](uint32_t x, uint32_t y) {
    const Triangle& a = triangles[x];
    const Triangle& b = triangles[y];
    if (a.face != b.face && !share_star(a, b, star) && triangles_meet(a, b, points, mesh.vertices))
      found = true;
    return found.load();
  });
  return found;
}

std::vector<std::pair<uint32_t, uint32_t>> intersecting_face_pairs(
    const PolygonMesh& mesh, std::span<const uint8_t> suspect, std::span<const uint32_t> group) {
  const bool all = suspect.empty();
  const size_t faces = mesh.face_count();
  if (!all && std::find(suspect.begin(), suspect.end(), uint8_t{1}) == suspect.end()) return {};
  // Faces that can meet a suspect one: all when suspects are many, else those whose box meets a
  // suspect face's box, found through a uniform grid over the suspects' boxes only (the few
  // faces with rounded vertices of a large result, without a broad phase over all of it).
  std::vector<uint8_t> needed(faces, 1);
  if (!all) {
    std::vector<Bbox> box(faces);
    parallel_for(faces, 4096, [&](size_t f0, size_t f1) {
      for (size_t f = f0; f < f1; ++f)
        for (uint32_t v : mesh.face(f)) box[f].add(mesh.vertices[v]);
    });
    std::vector<uint32_t> sus;
    Bbox span;
    double size = 0;
    for (uint32_t f = 0; f < faces; ++f)
      if (suspect[f]) {
        sus.push_back(f);
        span.add(box[f]);
        size += std::max({box[f].max.x - box[f].min.x, box[f].max.y - box[f].min.y,
                          box[f].max.z - box[f].min.z});
      }
    if (4 * sus.size() < faces) {
      // Cells of about twice the mean suspect box, at most about 8 per suspect in all.
      const Vec3 ext = span.max - span.min;
      double cell = std::max(2 * size / static_cast<double>(sus.size()),
                             std::max({ext.x, ext.y, ext.z}) * 1e-9);
      if (!(cell > 0)) cell = 1;  // all suspects at one point: one cell
      auto dims = [&](double c) {
        return std::array<int64_t, 3>{static_cast<int64_t>(ext.x / c) + 1,
                                      static_cast<int64_t>(ext.y / c) + 1,
                                      static_cast<int64_t>(ext.z / c) + 1};
      };
      auto n = dims(cell);
      while (n[0] * n[1] * n[2] > static_cast<int64_t>(8 * sus.size() + 64)) n = dims(cell *= 2);
      auto range = [&](const Bbox& b, int a) {
        // Clamped as doubles first: a face much larger than the span would overflow the cast.
        const double top = static_cast<double>(n[a] - 1);
        const double lo = std::clamp((b.min[a] - span.min[a]) / cell, 0.0, top);
        const double hi = std::clamp((b.max[a] - span.min[a]) / cell, 0.0, top);
        return std::pair<int64_t, int64_t>{static_cast<int64_t>(lo), static_cast<int64_t>(hi)};
      };
      // The suspects of each cell (compressed rows: a count pass, then a fill pass; one vector
      // per cell cost a third of this filter on cheese ∪ fandisk's 6.5k suspects).
      const size_t cells = static_cast<size_t>(n[0] * n[1] * n[2]);
      std::vector<uint32_t> first(cells + 1, 0), in_cell;
      auto each_cell = [&](uint32_t f, auto&& visit) {
        const auto [x0, x1] = range(box[f], 0);
        const auto [y0, y1] = range(box[f], 1);
        const auto [z0, z1] = range(box[f], 2);
        for (int64_t z = z0; z <= z1; ++z)
          for (int64_t y = y0; y <= y1; ++y)
            for (int64_t x = x0; x <= x1; ++x)
              visit(static_cast<size_t>((z * n[1] + y) * n[0] + x));
      };
      for (uint32_t f : sus) each_cell(f, [&](size_t c) { ++first[c + 1]; });
      for (size_t c = 0; c < cells; ++c) first[c + 1] += first[c];
      in_cell.resize(first[cells]);
      {
        std::vector<uint32_t> fill(first.begin(), first.end() - 1);
        for (uint32_t f : sus) each_cell(f, [&](size_t c) { in_cell[fill[c]++] = f; });
      }
      auto meet = [](const Bbox& a, const Bbox& b) {
        return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y &&
               b.min.y <= a.max.y && a.min.z <= b.max.z && b.min.z <= a.max.z;
      };
      parallel_for(faces, 4096, [&](size_t f0, size_t f1) {
        for (size_t f = f0; f < f1; ++f) {
          needed[f] = suspect[f];
          if (needed[f] || !meet(box[f], span)) continue;
          const auto [x0, x1] = range(box[f], 0);
          const auto [y0, y1] = range(box[f], 1);
          const auto [z0, z1] = range(box[f], 2);
          for (int64_t z = z0; z <= z1 && !needed[f]; ++z)
            for (int64_t y = y0; y <= y1 && !needed[f]; ++y)
              for (int64_t x = x0; x <= x1 && !needed[f]; ++x)
                for (size_t c = static_cast<size_t>((z * n[1] + y) * n[0] + x), i = first[c];
                     i < first[c + 1]; ++i)
                  if (meet(box[f], box[in_cell[i]])) {
                    needed[f] = 1;
                    break;
                  }
        }
      });
    }
  }
  std::vector<Point3> points(mesh.vertices.size());
  for (size_t v = 0; v < points.size(); ++v) points[v] = to_point(mesh.vertices[v]);
  // Tiles per chunk of faces, in parallel, then in face order.
  constexpr size_t kGrain = 1024;
  const size_t chunks = (faces + kGrain - 1) / kGrain;
  std::vector<std::vector<Triangle>> chunk_tris(chunks);
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> chunk_bad(chunks);
  parallel_for(faces, kGrain, [&](size_t f0, size_t f1) {
    std::vector<std::array<uint32_t, 3>> tiles;
    const size_t c = f0 / kGrain;
    for (size_t f = f0; f < f1; ++f) {
      if (!needed[f]) continue;
      tiles.clear();
      if (triangulate_face(mesh.vertices, mesh.face(f), tiles) != FaceTiling::kSimple) {
        if (all || suspect[f])
          chunk_bad[c].push_back({static_cast<uint32_t>(f), static_cast<uint32_t>(f)});
        continue;
      }
      for (const auto& t : tiles)
        chunk_tris[c].push_back(make_triangle(t, static_cast<uint32_t>(f), mesh.vertices));
    }
  });
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  std::vector<Triangle> triangles;
  for (size_t c = 0; c < chunks; ++c) {
    pairs.insert(pairs.end(), chunk_bad[c].begin(), chunk_bad[c].end());
    triangles.insert(triangles.end(), chunk_tris[c].begin(), chunk_tris[c].end());
  }
  // Every pair of meeting tile boxes (mesh/box_pairs.h); pairs without a suspect face skipped.
  std::vector<Bbox> boxes(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    for (uint32_t v : triangles[t].v) boxes[t].add(mesh.vertices[v]);
  // Pairs sharing a flat-star vertex are dropped by the scan itself (one colour for all).
  const std::vector<std::array<uint32_t, 3>> corners = corners_of(triangles);
  const std::vector<BoxCorners> marked =
      marked_corners(corners, star_vertices(corners, {}, mesh.vertices));
  const std::vector<uint32_t> one_colour(triangles.size(), 0);
  std::mutex found_mutex;  // contacts are rare: one lock per found pair
  box_pairs_between(boxes, one_colour, marked, [&](uint32_t x, uint32_t y) {
    const Triangle& a = triangles[x];
    const Triangle& b = triangles[y];
    if (a.face == b.face || (!all && !suspect[a.face] && !suspect[b.face])) return;
    if (!group.empty() && group[a.face] != 0 && group[a.face] == group[b.face]) return;
    if (triangles_meet(a, b, points, mesh.vertices)) {
      const std::lock_guard<std::mutex> lock(found_mutex);
      pairs.push_back({std::min(a.face, b.face), std::max(a.face, b.face)});
    }
  });
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace cover
