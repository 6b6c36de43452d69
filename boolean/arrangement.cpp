// Steps 1–3 of evaluate() (boolean/evaluate.h): leaf triangulation, exact pairwise triangle
// intersections, per-triangle constrained triangulations and global point identity. The
// exactness scheme is described in boolean/detail/arrangement.h.
//
// Notation
//   t, u        tris of different leaves whose closed double boxes meet (candidate pair)
//   hit         the exact intersection t ∩ u: nothing, a point, a segment, or (coplanar) the
//               overlap polygon, whose boundary segments become constraints of both t and u
//   local ids   per tri: 0..2 are its corners, then constraint endpoints and points created by
//               the triangulation (constraint crossings), in insertion order
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include "boolean/detail/arrangement.h"
#include "solid/parallel.h"

namespace cover::boolean_detail {
namespace {

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;

// ---- step 1: leaf faces → triangles ---------------------------------------------------------

/// Point ids of the input vertices, deduplicated by exact value (±0 equal).
std::vector<uint32_t> dedup_vertices(const Solid& solid, std::vector<Vec3>& originals) {
  struct Hash {
    size_t operator()(const Vec3& p) const {
      auto h = [](double d) { return std::hash<double>{}(d == 0 ? 0.0 : d); };
      return h(p.x) * 0x9e3779b97f4a7c15ull ^ (h(p.y) + 0x632be59bd9b4e019ull) * 31 ^ h(p.z);
    }
  };
  std::unordered_map<Vec3, uint32_t, Hash> index;
  std::vector<uint32_t> id(solid.vertices.size());
  for (size_t i = 0; i < solid.vertices.size(); ++i) {
    auto [it, fresh] = index.try_emplace(solid.vertices[i], static_cast<uint32_t>(originals.size()));
    if (fresh) originals.push_back(solid.vertices[i]);
    id[i] = it->second;
  }
  return id;
}

int dominant_axis(const Vec3& n) {
  const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
  return ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
}

Epick::Point_2 project(const Vec3& p, int k) {
  return {p[(k + 1) % 3], p[(k + 2) % 3]};
}

/// Triangles of one face (point ids, leaf orientation). Strictly convex loops (in the dominant
/// projection of the Newell normal) are fanned from the first vertex — the same triangles as the
/// covering; anything else (reflex or collinear corners, false edges) goes through a constrained
/// triangulation of the loop edges, keeping the regions crossed an odd number of times.
void triangulate_face(std::span<const uint32_t> loop, const std::vector<Vec3>& pos,
                      std::vector<std::array<uint32_t, 3>>& out) {
  const size_t n = loop.size();
  if (n < 3) return;
  if (n == 3) {
    out.push_back({loop[0], loop[1], loop[2]});
    return;
  }
  Vec3 normal{};
  for (size_t i = 0; i < n; ++i) {
    const Vec3& a = pos[loop[i]];
    const Vec3& b = pos[loop[(i + 1) % n]];
    normal = normal + Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x),
                           (a.x - b.x) * (a.y + b.y)};
  }
  const int k = dominant_axis(normal);
  bool convex = true;
  CGAL::Orientation first = CGAL::COLLINEAR;
  for (size_t i = 0; i < n && convex; ++i) {
    if (loop[i] == loop[(i + 1) % n]) convex = false;
    const auto o = CGAL::orientation(project(pos[loop[i]], k), project(pos[loop[(i + 1) % n]], k),
                                     project(pos[loop[(i + 2) % n]], k));
    if (o == CGAL::COLLINEAR || (first != CGAL::COLLINEAR && o != first)) convex = false;
    first = o;
  }
  std::vector<uint32_t> sorted(loop.begin(), loop.end());
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) convex = false;
  if (convex) {
    for (size_t i = 1; i + 1 < n; ++i) out.push_back({loop[0], loop[i], loop[i + 1]});
    return;
  }
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, Epick>;
  using Fb = CGAL::Constrained_triangulation_face_base_2<Epick>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Epick, Tds, CGAL::Exact_predicates_tag>;
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> vh(n);
  for (size_t i = 0; i < n; ++i) {
    vh[i] = cdt.insert(project(pos[loop[i]], k));
    vh[i]->info() = loop[i];
  }
  // Times the loop runs along each undirected edge: a false edge (twice) separates nothing.
  std::map<std::pair<Cdt::Vertex_handle, Cdt::Vertex_handle>, int> count;
  for (size_t i = 0; i < n; ++i) {
    Cdt::Vertex_handle a = vh[i], b = vh[(i + 1) % n];
    if (a == b) continue;
    cdt.insert_constraint(a, b);
    ++count[std::minmax(a, b)];
  }
  std::map<Cdt::Face_handle, int> inside;
  std::vector<Cdt::Face_handle> stack;
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
    if (cdt.is_infinite(f)) {
      inside[f] = 0;
      stack.push_back(f);
    }
  while (!stack.empty()) {
    Cdt::Face_handle f = stack.back();
    stack.pop_back();
    for (int i = 0; i < 3; ++i) {
      Cdt::Face_handle g = f->neighbor(i);
      if (inside.count(g)) continue;
      auto it = count.find(std::minmax(f->vertex(Cdt::cw(i)), f->vertex(Cdt::ccw(i))));
      inside[g] = inside[f] ^ (it != count.end() ? it->second & 1 : 0);
      stack.push_back(g);
    }
  }
  const bool flip = normal[k] < 0;  // CDT faces are counter-clockwise in the projection
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!inside[f]) continue;
    const uint32_t a = f->vertex(0)->info(), b = f->vertex(1)->info(), c = f->vertex(2)->info();
    out.push_back(flip ? std::array<uint32_t, 3>{a, c, b} : std::array<uint32_t, 3>{a, b, c});
  }
}

