// Step 3 of evaluate() (boolean/evaluate.h): each intersected tri is re-triangulated with its
// hits as constraints. The exactness scheme is described in boolean/detail/arrangement.h, the
// notation in boolean/detail/arrangement_steps.h.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <optional>
#include <tuple>
#include <unordered_map>

#include "cover/boolean/detail/arrangement_steps.h"
#include "cover/mesh/triangulate.h"
#include "cover/solid/predicates.h"

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

/// Sign of the k component of (b − a) × (c − a) for exact points — orient2d (solid/predicates.h)
/// in the projection that drops axis k — from interval arithmetic on the lazy approximations;
/// kUncertain when the interval contains 0.
constexpr int kUncertain = 2;
int orient_k_interval(const Point& a, const Point& b, const Point& c, int k) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  CGAL::Protect_FPU_rounding<true> guard;
  const auto& pa = CGAL::approx(a);
  const auto& pb = CGAL::approx(b);
  const auto& pc = CGAL::approx(c);
  const auto d = (pb[i] - pa[i]) * (pc[j] - pa[j]) - (pb[j] - pa[j]) * (pc[i] - pa[i]);
  if (d.inf() > 0) return 1;
  if (d.sup() < 0) return -1;
  return kUncertain;
}

/// The same sign in exact rationals (the lazy points' exact values).
int orient_k_exact(const Point& a, const Point& b, const Point& c, int k) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const auto& ea = CGAL::exact(a);
  const auto& eb = CGAL::exact(b);
  const auto& ec = CGAL::exact(c);
  using ET = std::decay_t<decltype(ea[0])>;
  const ET d = (eb[i] - ea[i]) * (ec[j] - ea[j]) - (eb[j] - ea[j]) * (ec[i] - ea[i]);
  return CGAL::sign(d);
}

/// Projected homogeneous coordinates (X, Y, W) of a point, point = (X/W, Y/W) in the projection.
using Homogeneous = std::array<CGAL::Mpzf, 3>;

/// The same sign for points in exact homogeneous Mpzf coordinates:
/// sign(det[[Xa, Ya, Wa], [Xb, Yb, Wb], [Xc, Yc, Wc]]) · sign(Wa·Wb·Wc).
int orient_homogeneous(const Homogeneous& a, const Homogeneous& b, const Homogeneous& c) {
  const CGAL::Mpzf d = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                       a[2] * (b[0] * c[1] - b[1] * c[0]);
  return d.sign() * a[2].sign() * b[2].sign() * c[2].sign();
}

