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
#include <chrono>
#include <cmath>
#include <compare>
#include <map>
#include <numeric>
#include <unordered_map>

#include "boolean/detail/arrangement.h"
#include "covering/predicates.h"
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

/// Tri pairs of different leaves whose closed double boxes meet, sorted. Per leaf l, its tris
/// against those of the later leaves (bipartite), each side first reduced to the boxes meeting the
/// other side's bounding box: a self-intersection over all tris spent most of its time on the
/// many same-leaf neighbours (bunny00 − elephant: 0.33–0.48 s → 0.02 s). Leaf l's boxes are cut
/// into slabs along x, each slab against the other boxes meeting it, in parallel (the sorted
/// result does not depend on the slabs or threads).
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
  auto bounds = [](const std::vector<Box>& range, size_t begin, size_t end) {
    CGAL::Bbox_3 b;
    for (size_t i = begin; i < end; ++i) b += range[i].bbox();
    return b;
  };
  constexpr size_t kSlab = 2048;  // boxes of leaf l per slab
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  // Tris are grouped by leaf, leaves in increasing order.
  for (size_t begin = 0; begin < tris.size();) {
    size_t end = begin;
    while (end < tris.size() && tris[end].leaf == tris[begin].leaf) ++end;
    if (end == tris.size()) break;
    const CGAL::Bbox_3 mine = bounds(boxes, begin, end), rest = bounds(boxes, end, tris.size());
    std::vector<Box> a, b;
    for (size_t i = begin; i < end; ++i)
      if (CGAL::do_overlap(boxes[i].bbox(), rest)) a.push_back(boxes[i]);
    for (size_t i = end; i < tris.size(); ++i)
      if (CGAL::do_overlap(boxes[i].bbox(), mine)) b.push_back(boxes[i]);
    std::sort(a.begin(), a.end(), [](const Box& x, const Box& y) {
      const double cx = x.min_coord(0) + x.max_coord(0), cy = y.min_coord(0) + y.max_coord(0);
      return cx < cy || (cx == cy && x.info() < y.info());
    });
    const size_t slabs = (a.size() + kSlab - 1) / kSlab;
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> found(slabs);
    parallel_for(slabs, 1, [&](size_t s0, size_t s1) {
      for (size_t s = s0; s < s1; ++s) {
        const size_t lo = s * kSlab, hi = std::min(a.size(), lo + kSlab);
        std::vector<Box> mine_s(a.begin() + lo, a.begin() + hi), other;
        const CGAL::Bbox_3 slab = bounds(a, lo, hi);
        for (const Box& x : b)
          if (CGAL::do_overlap(x.bbox(), slab)) other.push_back(x);
        // Closed boxes with exact double bounds: touching triangles are candidates too.
        CGAL::box_intersection_d(mine_s.begin(), mine_s.end(), other.begin(), other.end(),
                                 [&](const Box& x, const Box& y) {
                                   found[s].emplace_back(std::min(x.info(), y.info()),
                                                         std::max(x.info(), y.info()));
                                 });
      }
    });
    for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
    begin = end;
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

// Transversal pairs (the planes of t and u cross) never go through CGAL's generic
// intersection(Triangle_3, Triangle_3): its lazy result is a variant whose exact fallback redoes
// the whole triangle–triangle intersection in rationals each time a later predicate (CDT
// equality of the same point reached from two pairs) is uncertain — 80 % of evaluate's time on
// armadillo ∩ knot1 before this scheme. Instead:
//   * the configuration is decided by exact orient3d on the input doubles (covering/predicates.h);
//   * t ∩ plane(u) is an interval of the line plane(t) ∩ plane(u) whose ends are symbolic: a
//     corner of t lying in plane(u), or the crossing of an edge of t with plane(u) — the latter
//     constructed ONCE per (edge, tri) key (crossings()), so every pair that needs it shares one
//     lazy object and its id (the crossing of edge a–b with plane(u) is reached from both tris
//     of the edge);
//   * the hit is the overlap of t's and u's intervals, ordered by exact compare_xyz (a strictly
//     monotone order along any line).
// Coplanar pairs (rare except in axis-aligned scenes) keep CGAL's intersection.

/// Where a point of tri t lies on t: kCorner + i (corner i), kEdge + i (on the open edge from
/// corner i to corner i + 1), kInside (the open triangle), kUnknown (not established).
enum : uint8_t { kCorner = 0, kEdge = 3, kInside = 6, kUnknown = 7 };

/// One end of t ∩ plane(u) for non-coplanar t, u: a corner of t (id = point id, a == b) or the
/// crossing of t's edge a–b (a < b, point ids) with plane(u).
struct Sym {
  uint32_t a = kNone, b = kNone;
  uint8_t where = kUnknown;  ///< on t
};

struct PlaneCut {
  std::array<Sym, 2> end;
  int n = 0;           ///< 0: t misses the plane; 1: t touches it at a corner; 2: an interval
  bool along = false;  ///< both ends are corners: t ∩ plane(u) is t's edge kEdge + edge
  uint8_t edge = 0;
};

/// t ∩ plane(u) from the exact sides s[i] of t's corners (not all 0).
PlaneCut plane_cut(const Tri& t, const int s[3]) {
  PlaneCut c;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (s[i] == 0) c.end[c.n++] = {t.v[i], t.v[i], static_cast<uint8_t>(kCorner + i)};
    if (s[i] * s[j] < 0)
      c.end[c.n++] = {std::min(t.v[i], t.v[j]), std::max(t.v[i], t.v[j]),
                      static_cast<uint8_t>(kEdge + i)};
  }
  for (int i = 0; i < 3; ++i)
    if (s[i] == 0 && s[(i + 1) % 3] == 0) {
      c.along = true;
      c.edge = static_cast<uint8_t>(kEdge + i);
    }
  return c;
}