std::vector<Tri> leaf_tris(const Solid& solid, const std::vector<uint32_t>& id,
                           const std::vector<Vec3>& pos, size_t grain) {
  const size_t faces = solid.face_count();
  std::vector<std::vector<std::array<uint32_t, 3>>> per_face(faces);
  parallel_for(faces, grain * 16, [&](size_t begin, size_t end) {
    std::vector<uint32_t> loop;
    for (size_t f = begin; f < end; ++f) {
      auto face = solid.face(f);
      loop.assign(face.begin(), face.end());
      if (solid.face_sign[f] < 0) std::reverse(loop.begin(), loop.end());
      for (uint32_t& v : loop) v = id[v];
      triangulate_face(loop, pos, per_face[f]);
    }
  });
  std::vector<Tri> tris;
  // Faces are contiguous per leaf; keep leaf order so tris are grouped by leaf.
  for (uint32_t l = 0; l < solid.leaves.size(); ++l) {
    const Leaf& leaf = solid.leaves[l];
    for (uint32_t f = leaf.first_face; f < leaf.first_face + leaf.face_count; ++f)
      for (const auto& t : per_face[f]) {
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        auto p = [&](int i) { return Epick::Point_3(pos[t[i]].x, pos[t[i]].y, pos[t[i]].z); };
        if (CGAL::collinear(p(0), p(1), p(2))) continue;
        tris.push_back({t, solid.face_leaf[f]});
      }
  }
  return tris;
}

// ---- step 2: candidate pairs and exact intersections ----------------------------------------

std::vector<std::pair<uint32_t, uint32_t>> candidate_pairs(const std::vector<Tri>& tris,
                                                           const std::vector<Vec3>& pos) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, uint32_t,
                                                        CGAL::Box_intersection_d::ID_EXPLICIT>;
  std::vector<Box> boxes;
  boxes.reserve(tris.size());
  for (uint32_t i = 0; i < tris.size(); ++i) {
    CGAL::Bbox_3 b;
    for (uint32_t v : tris[i].v) b += CGAL::Bbox_3(pos[v].x, pos[v].y, pos[v].z, pos[v].x, pos[v].y, pos[v].z);
    boxes.emplace_back(b, i);
  }
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  // Closed boxes with exact double bounds: touching triangles are candidates too.
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    const uint32_t i = a.info(), j = b.info();
    if (tris[i].leaf != tris[j].leaf) pairs.emplace_back(std::min(i, j), std::max(i, j));
  });
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

/// The exact intersection of two tris as constraint segments and isolated points.
struct Hit {
  std::vector<K::Segment_3> segments;
  std::vector<Point> points;
  bool empty() const { return segments.empty() && points.empty(); }
};