/// The next common case without a triangulation: the tri is crossed by ONE polyline — its
/// transversal hits, all with tris of one other leaf that does not intersect itself, chain into
/// a simple path of at least two segments whose inner points lie inside the tri and whose two
/// ends lie on its boundary (a surface crossing the tri once). The path cuts the tri into two
/// simple polygons, each in the tri's orientation, which are ear-clipped. On
/// bench/evaluate_vs_manifold this is most of the tris that split_simple leaves (cheese ∪ fandisk,
/// armadillo ∩ knot1: the surface of the other mesh crosses a tri in 2–5 segments).
///
/// Why not the CDT: every hit end lies on an edge of one of the two tris, so the CDT's
/// orientation tests meet exact zeros constantly, each an exact rational evaluation of lazy
/// points (and, in flat regions, runs of collinear path points do the same). Here those zeros
/// are known without arithmetic: three points that lie on one line — an edge of the tri (its two
/// corners and the hit ends the intersection step placed on that edge), or one straight run of
/// the path (consecutive segments cut by coplanar tris of the other leaf, decided by exact
/// orient3d on the input doubles) — have orientation 0. Every other orientation is decided on the
/// lazy intervals, exact only when they straddle 0. Returns false (the caller runs the CDT) for
/// anything else: coplanar hits, several leaves, branches, closed loops, inner ends, isolated
/// points that are not path points, more than kMaxSegments segments, or a polygon whose ear
/// clipping gets stuck.
///
/// Why the path is simple: two segments t ∩ u1 and t ∩ u2 (u1, u2 tris of one clean leaf) meet
/// only in u1 ∩ u2, a shared edge or corner, whose point is built under one id (an edge × plane
/// crossing keyed by the edge, or the corner itself); a segment cannot pass through a corner of
/// its own tri except at an end. So the segments meet only at shared ids, and a path by ids with
/// every degree ≤ 2 is a simple curve, inside the open tri except at its ends.
bool split_polyline(const Tri& tri, const std::vector<TriHit>& hits, const Arrangement& arr,
                    const std::vector<uint8_t>& self, Local& local) {
  const std::vector<Tri>& tris = arr.tris;
  const std::vector<Point>& pts = arr.points;
  const std::vector<Vec3>& pos = arr.originals;
  constexpr size_t kMaxSegments = 16;  // ear clipping is O(n³) orientations: small polygons only
  struct Seg {
    uint32_t a, b;
    uint8_t wa, wb;  ///< where a and b lie on the tri
    uint32_t other;  ///< the other leaf's tri that cut it
  };
  std::vector<Seg> segs;
  std::vector<uint32_t> isolated;  // point hits off the corners
  uint32_t leaf = kNone;
  for (const TriHit& h : hits) {
    if (h.hit->ends[0].id == kNone) return false;  // coplanar
    const uint32_t ol = tris[h.other].leaf;
    if (ol == tri.leaf || (ol < self.size() && self[ol])) return false;
    if (leaf == kNone) leaf = ol;
    if (ol != leaf) return false;
    if (h.id(0) == h.id(1)) {
      if (h.on(0) >= kEdge) isolated.push_back(h.id(0));
      continue;
    }
    bool seen = false;
    for (const Seg& g : segs)
      seen = seen || (g.a == h.id(0) && g.b == h.id(1)) || (g.a == h.id(1) && g.b == h.id(0));
    if (!seen) segs.push_back({h.id(0), h.id(1), h.on(0), h.on(1), h.other});
    if (segs.size() > kMaxSegments) return false;
  }
  if (segs.size() < 2) return false;

  // ---- the path: nodes by id, degree ≤ 2, inner nodes inside, two ends on the boundary.
  struct Node {
    uint32_t id;
    uint8_t where;
    int degree = 0;
    std::array<int, 2> seg{-1, -1};
  };
  std::vector<Node> nodes;
  auto attach = [&](uint32_t id, uint8_t where, int g) {
    for (Node& n : nodes)
      if (n.id == id) {
        if (n.degree == 2 || n.where != where) return false;
        n.seg[n.degree++] = g;
        return true;
      }
    nodes.push_back({id, where, 1, {g, -1}});
    return true;
  };
  for (int g = 0; g < static_cast<int>(segs.size()); ++g)
    if (!attach(segs[g].a, segs[g].wa, g) || !attach(segs[g].b, segs[g].wb, g)) return false;
  int start = -1, ends = 0;
  for (int x = 0; x < static_cast<int>(nodes.size()); ++x) {
    const Node& n = nodes[x];
    if (n.degree == 1) {
      if (n.where >= kInside) return false;
      if (start < 0) start = x;
      ++ends;
    } else if (n.where != kInside) {
      return false;
    }
  }
  if (ends != 2) return false;
  std::vector<int> path{start};  // node indices P[0..k]
  std::vector<int> via;          // segment indices S[0..k-1]
  for (int cur = start, came = -1;;) {
    const Node& n = nodes[cur];
    const int g = n.seg[0] != came ? n.seg[0] : n.seg[1];
    if (g < 0) break;
    via.push_back(g);
    const uint32_t next = segs[g].a == n.id ? segs[g].b : segs[g].a;
    cur = -1;
    for (int x = 0; x < static_cast<int>(nodes.size()); ++x)
      if (nodes[x].id == next) cur = x;
    path.push_back(cur);
    came = g;
    if (nodes[cur].degree == 1) break;
  }
  if (via.size() != segs.size()) return false;  // not connected: more than one component
  for (uint32_t id : isolated) {
    bool on_path = false;
    for (const Node& n : nodes) on_path = on_path || n.id == id;
    if (!on_path) return false;
  }

  // ---- projection (drops the dominant axis of the tri's normal) and the tri's sign there.
  const int k = dominant_axis(normal_direction(pos[tri.v[0]], pos[tri.v[1]], pos[tri.v[2]]));
  const int sign = orient2d(pos[tri.v[0]], pos[tri.v[1]], pos[tri.v[2]], k);
  if (sign == 0) return false;

  // ---- local points: the corners, then the path's points off the corners; the lines each lies
  // on (bits 0–2: the tri's edges, edge i from corner i to i + 1; bits 3–63: straight runs).
  local.ids.assign(tri.v.begin(), tri.v.end());
  std::vector<uint64_t> lines{0b101, 0b011, 0b110};  // corner c: edges c and c − 1
  std::vector<uint32_t> at(path.size());             // local id of each path point
  for (size_t m = 0; m < path.size(); ++m) {
    const Node& n = nodes[path[m]];
    if (n.where < kEdge) {
      at[m] = n.where;
    } else {
      at[m] = static_cast<uint32_t>(local.ids.size());
      local.ids.push_back(n.id);
      lines.push_back(n.where < kInside ? uint64_t{1} << (n.where - kEdge) : 0);
    }
  }
  auto coplanar_tris = [&](const Tri& u, const Tri& w) {
    for (uint32_t c : w.v) {
      if (c == u.v[0] || c == u.v[1] || c == u.v[2]) continue;
      if (orient3d(pos[u.v[0]], pos[u.v[1]], pos[u.v[2]], pos[c]) != 0) return false;
    }
    return true;
  };
  int run = 3;
  for (size_t m = 0; m < via.size(); ++m) {
    if (m > 0 && !coplanar_tris(tris[segs[via[m - 1]].other], tris[segs[via[m]].other])) ++run;
    if (run < 64) {
      lines[at[m]] |= uint64_t{1} << run;
      lines[at[m + 1]] |= uint64_t{1} << run;
    }
  }
  // Exact fallback: input vertices and edge × plane crossings in homogeneous Mpzf coordinates
  // (exact_crossing), computed once per point; other points through their lazy exact values.
  std::vector<std::optional<Homogeneous>> exact(local.ids.size());
  auto homogeneous = [&](uint32_t q) -> const std::optional<Homogeneous>& {
    std::optional<Homogeneous>& h = exact[q];
    if (h) return h;
    const uint32_t id = local.ids[q];
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    if (id < pos.size()) {
      h = Homogeneous{CGAL::Mpzf(pos[id][i]), CGAL::Mpzf(pos[id][j]), CGAL::Mpzf(1.0)};
    } else if (id >= arr.first_crossing && id - arr.first_crossing < arr.crossings.size()) {
      const auto& [ea, eb, et] = arr.crossings[id - arr.first_crossing];
      const auto& w = tris[et].v;
      ExactCrossing e = exact_crossing(pos[ea], pos[eb], pos[w[0]], pos[w[1]], pos[w[2]]);
      h = Homogeneous{std::move(e.x[i]), std::move(e.x[j]), std::move(e.w)};
    }
    return h;
  };
  auto orient = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (lines[a] & lines[b] & lines[c]) return 0;
    const Point &pa = pts[local.ids[a]], &pb = pts[local.ids[b]], &pc = pts[local.ids[c]];
    const int s = orient_k_interval(pa, pb, pc, k);
    if (s != kUncertain) return s;
    const auto &ha = homogeneous(a), &hb = homogeneous(b), &hc = homogeneous(c);
    if (ha && hb && hc) return orient_homogeneous(*ha, *hb, *hc);
    return orient_k_exact(pa, pb, pc, k);
  };

  // ---- the two polygons: the boundary arc from one end forward (the tri's order) to the
  // other, closed by the path.
  auto place = [](uint8_t where) { return where < kEdge ? 2 * where : 2 * (where - kEdge) + 1; };
  const size_t last = path.size() - 1;
  const uint8_t w0 = nodes[path[0]].where, w1 = nodes[path[last]].where;
  bool first_ahead = false;  // both ends on one edge: path[0] comes first from its corner
  if (w0 == w1) {
    const uint32_t e = w0 - kEdge;
    const Vec3& c0 = pos[tri.v[e]];
    const Vec3& c1 = pos[tri.v[(e + 1) % 3]];
    const CGAL::Comparison_result dir =
        std::tie(c0.x, c0.y, c0.z) < std::tie(c1.x, c1.y, c1.z) ? CGAL::SMALLER : CGAL::LARGER;
    const CGAL::Comparison_result c =
        CGAL::compare_xyz(pts[nodes[path[0]].id], pts[nodes[path[last]].id]);
    if (c == CGAL::EQUAL) return false;
    first_ahead = c == dir;
  }
  auto arc = [&](uint8_t from, uint8_t to, bool ahead, std::vector<uint32_t>& poly) {
    const int a = place(from), b = place(to);
    int p = a;
    if (a == b && ahead) return;
    do {
      p = (p + 1) % 6;
      if (p % 2 == 0 && p != b) poly.push_back(static_cast<uint32_t>(p / 2));
    } while (p != b);
  };
  std::vector<uint32_t> A{at[last]}, B{at[0]};
  arc(w1, w0, !first_ahead, A);
  for (size_t m = 0; m < last; ++m) A.push_back(at[m]);
  arc(w0, w1, first_ahead, B);
  for (size_t m = last; m > 0; --m) B.push_back(at[m]);

  // ---- ear clipping (each polygon simple, in the tri's orientation); a triangle is an ear when
  // strictly convex and no other vertex of the polygon lies in it, boundary included. Then
  // Lawson flips of the polygon's diagonals towards the Delaunay triangulation in the same
  // projection (the pieces the CDT gave): ear clipping alone leaves slivers, whose rounded
  // corners then touch their neighbours (rounding contacts the repair cannot always undo). A
  // flip needs the quadrilateral strictly convex (exact, as above); the in-circle test only
  // chooses among valid triangulations, so it runs on the doubles nearest to the points.
  std::vector<std::array<double, 2>> flat(local.ids.size());
  for (size_t q = 0; q < flat.size(); ++q) {
    const auto& ap = CGAL::approx(pts[local.ids[q]]);
    flat[q] = {CGAL::to_double(ap[(k + 1) % 3]), CGAL::to_double(ap[(k + 2) % 3])};
  }
  auto in_circle = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t d) {  // d inside abc's circle
    const double adx = flat[a][0] - flat[d][0], ady = flat[a][1] - flat[d][1];
    const double bdx = flat[b][0] - flat[d][0], bdy = flat[b][1] - flat[d][1];
    const double cdx = flat[c][0] - flat[d][0], cdy = flat[c][1] - flat[d][1];
    const double det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
                       (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                       (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
    return det * sign > 0;
  };
  auto flip_to_delaunay = [&](std::vector<std::array<uint32_t, 3>>& ts) {
    size_t budget = 4 * ts.size() * ts.size() + 8;  // approximate tests: no cycling
    for (bool flipped = true; flipped && budget > 0;) {
      flipped = false;
      for (size_t x = 0; x < ts.size() && !flipped; ++x)
        for (int e = 0; e < 3 && !flipped; ++e) {
          const uint32_t a = ts[x][e], b = ts[x][(e + 1) % 3], c = ts[x][(e + 2) % 3];
          for (size_t y = x + 1; y < ts.size() && !flipped; ++y)
            for (int f = 0; f < 3; ++f) {
              if (ts[y][f] != b || ts[y][(f + 1) % 3] != a) continue;
              const uint32_t d = ts[y][(f + 2) % 3];
              if (in_circle(a, b, c, d) && orient(c, a, d) == sign && orient(d, b, c) == sign) {
                ts[x] = {c, a, d};
                ts[y] = {d, b, c};
                flipped = true;
                --budget;
              }
              break;
            }
        }
    }
  };
  auto clip = [&](std::vector<uint32_t> poly) {
    std::vector<std::array<uint32_t, 3>> ts;
    auto done = [&] {
      flip_to_delaunay(ts);
      local.tris.insert(local.tris.end(), ts.begin(), ts.end());
      return true;
    };
    while (poly.size() > 3) {
      const size_t n = poly.size();
      bool cut = false;
      for (size_t x = 0; x < n && !cut; ++x) {
        const uint32_t a = poly[(x + n - 1) % n], v = poly[x], b = poly[(x + 1) % n];
        if (orient(a, v, b) != sign) continue;
        bool empty = true;
        for (size_t y = 0; y < n && empty; ++y) {
          const uint32_t w = poly[y];
          if (w == a || w == v || w == b) continue;
          empty = !(orient(a, v, w) * sign >= 0 && orient(v, b, w) * sign >= 0 &&
                    orient(b, a, w) * sign >= 0);
        }
        if (!empty) continue;
        ts.push_back({a, v, b});
        poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(x));
        cut = true;
      }
      if (!cut) return false;
    }
    if (orient(poly[0], poly[1], poly[2]) != sign) return false;
    ts.push_back({poly[0], poly[1], poly[2]});
    return done();
  };
  if (!clip(A) || !clip(B)) return false;
  for (auto& t : local.tris)
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());  // orientation kept
  std::sort(local.tris.begin(), local.tris.end());
  for (size_t m = 0; m < last; ++m) local.cuts.emplace_back(at[m], at[m + 1]);
  return true;
}

}  // namespace

