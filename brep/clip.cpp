// Plane clip on the HalfedgeMesh ([Erleben2006 §3] "Determining Open Boundaries").
//
// Steps, all with the kernel's operators:
//   1. exact side s(v) ∈ {−1, 0, +1} of every input vertex (plane_side, no tolerance);
//   2. a face with vertices on both sides whose boundary meets the plane more than twice (only a
//      non-convex face can) is first triangulated by ear clipping in its own projection plane
//      (exact orient2d on the input doubles): we triangulate such faces rather than pairing the
//      crossings along the line, so every remaining crossing face meets the plane exactly twice;
//   3. split_edge on every edge with s = +1 at one end and −1 at the other: one new vertex per
//      edge, shared by the faces (and later the halves) on both sides;
//   4. split_face of every crossing face between its two vertices on the plane;
//   5. every face now lies on one side; a face lying in the plane goes to the half it bounds from
//      outside (its normal·n < 0: above, > 0: below; exact area sign);
//   6. detach_edge on every edge between faces of different halves (both ends are on the plane);
//   7. caps on the border rings (cap.cpp), then split_nonmanifold_vertices separates the halves'
//      shared plane vertices and the fans of pinched vertices.
#include "cover/brep/clip.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "cover/brep/detail/clip_internal.h"
#include "cover/brep/detail/ear_clip.h"
#include "cover/mesh/triangulate.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover::brep {
namespace {

/// Ear-clip face f (its input vertices, in the projection of its Newell normal) with split_face;
/// each new face's input face is appended to `source`.
void triangulate_face(HalfedgeMesh& m, uint32_t f, std::vector<uint32_t>& source) {
  std::vector<uint32_t> he;
  Vec3 normal;
  {
    uint32_t h = m.face_halfedge(f);
    do {
      he.push_back(h);
      const Vec3& p = m.position(m.origin(h));
      const Vec3& q = m.position(m.head(h));
      normal = normal + Vec3{(p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x),
                             (p.x - q.x) * (p.y + q.y)};
      h = m.next(h);
    } while (h != m.face_halfedge(f));
  }
  const int axis = dominant_axis(normal);
  const int sign = normal[axis] < 0 ? -1 : 1;
  const int u = axis == 2 ? 0 : axis + 1, w = axis == 0 ? 2 : (axis == 1 ? 0 : 1);
  struct Geometry {
    const HalfedgeMesh& m;
    const std::vector<uint32_t>& he;
    int axis, sign, u, w;
    const Vec3& p(uint32_t i) const { return m.position(m.origin(he[i])); }
    int orient(uint32_t a, uint32_t b, uint32_t c) const {
      return sign * orient2d(p(a), p(b), p(c), axis);
    }
    uint32_t id(uint32_t i) const { return m.origin(he[i]); }
    bool thin(uint32_t, uint32_t, uint32_t) const { return false; }
    std::array<double, 4> bounds(uint32_t i) const { return {p(i)[u], p(i)[u], p(i)[w], p(i)[w]}; }
    bool box_may_contain(uint32_t q, uint32_t a, uint32_t b, uint32_t c) const {
      for (int k : {u, w}) {
        const double x = p(q)[k];
        if (x < std::min({p(a)[k], p(b)[k], p(c)[k]}) || x > std::max({p(a)[k], p(b)[k], p(c)[k]}))
          return false;
      }
      return true;
    }
  } geometry{m, he, axis, sign, u, w};
  int64_t forced = 0;
  const auto tris = detail::ear_clip(static_cast<uint32_t>(he.size()), geometry, forced);
  // out[i]: the remainder's half-edge leaving corner i. Cutting ear (a, b, c) splits off the
  // chain a → b → c; the remainder keeps the new half-edge a → c.
  std::vector<uint32_t> out = he;
  for (size_t t = 0; t + 1 < tris.size(); ++t) {
    out[tris[t][0]] = m.split_face(out[tris[t][0]], out[tris[t][2]]);
    source.push_back(source[f]);
  }
}

/// The clip by `plane`, or, when `through` is set, by the exact plane through those points (then
/// `plane` is a rounded stand-in whose normal's dominant component has the exact sign).
ClipResult clip_impl(const PolygonMesh& mesh, const Plane& plane,
                     const std::optional<std::array<Vec3, 3>>& through, int axis,
                     const ClipOptions& options) {
  const Vec3 n = plane.normal;
  HalfedgeMesh m = HalfedgeMesh::from_polygon_mesh(mesh);
  {
    int64_t border = 0;
    for (uint32_t h = 0; h < m.halfedge_slots(); ++h) border += m.is_border(h);
    if (border > 0) throw InputError("open mesh: " + std::to_string(border) + " boundary edges");
  }
  detail::CapContext ctx;
  ctx.plane = plane;
  ctx.through = through;
  ctx.axis = axis;
  ctx.original_vertices = m.vertex_slots();
  ctx.input_points.assign(mesh.vertices.begin(), mesh.vertices.end());
  ctx.triangulate = options.triangulate_caps;
  const uint32_t n0 = m.vertex_slots();

  // 1. Exact vertex sides.
  std::vector<int8_t> side(n0);
  parallel_for(n0, 4096, [&](size_t b, size_t e) {
    for (size_t v = b; v < e; ++v)
      side[v] = static_cast<int8_t>(
          through ? orient3d((*through)[0], (*through)[1], (*through)[2], mesh.vertices[v])
                  : plane_side(n, plane.offset, mesh.vertices[v]));
  });
  auto sign_of = [&](uint32_t v) { return v < n0 ? side[v] : int8_t{0}; };

  // 2. Crossing faces that meet the plane more than twice are triangulated first.
  // source[f]: the input face that face f is part of (split_face appends one face each time).
  const uint32_t f0 = m.face_slots();
  std::vector<uint32_t> source(f0);
  for (uint32_t f = 0; f < f0; ++f) source[f] = f;
  for (uint32_t f = 0; f < f0; ++f) {
    bool pos = false, neg = false;
    int meets = 0;
    uint32_t h = m.face_halfedge(f);
    do {
      const int8_t a = side[m.origin(h)], b = side[m.head(h)];
      pos |= a > 0;
      neg |= a < 0;
      meets += (a == 0) + (a * b < 0);
      h = m.next(h);
    } while (h != m.face_halfedge(f));
    if (pos && neg && meets > 2) triangulate_face(m, f, source);
  }

  // 3. Split crossing edges (each constructed point once, shared by both sides).
  const uint32_t h0 = m.halfedge_slots();
  for (uint32_t h = 0; h < h0; h += 2) {
    const uint32_t a = m.origin(h), b = m.head(h);
    if (side[a] * side[b] >= 0) continue;
    const Vec3 pa = mesh.vertices[a], pb = mesh.vertices[b];
    // Provisional position; cap.cpp replaces it by the exact point rounded to nearest.
    const double t = (plane.offset - dot(n, pa)) / (dot(n, pb) - dot(n, pa));
    m.split_edge(h, pa + (std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.5) * (pb - pa));
    ctx.constructed_from.push_back({a, b});
  }

  // 4. Split crossing faces between their two vertices on the plane.
  const uint32_t f1 = m.face_slots();
  for (uint32_t f = 0; f < f1; ++f) {
    bool pos = false, neg = false;
    uint32_t zero[3] = {kNone, kNone, kNone}, nz = 0;
    uint32_t h = m.face_halfedge(f);
    do {
      const int8_t s = sign_of(m.origin(h));
      pos |= s > 0;
      neg |= s < 0;
      if (s == 0 && nz < 3) zero[nz++] = h;
      h = m.next(h);
    } while (h != m.face_halfedge(f));
    if (!(pos && neg)) continue;
    if (nz != 2) throw InternalError("clip: crossing face does not meet the plane twice");
    m.split_face(zero[0], zero[1]);
    source.push_back(source[f]);
  }

  // 5. Sides of faces (0 above, 1 below).
  ctx.face_side.assign(m.face_slots(), 0);
  std::vector<Vec3> loop;
  for (uint32_t f = 0; f < m.face_slots(); ++f) {
    int s = 0;
    loop.clear();
    uint32_t h = m.face_halfedge(f);
    do {
      if (s == 0) s = sign_of(m.origin(h));
      loop.push_back(m.position(m.origin(h)));
      h = m.next(h);
    } while (h != m.face_halfedge(f));
    if (s == 0) {  // in the plane: all its vertices are input vertices
      const int area = polygon_orientation(loop, ctx.axis);
      s = -area * (n[ctx.axis] > 0 ? 1 : -1);  // normal·n < 0 → above
      if (s == 0) s = 1;
    }
    ctx.face_side[f] = s > 0 ? 0 : 1;
  }

  // 6. Detach the edges between the halves.
  const uint32_t h1 = m.halfedge_slots();
  for (uint32_t h = 0; h < h1; h += 2)
    if (ctx.face_side[m.face(h)] != ctx.face_side[m.face(h ^ 1)]) m.detach_edge(h);

  // 7. Caps, then one vertex per fan.
  const auto cap_start = std::chrono::steady_clock::now();
  const detail::CapStats stats = detail::add_caps(m, ctx);
  source.resize(m.face_slots(), kNoFace);
  const double cap_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - cap_start).count();
  ClipResult result;
  result.constructed_vertices = static_cast<int64_t>(ctx.constructed_from.size());
  result.split_vertices = m.split_nonmanifold_vertices();
  result.forced_ears = stats.forced_ears;
  result.cap_seconds = cap_seconds;
  result.above.rings = stats.rings[0];
  result.below.rings = stats.rings[1];
  result.above.cap_faces = stats.cap_faces[0];
  result.below.cap_faces = stats.cap_faces[1];