Hit intersect(const Tri& a, const Tri& b, const std::vector<Point>& pts,
              const std::vector<Vec3>& pos) {
  Hit hit;
  auto epick = [&](uint32_t v) { return Epick::Point_3(pos[v].x, pos[v].y, pos[v].z); };
  if (!CGAL::do_intersect(Epick::Triangle_3(epick(a.v[0]), epick(a.v[1]), epick(a.v[2])),
                          Epick::Triangle_3(epick(b.v[0]), epick(b.v[1]), epick(b.v[2]))))
    return hit;
  const K::Triangle_3 ta(pts[a.v[0]], pts[a.v[1]], pts[a.v[2]]);
  const K::Triangle_3 tb(pts[b.v[0]], pts[b.v[1]], pts[b.v[2]]);
  const auto result = CGAL::intersection(ta, tb);
  if (!result) return hit;
  auto polygon = [&](const std::vector<Point>& loop) {
    for (size_t i = 0; i < loop.size(); ++i)
      hit.segments.emplace_back(loop[i], loop[(i + 1) % loop.size()]);
  };
  if (const Point* p = boost::get<Point>(&*result)) {
    hit.points.push_back(*p);
  } else if (const K::Segment_3* s = boost::get<K::Segment_3>(&*result)) {
    hit.segments.push_back(*s);
  } else if (const K::Triangle_3* t = boost::get<K::Triangle_3>(&*result)) {
    polygon({t->vertex(0), t->vertex(1), t->vertex(2)});
  } else if (const auto* loop = boost::get<std::vector<Point>>(&*result)) {
    polygon(*loop);
  }
  return hit;
}

// ---- step 3: per-tri constrained triangulation ----------------------------------------------

struct VInfo {
  uint32_t id = kNone;  ///< local point id
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_intersections_tag>;
using CdtPlus = CGAL::Constrained_triangulation_plus_2<Cdt>;

struct Local {
  std::vector<Point> points;    ///< local points (0..2: the tri's corners)
  std::vector<std::array<uint32_t, 3>> tris;           ///< local ids, the tri's orientation
  std::vector<std::pair<uint32_t, uint32_t>> cuts;     ///< local id pairs on intersections
};

Local split_tri(const Tri& tri, const std::vector<const Hit*>& hits,
                const std::vector<Point>& pts, const std::vector<Vec3>& pos) {
  Local local;
  const Point& a = pts[tri.v[0]];
  const Point& b = pts[tri.v[1]];
  const Point& c = pts[tri.v[2]];
  const Vec3 nd = cross(pos[tri.v[1]] - pos[tri.v[0]], pos[tri.v[2]] - pos[tri.v[0]]);
  const int k = dominant_axis(nd), i = (k + 1) % 3, j = (k + 2) % 3;
  const K::Vector_3 n = CGAL::cross_product(b - a, c - a);
  auto to2 = [&](const Point& p) { return K::Point_2(p[i], p[j]); };
  CdtPlus cdt;
  auto add = [&](const Point& p) {
    CdtPlus::Vertex_handle v = cdt.insert(to2(p));
    if (v->info().id == kNone) {
      v->info().id = static_cast<uint32_t>(local.points.size());
      local.points.push_back(p);
    }
    return v;
  };
  const CdtPlus::Vertex_handle va = add(a), vb = add(b), vc = add(c);
  cdt.insert_constraint(va, vb);
  cdt.insert_constraint(vb, vc);
  cdt.insert_constraint(vc, va);
  std::vector<CdtPlus::Constraint_id> cuts;
  for (const Hit* hit : hits) {
    for (const K::Segment_3& s : hit->segments) {
      const CdtPlus::Vertex_handle p = add(s.source()), q = add(s.target());
      if (p != q) cuts.push_back(cdt.insert_constraint(p, q));
    }
    for (const Point& p : hit->points) add(p);
  }
  // Points created at constraint crossings: lift onto the tri's plane exactly.
  const K::FT d = n.x() * a.x() + n.y() * a.y() + n.z() * a.z();
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    if (v->info().id != kNone) continue;
    v->info().id = static_cast<uint32_t>(local.points.size());
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
    local.tris.push_back(flip ? std::array<uint32_t, 3>{x, z, y}
                              : std::array<uint32_t, 3>{x, y, z});
  }
  for (const auto& cid : cuts) {
    uint32_t prev = kNone;
    for (auto it = cdt.vertices_in_constraint_begin(cid); it != cdt.vertices_in_constraint_end(cid);
         ++it) {
      const uint32_t id = (*it)->info().id;
      if (prev != kNone) local.cuts.emplace_back(prev, id);
      prev = id;
    }
  }
  return local;
}