Local split_tri(const Tri& tri, const std::vector<TriHit>& hits, const Arrangement& arr,
                const std::vector<uint8_t>& self) {
  const std::vector<Point>& pts = arr.points;
  const std::vector<Vec3>& pos = arr.originals;
  Local local;
  if (split_simple(tri, hits, local)) return local;
  local = Local{};
  if (split_polyline(tri, hits, arr, self, local)) return local;
  local = Local{};
  const Point& a = pts[tri.v[0]];
  const Point& b = pts[tri.v[1]];
  const Point& c = pts[tri.v[2]];
  // The projection: the dominant axis of the normal in doubles, or the next axis where the
  // exact orient2d is not 0 (a doubles normal can pick an axis the plane is parallel to); its
  // sign is that of the normal's k component, exactly.
  int k = dominant_axis(normal_direction(pos[tri.v[0]], pos[tri.v[1]], pos[tri.v[2]]));
  int sign = orient2d(pos[tri.v[0]], pos[tri.v[1]], pos[tri.v[2]], k);
  for (int step = 1; sign == 0 && step < 3; ++step) {
    const int axis = (k + step) % 3;
    sign = orient2d(pos[tri.v[0]], pos[tri.v[1]], pos[tri.v[2]], axis);
    if (sign != 0) k = axis;
  }
  const int i = (k + 1) % 3, j = (k + 2) % 3;
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
      const Cdt::Vertex_handle p = add_value(s.source(), kNone), q = add_value(s.target(), kNone);
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
  const bool flip = sign < 0;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    const uint32_t x = f->vertex(0)->info().id, y = f->vertex(1)->info().id,
                   z = f->vertex(2)->info().id;
    std::array<uint32_t, 3> t =
        flip ? std::array<uint32_t, 3>{x, z, y} : std::array<uint32_t, 3>{x, y, z};
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
