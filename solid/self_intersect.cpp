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
#include <CGAL/box_intersection_d.h>

#include <array>
#include <cstdint>
#include <vector>

#include "solid/triangulate.h"
#include "solid/validate.h"

namespace cover {
namespace {

using K = CGAL::Epick;
using Point3 = K::Point_3;

using Box =
    CGAL::Box_intersection_d::Box_with_info_d<double, 3, uint32_t,
                                              CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;

Point3 to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

struct Triangle {
  std::array<uint32_t, 3> v;
  uint32_t face;
};

/// Whether two triangles of different faces meet anywhere beyond their shared vertices.
bool triangles_meet(const Triangle& a, const Triangle& b, const std::vector<Point3>& p) {
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
  const K::Triangle_3 ta(p[a.v[0]], p[a.v[1]], p[a.v[2]]);
  const K::Triangle_3 tb(p[b.v[0]], p[b.v[1]], p[b.v[2]]);
  if (shared == 1) {
    const K::Segment_3 sa(p[a.v[(ia + 1) % 3]], p[a.v[(ia + 2) % 3]]);
    const K::Segment_3 sb(p[b.v[(ib + 1) % 3]], p[b.v[(ib + 2) % 3]]);
    return CGAL::do_intersect(ta, sb) || CGAL::do_intersect(tb, sa);
  }
  return CGAL::do_intersect(ta, tb);
}

struct FoundIntersection {};

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

  std::vector<Box> boxes;
  boxes.reserve(triangles.size());
  for (uint32_t t = 0; t < triangles.size(); ++t) {
    const auto& v = triangles[t].v;
    boxes.emplace_back(points[v[0]].bbox() + points[v[1]].bbox() + points[v[2]].bbox(), t);
  }
  std::vector<const Box*> box_ptrs;
  box_ptrs.reserve(boxes.size());
  for (const Box& b : boxes) box_ptrs.push_back(&b);

  auto test_pair = [&](const Box* x, const Box* y) {
    const Triangle& a = triangles[x->info()];
    const Triangle& b = triangles[y->info()];
    if (a.face != b.face && triangles_meet(a, b, points)) throw FoundIntersection{};
  };
  constexpr std::ptrdiff_t kCutoff = 2000;  // as in CGAL's self_intersections
  try {
    CGAL::box_self_intersection_d(box_ptrs.begin(), box_ptrs.end(), test_pair, kCutoff);
  } catch (const FoundIntersection&) {
    return true;
  }
  return false;
}

}  // namespace cover
