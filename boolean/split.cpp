// Step 3 of evaluate() (boolean/evaluate.h): each intersected tri is re-triangulated with its
// hits as constraints. The exactness scheme is described in boolean/detail/arrangement.h, the
// notation in boolean/detail/arrangement_steps.h.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <unordered_map>

#include "boolean/detail/arrangement_steps.h"
#include "solid/triangulate.h"

namespace cover::boolean_detail {
namespace {

struct VInfo {
  uint32_t id = kNone;  ///< local point id
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_intersections_tag>;

/// The common cases without a triangulation: every transversal hit is the same segment (or a
/// point at a corner) whose ends lie on the tri's boundary (see the cases below). Returns false
/// when the tri needs the constrained triangulation. On bench/evaluate_vs_cgal about half of the
/// cut tris (armadillo ∩ knot1: 1262 of 2147; cheese ∪ fandisk: 1092 of 2469), each saving a CDT
/// (tens of µs with its lazy 2D points).
bool split_simple(const Tri& tri, const std::vector<TriHit>& hits, Local& local) {
  uint32_t p = kNone, q = kNone;
  uint8_t wp = kUnknown, wq = kUnknown;
  for (const TriHit& h : hits) {
    if (h.hit->ends[0].id == kNone) return false;  // coplanar
    if (h.id(0) == h.id(1)) {
      if (h.on(0) >= kEdge) return false;  // isolated point off the corners
      continue;
    }
    if (p == kNone) {
      p = h.id(0), q = h.id(1), wp = h.on(0), wq = h.on(1);
    } else if (!((h.id(0) == p && h.id(1) == q) || (h.id(0) == q && h.id(1) == p))) {
      return false;
    }
  }
  local.ids.assign(tri.v.begin(), tri.v.end());
  const std::array<uint32_t, 3> c{0, 1, 2};
  if (p == kNone) {  // only corner points
    local.tris.push_back(c);
    return true;
  }
  if (wp >= kInside || wq >= kInside) return false;
  // Segment p–q with both ends on the boundary; make p the one with the lower position code.
  if (wq < wp) std::swap(p, q), std::swap(wp, wq);
  if (wq < kEdge) {  // corner–corner: an edge of the tri
    local.tris.push_back(c);
    local.cuts.emplace_back(wp, wq);
    return true;
  }
  local.ids.push_back(q);
  const uint32_t lq = 3;
  if (wp < kEdge) {  // corner k – point on an edge
    const uint32_t k = wp, e = wq - kEdge;
    if (e != (k + 1) % 3) return false;  // along an edge next to k: rare
    local.tris.push_back({k, (k + 1) % 3, lq});
    local.tris.push_back({k, lq, (k + 2) % 3});
    local.cuts.emplace_back(k, lq);
    return true;
  }
  const uint32_t ep = wp - kEdge, eq = wq - kEdge;
  if (ep == eq) return false;  // both on one edge: rare
  local.ids.push_back(p);
  const uint32_t lp = 4;
  // p on edge i, q on edge i + 1 (cutting off corner i + 1), after naming.
  uint32_t i = ep, a = lp, b = lq;
  if (eq != (ep + 1) % 3) i = eq, a = lq, b = lp;
  local.tris.push_back({a, (i + 1) % 3, b});
  local.tris.push_back({i, a, b});
  local.tris.push_back({i, b, (i + 2) % 3});
  local.cuts.emplace_back(a, b);
  return true;
}

}  // namespace

Local split_tri(const Tri& tri, const std::vector<TriHit>& hits, const std::vector<Point>& pts,
                const std::vector<Vec3>& pos) {
  Local local;
  if (split_simple(tri, hits, local)) return local;
  local = Local{};
  const Point& a = pts[tri.v[0]];
  const Point& b = pts[tri.v[1]];
  const Point& c = pts[tri.v[2]];
  const Vec3 nd = cross(pos[tri.v[1]] - pos[tri.v[0]], pos[tri.v[2]] - pos[tri.v[0]]);
  const int k = dominant_axis(nd), i = (k + 1) % 3, j = (k + 2) % 3;
  const K::Vector_3 n = CGAL::cross_product(b - a, c - a);
  auto to2 = [&](const Point& p) { return K::Point_2(p[i], p[j]); };
  Cdt cdt;
  std::unordered_map<uint32_t, Cdt::Vertex_handle> by_id;  // points inserted by id
  auto add_value = [&](const Point& p, uint32_t id) {
    Cdt::Vertex_handle v = cdt.insert(to2(p));
    if (v->info().id == kNone) {
      v->info().id = static_cast<uint32_t>(local.ids.size());
      local.ids.push_back(id);
      if (id == kNone) local.points.push_back(p);
    }
    return v;
  };
  auto add = [&](uint32_t id) {
    auto [it, fresh] = by_id.try_emplace(id);
    if (fresh) it->second = add_value(pts[id], id);
    return it->second;
  };
  // The tri's corners first; its edges need no constraints: every point lies in the closed tri,
  // so its edges are the hull's and never flipped. Every constrained edge is then a cut edge
  // (a plain CDT: the constraint hierarchy of Constrained_triangulation_plus_2 cost about a
  // fifth of this step's CPU time, for the same pieces).
  add(tri.v[0]);
  add(tri.v[1]);
  add(tri.v[2]);
  for (const TriHit& h : hits) {
    if (h.hit->ends[0].id != kNone) {
      const Cdt::Vertex_handle p = add(h.id(0)), q = add(h.id(1));
      if (p != q) cdt.insert_constraint(p, q);
      continue;
    }
    for (const K::Segment_3& s : h.hit->segments) {
      const Cdt::Vertex_handle p = add_value(s.source(), kNone),
                               q = add_value(s.target(), kNone);
      if (p != q) cdt.insert_constraint(p, q);
    }
    for (const Point& p : h.hit->points) add_value(p, kNone);
  }
  // Points created at constraint crossings: lift onto the tri's plane exactly. They are numbered
  // in exact (x, y) order of their projections, not in the triangulation's storage order: that
  // order (like the faces' below) depends on which of two faces a point location on an edge
  // returned, which CGAL's randomized walk makes depend on the thread's history.
  const K::FT d = n.x() * a.x() + n.y() * a.y() + n.z() * a.z();
  std::vector<Cdt::Vertex_handle> crossings;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    if (v->info().id == kNone) crossings.push_back(v);
  std::sort(crossings.begin(), crossings.end(), [](const auto& x, const auto& y) {
    return CGAL::compare_xy(x->point(), y->point()) == CGAL::SMALLER;
  });
  for (const Cdt::Vertex_handle& v : crossings) {
    v->info().id = static_cast<uint32_t>(local.ids.size());
    local.ids.push_back(kNone);
    const K::FT xi = v->point().x(), xj = v->point().y();
    const K::FT xk = (d - n[i] * xi - n[j] * xj) / n[k];
    K::FT xyz[3];
    xyz[i] = xi;
    xyz[j] = xj;
    xyz[k] = xk;
    local.points.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  const bool flip = nd[k] < 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    const uint32_t x = f->vertex(0)->info().id, y = f->vertex(1)->info().id,
                   z = f->vertex(2)->info().id;
    std::array<uint32_t, 3> t = flip ? std::array<uint32_t, 3>{x, z, y} : std::array<uint32_t, 3>{x, y, z};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());  // orientation kept
    local.tris.push_back(t);
  }
  std::sort(local.tris.begin(), local.tris.end());  // canonical: independent of storage order
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e)
    if (cdt.is_constrained(*e))
      local.cuts.emplace_back(e->first->vertex(Cdt::cw(e->second))->info().id,
                              e->first->vertex(Cdt::ccw(e->second))->info().id);
  return local;
}

}  // namespace cover::boolean_detail