struct LessXyz {
  bool operator()(const Point& p, const Point& q) const {
    return CGAL::compare_xyz(p, q) == CGAL::SMALLER;
  }
};

}  // namespace

Arrangement build_arrangement(const Solid& solid, size_t grain) {
  Arrangement arr;
  const std::vector<uint32_t> id = dedup_vertices(solid, arr.originals);
  arr.points.reserve(arr.originals.size());
  for (const Vec3& p : arr.originals) arr.points.emplace_back(p.x, p.y, p.z);
  arr.tris = leaf_tris(solid, id, arr.originals, grain);
  const std::vector<Tri>& tris = arr.tris;

  const auto pairs = candidate_pairs(tris, arr.originals);
  arr.candidate_pairs = pairs.size();
  std::vector<Hit> hits(pairs.size());
  parallel_for(pairs.size(), grain, [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p)
      hits[p] = intersect(tris[pairs[p].first], tris[pairs[p].second], arr.points, arr.originals);
  });

  // Hits per tri (CSR, pair order).
  std::vector<uint32_t> start(tris.size() + 1, 0);
  for (size_t p = 0; p < pairs.size(); ++p)
    if (!hits[p].empty()) {
      ++arr.intersecting_pairs;
      ++start[pairs[p].first + 1];
      ++start[pairs[p].second + 1];
    }
  for (size_t t = 0; t < tris.size(); ++t) start[t + 1] += start[t];
  std::vector<const Hit*> by_tri(start.back());
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t p = 0; p < pairs.size(); ++p)
      if (!hits[p].empty()) {
        by_tri[fill[pairs[p].first]++] = &hits[p];
        by_tri[fill[pairs[p].second]++] = &hits[p];
      }
  }
  std::vector<uint32_t> touched;
  for (uint32_t t = 0; t < tris.size(); ++t)
    if (start[t + 1] > start[t]) touched.push_back(t);

  std::vector<Local> locals(touched.size());
  parallel_for(touched.size(), std::max<size_t>(1, grain / 8), [&](size_t begin, size_t end) {
    for (size_t x = begin; x < end; ++x) {
      const uint32_t t = touched[x];
      std::vector<const Hit*> h(by_tri.begin() + start[t], by_tri.begin() + start[t + 1]);
      locals[x] = split_tri(tris[t], h, arr.points, arr.originals);
    }
  });

  // Global identity of points by exact value (serial, deterministic: touched-tri order).
  std::map<Point, uint32_t, LessXyz> index;
  for (uint32_t t : touched)
    for (uint32_t v : tris[t].v) index.emplace(arr.points[v], v);
  for (size_t p = 0; p < pairs.size(); ++p)
    if (!hits[p].empty())
      for (uint32_t t : {pairs[p].first, pairs[p].second})
        for (uint32_t v : tris[t].v) index.emplace(arr.points[v], v);

  size_t next_touched = 0;
  std::vector<uint32_t> map;
  for (uint32_t t = 0; t < tris.size(); ++t) {
    if (next_touched < touched.size() && touched[next_touched] == t) {
      Local& local = locals[next_touched++];
      map.resize(local.points.size());
      for (size_t q = 0; q < local.points.size(); ++q) {
        if (q < 3) {
          map[q] = tris[t].v[q];
          continue;
        }
        auto [it, fresh] =
            index.emplace(local.points[q], static_cast<uint32_t>(arr.points.size()));
        if (fresh) arr.points.push_back(local.points[q]);
        map[q] = it->second;
      }
      for (const auto& lt : local.tris) arr.pieces.push_back({{map[lt[0]], map[lt[1]], map[lt[2]]}, t});
      for (const auto& [x, y] : local.cuts) arr.cuts.push_back(edge_key(map[x], map[y]));
      local = Local{};
    } else {
      arr.pieces.push_back({tris[t].v, t});
    }
  }
  std::sort(arr.cuts.begin(), arr.cuts.end());
  arr.cuts.erase(std::unique(arr.cuts.begin(), arr.cuts.end()), arr.cuts.end());
  return arr;
}

}  // namespace cover::boolean_detail