/// Phase A of a candidate pair: apart, transversal (the two plane cuts) or coplanar.
struct PairCut {
  enum Kind : uint8_t { kApart, kTransversal, kCoplanar } kind = kApart;
  PlaneCut t, u;
};

PairCut cut_pair(const Tri& t, const Tri& u, const std::vector<Vec3>& pos) {
  PairCut r;
  int st[3], su[3];
  for (int i = 0; i < 3; ++i) st[i] = orient3d(pos[u.v[0]], pos[u.v[1]], pos[u.v[2]], pos[t.v[i]]);
  if (st[0] == st[1] && st[1] == st[2]) {
    if (st[0] == 0) r.kind = PairCut::kCoplanar;
    return r;
  }
  for (int i = 0; i < 3; ++i) su[i] = orient3d(pos[t.v[0]], pos[t.v[1]], pos[t.v[2]], pos[u.v[i]]);
  if (su[0] == su[1] && su[1] == su[2]) return r;  // (all 0 is impossible: t is not in plane(u))
  r.kind = PairCut::kTransversal;
  r.t = plane_cut(t, st);
  r.u = plane_cut(u, su);
  return r;
}

/// A crossing: edge `edge` (edge_key) with the plane of tri `tri`.
struct CrossKey {
  uint64_t edge;
  uint32_t tri;
  auto operator<=>(const CrossKey&) const = default;
};

/// The exact point of line a–b in the plane of w (the line crosses it): a + (b − a)·dₐ/(dₐ − d_b),
/// d_x = n·(x − w₀), n = (w₁ − w₀)×(w₂ − w₀).
Point crossing(const Point& a, const Point& b, const Tri& w, const std::vector<Point>& pts) {
  const Point& p = pts[w.v[0]];
  const K::Vector_3 n = CGAL::cross_product(pts[w.v[1]] - p, pts[w.v[2]] - p);
  const K::FT da = n * (a - p), db = n * (b - p);
  return a + (b - a) * (da / (da - db));
}

