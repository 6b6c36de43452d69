// Exact self-intersection test (validate.h). All predicates are CGAL's Epick filtered predicates
// on the input doubles (exact); no point is ever constructed. Notation:
//   triangle   three vertex indices and the face it covers; collinear triangles are dropped
//   tiling     the triangles of one face (solid/triangulate.h) cover exactly the face's region,
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
#include <cstdint>
#include <mutex>
#include <vector>

#include "solid/box_pairs.h"
#include "solid/parallel.h"
#include "solid/predicates.h"
#include "solid/triangulate.h"
#include "solid/validate.h"

namespace cover {
namespace {

using K = CGAL::Epick;
using Point3 = K::Point_3;

Point3 to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

struct Triangle {
  std::array<uint32_t, 3> v;
  uint32_t face;
};

/// Whether the corners of `b` not in `skip` lie strictly on one side of the plane of `a`
/// (exact orient3d on the doubles): then b meets a's plane at most in the skipped corners.
bool strictly_aside(const Triangle& a, const Triangle& b, std::span<const Vec3> v,
                    uint32_t skip) {
  int side = 0;
  for (uint32_t c : b.v) {
    if (c == skip) continue;
    const int s = orient3d(v[a.v[0]], v[a.v[1]], v[a.v[2]], v[c]);
    if (s == 0 || (side != 0 && s != side)) return false;
    side = s;
  }
  return true;
}

/// Whether two triangles of different faces meet anywhere beyond their shared vertices.
/// Before CGAL's tests, a filter of at most six exact orient3d: when the unshared corners of one
/// triangle lie strictly on one side of the other's plane, they meet at most in the shared vertex.
bool triangles_meet(const Triangle& a, const Triangle& b, const std::vector<Point3>& p,
                    std::span<const Vec3> v) {
  int shared = 0, ia = 0, ib = 0;
  std::array<bool, 3> a_shared{}, b_shared{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a.v[i] == b.v[j]) {
        ++shared;
        a_shared[i] = b_shared[j] = true;
        ia = i;
        ib = j;
      }
  if (shared == 3) return true;
  if (shared == 2) {
    int ra = 0, rb = 0;  // the unshared (third) vertices
    while (a_shared[ra]) ++ra;
    while (b_shared[rb]) ++rb;
    const Point3& q0 = p[a.v[(ra + 1) % 3]];
    const Point3& q1 = p[a.v[(ra + 2) % 3]];
    return CGAL::coplanar(q0, q1, p[a.v[ra]], p[b.v[rb]]) &&
           CGAL::coplanar_orientation(q0, q1, p[a.v[ra]], p[b.v[rb]]) == CGAL::POSITIVE;
  }
  const uint32_t skip = shared == 1 ? a.v[ia] : UINT32_MAX;
  if (strictly_aside(a, b, v, skip) || strictly_aside(b, a, v, skip)) return false;
  const K::Triangle_3 ta(p[a.v[0]], p[a.v[1]], p[a.v[2]]);
  const K::Triangle_3 tb(p[b.v[0]], p[b.v[1]], p[b.v[2]]);
  if (shared == 1) {
    const K::Segment_3 sa(p[a.v[(ia + 1) % 3]], p[a.v[(ia + 2) % 3]]);
    const K::Segment_3 sb(p[b.v[(ib + 1) % 3]], p[b.v[(ib + 2) % 3]]);
    return CGAL::do_intersect(ta, sb) || CGAL::do_intersect(tb, sa);
  }
  return CGAL::do_intersect(ta, tb);
}

}  // namespace

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
    for (const auto& t : tiles) triangles.push_back({t, static_cast<uint32_t>(f)});
  }

  // Every pair of meeting triangle boxes (solid/box_pairs.h: a grid, in parallel); the answer
  // does not depend on the order, and a found intersection stops the search.
  std::vector<Bbox> boxes(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    for (uint32_t v : triangles[t].v) boxes[t].add(mesh.vertices[v]);
  std::atomic<bool> found{false};
  box_pairs(boxes, [&](uint32_t x, uint32_t y) {
    const Triangle& a = triangles[x];
    const Triangle& b = triangles[y];
    if (a.face != b.face && triangles_meet(a, b, points, mesh.vertices)) found = true;
    return found.load();
  });
  return found;
}

std::vector<std::pair<uint32_t, uint32_t>> intersecting_face_pairs(
    const PolygonMesh& mesh, std::span<const uint8_t> suspect) {
  const bool all = suspect.empty();
  const size_t faces = mesh.face_count();
  if (!all && std::find(suspect.begin(), suspect.end(), uint8_t{1}) == suspect.end()) return {};
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
      tiles.clear();
      if (triangulate_face(mesh.vertices, mesh.face(f), tiles) != FaceTiling::kSimple) {
        if (all || suspect[f]) chunk_bad[c].push_back({static_cast<uint32_t>(f), static_cast<uint32_t>(f)});
        continue;
      }
      for (const auto& t : tiles) chunk_tris[c].push_back({t, static_cast<uint32_t>(f)});
    }
  });
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  std::vector<Triangle> triangles;
  for (size_t c = 0; c < chunks; ++c) {
    pairs.insert(pairs.end(), chunk_bad[c].begin(), chunk_bad[c].end());
    triangles.insert(triangles.end(), chunk_tris[c].begin(), chunk_tris[c].end());
  }
  // Every pair of meeting tile boxes (solid/box_pairs.h); pairs without a suspect face skipped.
  std::vector<Bbox> boxes(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t)
    for (uint32_t v : triangles[t].v) boxes[t].add(mesh.vertices[v]);
  std::mutex found_mutex;  // contacts are rare: one lock per found pair
  box_pairs(boxes, [&](uint32_t x, uint32_t y) {
    const Triangle& a = triangles[x];
    const Triangle& b = triangles[y];
    if (a.face == b.face || (!all && !suspect[a.face] && !suspect[b.face])) return false;
    if (triangles_meet(a, b, points, mesh.vertices)) {
      const std::lock_guard<std::mutex> lock(found_mutex);
      pairs.push_back({std::min(a.face, b.face), std::max(a.face, b.face)});
    }
    return false;
  });
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace cover