  // Output: the faces of each half over their own vertices.
  std::vector<uint32_t> index, ids;
  for (int s = 0; s < 2; ++s) {
    index.assign(m.vertex_slots(), kNone);
    PolygonMesh& out = s == 0 ? result.above.mesh : result.below.mesh;
    for (uint32_t f = 0; f < m.face_slots(); ++f) {
      if (ctx.face_side[f] != s) continue;
      ids.clear();
      uint32_t h = m.face_halfedge(f);
      do {
        const uint32_t v = m.origin(h);
        if (index[v] == kNone) {
          index[v] = static_cast<uint32_t>(out.vertices.size());
          out.vertices.push_back(m.position(v));
        }
        ids.push_back(index[v]);
        h = m.next(h);
      } while (h != m.face_halfedge(f));
      out.add_face(ids);
      (s == 0 ? result.above : result.below)
          .face_source.push_back(f < source.size() ? source[f] : kNoFace);
    }
  }
  return result;
}

}  // namespace

ClipResult clip(const PolygonMesh& mesh, const Plane& plane, const ClipOptions& options) {
  const Vec3 n = plane.normal;
  if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z) ||
      !std::isfinite(plane.offset))
    throw InputError("clip plane: expected finite numbers");
  if (n.x == 0 && n.y == 0 && n.z == 0) throw InputError("clip plane: the normal must be non-zero");
  return clip_impl(mesh, plane, std::nullopt, dominant_axis(n), options);
}

ClipResult clip(const PolygonMesh& mesh, const std::array<Vec3, 3>& through,
                const ClipOptions& options) {
  for (const Vec3& p : through)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError("clip plane: expected finite points");
  const Vec3 &p0 = through[0], &p1 = through[1], &p2 = through[2];
  const Vec3 approx = cross(p1 - p0, p2 - p0);
  // The cap projects along an axis where the exact normal is non-zero (orient2d is the sign of
  // that component of (p1 − p0) × (p2 − p0)); the largest rounded component first.
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3,
            [&](int a, int b) { return std::abs(approx[a]) > std::abs(approx[b]); });
  for (int axis : order) {
    const int sign = orient2d(p0, p1, p2, axis);
    if (sign == 0) continue;
    double c[3] = {approx.x, approx.y, approx.z};
    c[axis] = sign * std::max(std::abs(c[axis]), std::numeric_limits<double>::min());
    const Vec3 normal{c[0], c[1], c[2]};
    return clip_impl(mesh, Plane{normal, dot(normal, p0)}, through, axis, options);
  }
  throw InputError("clip plane: the three points are collinear");
}

}  // namespace cover::brep