/// One end of a hit: a point id and where it lies on each of the two tris.
struct End {
  uint32_t id = kNone;
  uint8_t on_t = kUnknown, on_u = kUnknown;
};

/// The exact intersection of two tris: a point or a segment of ids (transversal), or constraint
/// segments and isolated points by value (coplanar, CGAL).
struct Hit {
  std::array<End, 2> ends;  ///< transversal: ends[0].id != kNone; a point when ids are equal
  std::vector<K::Segment_3> segments;
  std::vector<Point> points;
  bool empty() const { return ends[0].id == kNone && segments.empty() && points.empty(); }
};

/// Transversal hit from the two plane cuts; `id` maps a Sym of t (other = u) or of u to its id.
template <class Id>
Hit transversal_hit(const PairCut& c, const std::vector<Point>& pts, const Id& id) {
  Hit hit;
  struct E {
    uint32_t id;
    uint8_t on_t, on_u;
  };
  auto interior = [](const PlaneCut& pc) { return pc.along ? pc.edge : uint8_t{kInside}; };
  auto less = [&](uint32_t x, uint32_t y) {
    return x != y && CGAL::compare_xyz(pts[x], pts[y]) == CGAL::SMALLER;
  };
  // Ends of each interval with their positions, sorted along the line.
  E p[2], q[2];
  for (int i = 0; i < 2; ++i) {
    const Sym& s = c.t.end[std::min(i, c.t.n - 1)];
    p[i] = {id(s, true), s.where, interior(c.u)};
    const Sym& r = c.u.end[std::min(i, c.u.n - 1)];
    q[i] = {id(r, false), interior(c.t), r.where};
  }
  if (less(p[1].id, p[0].id)) std::swap(p[0], p[1]);
  if (less(q[1].id, q[0].id)) std::swap(q[0], q[1]);
  // The overlap [max(p0, q0), min(p1, q1)]; at equal values the end is on both boundaries.
  auto pick = [&](const E& x, const E& y, bool want_max) {
    if (x.id == y.id) return E{x.id, x.on_t, y.on_u};
    const CGAL::Comparison_result cmp = CGAL::compare_xyz(pts[x.id], pts[y.id]);
    if (cmp == CGAL::EQUAL) return E{std::min(x.id, y.id), x.on_t, y.on_u};
    return (cmp == CGAL::LARGER) == want_max ? x : y;
  };
  E lo = pick(p[0], q[0], true), hi = pick(p[1], q[1], false);
  if (lo.id != hi.id) {
    const CGAL::Comparison_result cmp = CGAL::compare_xyz(pts[lo.id], pts[hi.id]);
    if (cmp == CGAL::LARGER) return hit;
    if (cmp == CGAL::EQUAL) {  // one point: the most specific positions (corner < edge < inside)
      lo = {std::min(lo.id, hi.id), std::min(lo.on_t, hi.on_t), std::min(lo.on_u, hi.on_u)};
      hi = lo;
    }
  }
  hit.ends[0] = {lo.id, lo.on_t, lo.on_u};
  hit.ends[1] = {hi.id, hi.on_t, hi.on_u};
  return hit;
}

