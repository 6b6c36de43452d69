// Exact self-intersection test (validate.h) and the exact predicates of detail/exact_geometry.h.
// The only file of solid/ that includes CGAL. All predicates are CGAL's Epick filtered predicates
// on the input doubles (exact); no point is ever constructed. Notation:
//   ring       a face's index list without consecutive repeats (cyclic)
//   triangle   three vertex indices and the face it covers; collinear triangles are dropped
//   tiling     the triangles of one face cover exactly the face's region, every ring vertex a
//              tile corner: a fan when the ring is strictly convex, else a constrained
//              triangulation of the ring in the face's projection plane with even-odd inside
//              marking (false pairs cancel, so holes stay holes)
// Two triangles of the same face never count as intersecting. For other pairs the tests follow
// CGAL::Polygon_mesh_processing::self_intersections (internal::do_faces_intersect), with shared
// vertices decided by index:
//   3 shared  the same triangle twice: intersecting
//   2 shared  intersecting iff coplanar and both third vertices on the same side of the edge
//   1 shared  intersecting iff the edge opposite the shared vertex in one meets the other triangle
//   0 shared  CGAL::do_intersect (touching counts)

#include <CGAL/Constrained_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "solid/detail/exact_geometry.h"
#include "solid/validate.h"

namespace cover {
namespace {

using K = CGAL::Epick;
using Point2 = K::Point_2;
using Point3 = K::Point_3;

using Vb = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<
    K, CGAL::Triangulation_face_base_with_info_2<int, K>>;  // info: nesting level
using Cdt =
    CGAL::Constrained_triangulation_2<K, CGAL::Triangulation_data_structure_2<Vb, Fb>,
                                      CGAL::No_constraint_intersection_requiring_constructions_tag>;

using Box =
    CGAL::Box_intersection_d::Box_with_info_d<double, 3, uint32_t,
                                              CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;

/// Above this many vertices a ring is tiled by the constrained triangulation (the convexity
/// test is quadratic).
constexpr size_t kMaxFanRing = 32;

Point3 to_point(const Vec3& v) { return {v.x, v.y, v.z}; }

struct Triangle {
  std::array<uint32_t, 3> v;
  uint32_t face;
};

/// Builds the covering triangles of every face.
class Tiler {
 public:
  Tiler(const std::vector<Point3>& points, std::vector<Triangle>& out)
      : points_(points), out_(out) {}

  /// Appends face f's tiling; false when its boundary crosses itself (a self-intersection).
  bool add_face(std::span<const uint32_t> loop, uint32_t f) {
    ring_.clear();
    for (size_t i = 0; i < loop.size(); ++i)
      if (loop[i] != loop[i + 1 < loop.size() ? i + 1 : 0]) ring_.push_back(loop[i]);
    if (ring_.size() < 3) return true;
    if (ring_.size() == 3) {
      add_triangle(ring_[0], ring_[1], ring_[2], f);
      return true;
    }
    axis_ = dominant_axis();
    if (is_convex()) {
      for (size_t i = 1; i + 1 < ring_.size(); ++i)
        add_triangle(ring_[0], ring_[i], ring_[i + 1], f);
      return true;
    }
    return add_constrained(f);
  }

 private:
  void add_triangle(uint32_t a, uint32_t b, uint32_t c, uint32_t f) {
    if (!CGAL::collinear(points_[a], points_[b], points_[c])) out_.push_back({{a, b, c}, f});
  }

  /// Largest component of the ring's Newell normal: the coordinate the projection drops.
  int dominant_axis() const {
    std::array<double, 3> n{};
    const Point3& o = points_[ring_[0]];
    for (size_t i = 1; i + 1 < ring_.size(); ++i) {
      const auto c = CGAL::cross_product(points_[ring_[i]] - o, points_[ring_[i + 1]] - o);
      n[0] += c.x();
      n[1] += c.y();
      n[2] += c.z();
    }
    int axis = 2;
    for (int i = 0; i < 2; ++i)
      if (std::abs(n[i]) > std::abs(n[axis])) axis = i;
    return axis;
  }

  /// Projection that drops axis_ (cyclic order kept, so orientation follows the normal's sign).
  Point2 project(uint32_t v) const {
    const Point3& p = points_[v];
    if (axis_ == 0) return {p.y(), p.z()};
    if (axis_ == 1) return {p.z(), p.x()};
    return {p.x(), p.y()};
  }