Hit coplanar_hit(const Tri& a, const Tri& b, const std::vector<Point>& pts) {
  Hit hit;
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

// ---- step 3: per-tri re-triangulation -------------------------------------------------------

struct VInfo {
  uint32_t id = kNone;  ///< local point id
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_intersections_tag>;
using CdtPlus = CGAL::Constrained_triangulation_plus_2<Cdt>;

struct Local {
  std::vector<uint32_t> ids;    ///< per local point: its point id, kNone when only its value is known
  std::vector<Point> points;    ///< values of the local points with ids[q] == kNone (in order)
  std::vector<std::array<uint32_t, 3>> tris;        ///< local ids, the tri's orientation
  std::vector<std::pair<uint32_t, uint32_t>> cuts;  ///< local id pairs on intersections
};

/// One hit as seen from its tri: the ends' ids and positions on this tri.
struct TriHit {
  const Hit* hit;
  bool first;  ///< this tri is the pair's t
  uint32_t id(int e) const { return hit->ends[e].id; }
  uint8_t on(int e) const { return first ? hit->ends[e].on_t : hit->ends[e].on_u; }
};

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
  CdtPlus cdt;
  std::unordered_map<uint32_t, CdtPlus::Vertex_handle> by_id;  // points inserted by id
  auto add_value = [&](const Point& p, uint32_t id) {
    CdtPlus::Vertex_handle v = cdt.insert(to2(p));
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
  const CdtPlus::Vertex_handle va = add(tri.v[0]), vb = add(tri.v[1]), vc = add(tri.v[2]);
  cdt.insert_constraint(va, vb);
  cdt.insert_constraint(vb, vc);
  cdt.insert_constraint(vc, va);
  std::vector<CdtPlus::Constraint_id> cuts;
  for (const TriHit& h : hits) {
    if (h.hit->ends[0].id != kNone) {
      const CdtPlus::Vertex_handle p = add(h.id(0)), q = add(h.id(1));
      if (p != q) cuts.push_back(cdt.insert_constraint(p, q));
      continue;
    }
    for (const K::Segment_3& s : h.hit->segments) {
      const CdtPlus::Vertex_handle p = add_value(s.source(), kNone),
                                   q = add_value(s.target(), kNone);
      if (p != q) cuts.push_back(cdt.insert_constraint(p, q));
    }
    for (const Point& p : h.hit->points) add_value(p, kNone);
  }
  // Points created at constraint crossings: lift onto the tri's plane exactly.
  const K::FT d = n.x() * a.x() + n.y() * a.y() + n.z() * a.z();
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    if (v->info().id != kNone) continue;
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

// ---- global identity by value ---------------------------------------------------------------

/// Merges points of equal exact value (union to the smallest id). Ids are built canonically, so
/// equal values under different ids arise only at degeneracies (an edge crossing another leaf's
/// edge exactly, a vertex on another leaf's face, triple points, coplanar overlaps); candidates
/// are found by hashing grid cells (side h ≫ the width of the lazy intervals) that each point's
/// interval box meets, then compared exactly within a cell — only really equal (or 1e-11 close)
/// points ever reach exact arithmetic.
std::vector<uint32_t> merge_equal(const std::vector<Point>& pts, const std::vector<uint32_t>& ids,
                                  const Bbox& box) {
  std::vector<uint32_t> parent(pts.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const double extent = std::max({box.max.x - box.min.x, box.max.y - box.min.y,
                                  box.max.z - box.min.z, 1e-300});
  const double h = extent * 0x1p-36;
  std::vector<std::pair<uint64_t, uint32_t>> cells;
  cells.reserve(ids.size());
  for (uint32_t id : ids) {
    const auto& ap = CGAL::approx(pts[id]);
    int64_t lo[3], hi[3];
    bool wide = false;
    for (int a = 0; a < 3; ++a) {
      lo[a] = static_cast<int64_t>(std::floor((ap[a].inf() - box.min[a]) / h));
      hi[a] = static_cast<int64_t>(std::floor((ap[a].sup() - box.min[a]) / h));
      wide = wide || hi[a] - lo[a] > 1 || !std::isfinite(ap[a].inf()) || !std::isfinite(ap[a].sup());
    }
    if (wide) {  // interval too loose for the grid: one cell for all such points
      cells.emplace_back(~uint64_t{0}, id);
      continue;
    }
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) {
          uint64_t key = static_cast<uint64_t>(x) * 0x9e3779b97f4a7c15ull;
          key ^= static_cast<uint64_t>(y) * 0xc2b2ae3d27d4eb4full + (key >> 29);
          key ^= static_cast<uint64_t>(z) * 0x165667b19e3779f9ull + (key >> 31);
          cells.emplace_back(key == ~uint64_t{0} ? 0 : key, id);
        }
  }
  std::sort(cells.begin(), cells.end());
  std::vector<uint32_t> group;
  for (size_t i = 0; i < cells.size();) {
    size_t j = i;
    group.clear();
    while (j < cells.size() && cells[j].first == cells[i].first) group.push_back(cells[j++].second);
    i = j;
    if (group.size() < 2) continue;
    std::sort(group.begin(), group.end(), [&](uint32_t x, uint32_t y) {
      const CGAL::Comparison_result c = CGAL::compare_xyz(pts[x], pts[y]);
      return c == CGAL::SMALLER || (c == CGAL::EQUAL && x < y);
    });
    for (size_t g = 1; g < group.size(); ++g)
      if (group[g] != group[g - 1] && CGAL::compare_xyz(pts[group[g]], pts[group[g - 1]]) == CGAL::EQUAL) {
        const uint32_t x = find(group[g]), y = find(group[g - 1]);
        if (x != y) parent[std::max(x, y)] = std::min(x, y);
      }
  }
  for (uint32_t x = 0; x < parent.size(); ++x) parent[x] = find(x);
  return parent;
}

}  // namespace

Arrangement build_arrangement(const Solid& solid, size_t grain, EvaluatePhases& seconds) {
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  auto lap = [&t0](double& into) {
    const auto now = Clock::now();
    into = std::chrono::duration<double>(now - t0).count();
    t0 = now;
  };
  Arrangement arr;
  const std::vector<uint32_t> id = dedup_vertices(solid, arr.originals);
  arr.points.reserve(arr.originals.size());
  for (const Vec3& p : arr.originals) arr.points.emplace_back(p.x, p.y, p.z);
  arr.tris = leaf_tris(solid, id, arr.originals, grain);
  const std::vector<Tri>& tris = arr.tris;
  const std::vector<Vec3>& pos = arr.originals;
  lap(seconds.triangulate);

  const auto pairs = candidate_pairs(tris, pos);
  arr.candidate_pairs = pairs.size();
  lap(seconds.pairs);

  // Phase A: exact configuration of every pair (doubles only).
  std::vector<PairCut> cuts(pairs.size());
  parallel_for(pairs.size(), grain * 4, [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p)
      cuts[p] = cut_pair(tris[pairs[p].first], tris[pairs[p].second], pos);
  });
  // The crossings needed, each constructed once (key order: deterministic ids).
  std::vector<CrossKey> keys;
  for (size_t p = 0; p < pairs.size(); ++p) {
    if (cuts[p].kind != PairCut::kTransversal) continue;
    for (int e = 0; e < cuts[p].t.n; ++e)
      if (cuts[p].t.end[e].a != cuts[p].t.end[e].b)
        keys.push_back({edge_key(cuts[p].t.end[e].a, cuts[p].t.end[e].b), pairs[p].second});
    for (int e = 0; e < cuts[p].u.n; ++e)
      if (cuts[p].u.end[e].a != cuts[p].u.end[e].b)
        keys.push_back({edge_key(cuts[p].u.end[e].a, cuts[p].u.end[e].b), pairs[p].first});
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  const size_t first_crossing = arr.points.size();
  arr.points.resize(first_crossing + keys.size());
  parallel_for(keys.size(), grain * 4, [&](size_t begin, size_t end) {
    for (size_t x = begin; x < end; ++x) {
      const uint32_t a = static_cast<uint32_t>(keys[x].edge >> 32),
                     b = static_cast<uint32_t>(keys[x].edge & 0xffffffffu);
      arr.points[first_crossing + x] = crossing(arr.points[a], arr.points[b], tris[keys[x].tri],
                                                arr.points);
    }
  });
  // Phase B: the hits.
  std::vector<Hit> hits(pairs.size());
  parallel_for(pairs.size(), grain, [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      const auto [t, u] = pairs[p];
      if (cuts[p].kind == PairCut::kCoplanar) {
        hits[p] = coplanar_hit(tris[t], tris[u], arr.points);
      } else if (cuts[p].kind == PairCut::kTransversal) {
        hits[p] = transversal_hit(cuts[p], arr.points, [&](const Sym& s, bool of_t) {
          if (s.a == s.b) return s.a;
          const CrossKey key{edge_key(s.a, s.b), of_t ? u : t};
          return static_cast<uint32_t>(first_crossing +
                                       (std::lower_bound(keys.begin(), keys.end(), key) - keys.begin()));
        });
      }
    }
  });
  cuts = {};
  lap(seconds.intersect);

  // Hits per tri (CSR, pair order).
  std::vector<uint32_t> start(tris.size() + 1, 0);
  for (size_t p = 0; p < pairs.size(); ++p)
    if (!hits[p].empty()) {
      ++arr.intersecting_pairs;
      ++start[pairs[p].first + 1];
      ++start[pairs[p].second + 1];
    }
  for (size_t t = 0; t < tris.size(); ++t) start[t + 1] += start[t];
  std::vector<TriHit> by_tri(start.back());
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t p = 0; p < pairs.size(); ++p)
      if (!hits[p].empty()) {
        by_tri[fill[pairs[p].first]++] = {&hits[p], true};
        by_tri[fill[pairs[p].second]++] = {&hits[p], false};
      }
  }
  std::vector<uint32_t> touched;
  for (uint32_t t = 0; t < tris.size(); ++t)
    if (start[t + 1] > start[t]) touched.push_back(t);

  std::vector<Local> locals(touched.size());
  parallel_for(touched.size(), std::max<size_t>(1, grain / 8), [&](size_t begin, size_t end) {
    std::vector<TriHit> h;
    for (size_t x = begin; x < end; ++x) {
      const uint32_t t = touched[x];
      h.assign(by_tri.begin() + start[t], by_tri.begin() + start[t + 1]);
      locals[x] = split_tri(tris[t], h, arr.points, pos);
    }
  });
  lap(seconds.split);

  // Value-only points get ids in touched-tri order; then equal values merge (deterministic).
  std::vector<std::vector<uint32_t>> local_ids(touched.size());
  for (size_t x = 0; x < touched.size(); ++x) {
    Local& local = locals[x];
    size_t next = 0;
    for (uint32_t& q : local.ids)
      if (q == kNone) {
        q = static_cast<uint32_t>(arr.points.size());
        arr.points.push_back(std::move(local.points[next++]));
      }
  }
  std::vector<uint32_t> used;
  for (const Local& local : locals) used.insert(used.end(), local.ids.begin(), local.ids.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  Bbox box;
  for (const Vec3& p : pos) box.add(p);
  const std::vector<uint32_t> rep = merge_equal(arr.points, used, box);

  size_t next_touched = 0;
  for (uint32_t t = 0; t < tris.size(); ++t) {
    if (next_touched < touched.size() && touched[next_touched] == t) {
      Local& local = locals[next_touched++];
      auto map = [&](uint32_t q) { return rep[local.ids[q]]; };
      for (const auto& lt : local.tris) arr.pieces.push_back({{map(lt[0]), map(lt[1]), map(lt[2])}, t});
      for (const auto& [x, y] : local.cuts) arr.cuts.push_back(edge_key(map(x), map(y)));
      local = Local{};
    } else {
      arr.pieces.push_back({tris[t].v, t});
    }
  }
  std::sort(arr.cuts.begin(), arr.cuts.end());
  arr.cuts.erase(std::unique(arr.cuts.begin(), arr.cuts.end()), arr.cuts.end());
  lap(seconds.identify);
  return arr;
}

}  // namespace cover::boolean_detail