  /// True when the projected ring is strictly convex: no index repeats, every vertex lies on one
  /// closed side of every edge's line (the same side for all edges), and no three consecutive
  /// vertices are collinear. Its fan then tiles it with every ring vertex a corner of a tile (a
  /// vertex in the middle of a straight side would vanish from a fan's tiles and then look like a
  /// contact with the neighbouring face).
  bool is_convex() const {
    const size_t n = ring_.size();
    if (n > kMaxFanRing) return false;
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j)
        if (ring_[i] == ring_[j]) return false;
    bool positive = false, negative = false;
    for (size_t i = 0; i < n; ++i) {
      const Point2 a = project(ring_[i]), b = project(ring_[(i + 1) % n]);
      for (size_t k = 0; k < n; ++k) {
        const CGAL::Orientation o = CGAL::orientation(a, b, project(ring_[k]));
        if (o == CGAL::COLLINEAR && k == (i + 2) % n) return false;
        positive |= o == CGAL::POSITIVE;
        negative |= o == CGAL::NEGATIVE;
      }
    }
    return !(positive && negative);
  }

  /// Tiles a non-convex ring (holes joined by false edges included): the ring's edges used an odd
  /// number of times are constraints, and the triangles at odd nesting depth are inside.
  bool add_constrained(uint32_t f) {
    Cdt cdt;
    std::vector<Cdt::Vertex_handle> handles(ring_.size());
    for (size_t i = 0; i < ring_.size(); ++i) {
      const size_t before = cdt.number_of_vertices();
      handles[i] = cdt.insert(project(ring_[i]));
      if (cdt.number_of_vertices() > before) handles[i]->info() = ring_[i];
    }
    keys_.clear();
    for (size_t i = 0; i < ring_.size(); ++i) {
      const uint64_t u = ring_[i], v = ring_[(i + 1) % ring_.size()];
      keys_.push_back(std::min(u, v) << 32 | std::max(u, v));
    }
    std::sort(keys_.begin(), keys_.end());
    try {
      for (size_t i = 0; i < ring_.size(); ++i) {
        const uint64_t u = ring_[i], v = ring_[(i + 1) % ring_.size()];
        const auto range =
            std::equal_range(keys_.begin(), keys_.end(), std::min(u, v) << 32 | std::max(u, v));
        if ((range.second - range.first) % 2 == 1 && handles[i] != handles[(i + 1) % ring_.size()])
          cdt.insert_constraint(handles[i], handles[(i + 1) % ring_.size()]);
      }
    } catch (const Cdt::Intersection_of_constraints_exception&) {
      return false;
    }
    if (cdt.dimension() < 2) return true;
    mark_nesting(cdt);
    for (auto fh : cdt.finite_face_handles())
      if (fh->info() % 2 == 1)
        add_triangle(fh->vertex(0)->info(), fh->vertex(1)->info(), fh->vertex(2)->info(), f);
    return true;
  }

  /// Nesting level of every face: 0 outside, +1 across each constrained edge (breadth first).
  static void mark_nesting(Cdt& cdt) {
    for (auto fh : cdt.all_face_handles()) fh->info() = -1;
    std::vector<Cdt::Face_handle> stack{cdt.infinite_face()}, next_level;
    cdt.infinite_face()->info() = 0;
    for (int level = 0; !stack.empty(); ++level) {
      while (!stack.empty()) {
        Cdt::Face_handle fh = stack.back();
        stack.pop_back();
        for (int i = 0; i < 3; ++i) {
          Cdt::Face_handle nb = fh->neighbor(i);
          if (nb->info() != -1) continue;
          if (cdt.is_constrained({fh, i})) {
            next_level.push_back(nb);
          } else {
            nb->info() = level;
            stack.push_back(nb);
          }
        }
      }
      for (Cdt::Face_handle fh : next_level)
        if (fh->info() == -1) {
          fh->info() = level + 1;
          stack.push_back(fh);
        }
      next_level.clear();
    }
  }

  const std::vector<Point3>& points_;
  std::vector<Triangle>& out_;
  std::vector<uint32_t> ring_;
  std::vector<uint64_t> keys_;
  int axis_ = 2;
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

namespace detail {

bool all_collinear(std::span<const Vec3> vertices, std::span<const uint32_t> loop) {
  if (loop.empty()) return true;
  const Vec3& a = vertices[loop[0]];
  size_t i = 1;
  while (i < loop.size() && vertices[loop[i]] == a) ++i;
  if (i == loop.size()) return true;
  const Point3 pa = to_point(a), pb = to_point(vertices[loop[i]]);
  for (++i; i < loop.size(); ++i)
    if (!CGAL::collinear(pa, pb, to_point(vertices[loop[i]]))) return false;
  return true;
}

}  // namespace detail

bool self_intersects(const PolygonMesh& mesh) {
  std::vector<Point3> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.push_back(to_point(v));

  std::vector<Triangle> triangles;
  triangles.reserve(mesh.face_vertices.size());
  Tiler tiler(points, triangles);
  for (size_t f = 0; f < mesh.face_count(); ++f)
    if (!tiler.add_face(mesh.face(f), static_cast<uint32_t>(f))) return true;

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
