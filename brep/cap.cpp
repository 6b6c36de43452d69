// Patching the plane cut: rings, ring hierarchy, split-and-merge bridges, convex decomposition
// and cap faces (Erleben & Henriksen 2006, §3–§6).
//
// EXACTNESS SCHEME
//   A constructed point p = a + t(b − a), t = (d − n·a)/(n·(b − a)), of a split edge (a, b) is
//   not a double. Every 2D decision below — ring orientation, point-in-ring, the angular order at
//   pinched vertices, bridge visibility, ear and convexity tests — is evaluated on the exact p:
//   CGAL's Epeck (lazy exact rationals: interval filter first, exact only when it is inconclusive)
//   with p built from the input doubles. The 2D point drops the dominant axis k of n:
//   (p[k+1], p[k+2]), whose orientation is the sign of the k component of the 3D normal; the
//   coordinates are swapped where needed so that every cap face (outward normal −n above, +n
//   below) is counter-clockwise in its side's frame: outer rings are counter-clockwise, holes
//   clockwise. Input vertices on the plane enter as their exact doubles. Two ring nodes are the
//   same point exactly when they are the same mesh vertex (a closed non-self-intersecting input
//   cannot make two different edges cross the plane at one point), so identity is by vertex id.
//   Output positions are the exact points rounded to the nearest double (ties to even): on an
//   axis-aligned plane x = c the x coordinate is then c. Rings are small next to the mesh, so
//   this costs little (bench/clip_vs_cgal.cpp measures the whole clip).
//   Rounding can move a point across a line through near-collinear neighbours (a planar region
//   of the input cut by the plane gives exactly collinear ring points). So the decomposition's
//   orientation tests (ear, containment, Hertel–Mehlhorn convexity) take the sign only where the
//   exact points and the rounded output points agree, and 0 (degenerate: not convex, blocking)
//   where they differ: every cap face is then valid both exactly and as written. Both signs are
//   exact (the rounded points are doubles: exact orient2d with a filter).
//
// Notation: a ring is a cycle of border half-edges of one side, oriented like the cap face that
// will close it (each is the twin of a face side on the cut). A node is one corner of a ring or
// of a merged polygon: its point slot, its vertex id and the half-edge leaving it.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <unordered_map>

#include "cover/brep/detail/clip_internal.h"
#include "cover/brep/detail/ear_clip.h"
#include "cover/solid/errors.h"

namespace cover::brep::detail {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = K::FT;
using Point2 = K::Point_2;
using KI = CGAL::Exact_predicates_inexact_constructions_kernel;  // the rounded (double) points

/// The exact value x rounded to the nearest double (ties to even).
double nearest_double(const FT& x) {
  const auto& e = CGAL::exact(x);
  using E = std::decay_t<decltype(e)>;
  const std::pair<double, double> iv = CGAL::to_interval(e);
  double lo = iv.first, hi = iv.second;
  while (lo != hi) {
    if (std::nextafter(lo, hi) == hi) {
      const CGAL::Comparison_result c = CGAL::compare(e, (E(lo) + E(hi)) / 2);
      if (c == CGAL::SMALLER) return lo;
      if (c == CGAL::LARGER) return hi;
      return (std::bit_cast<uint64_t>(lo) & 1) ? hi : lo;
    }
    const double mid = lo / 2 + hi / 2;  // strictly between lo and hi (≥ 2 ulps apart)
    const CGAL::Comparison_result c = CGAL::compare(e, E(mid));
    if (c == CGAL::EQUAL) return mid;
    (c == CGAL::SMALLER ? hi : lo) = mid;
  }
  return lo;
}

/// Ear clipping (ear_clip.h) of the sub-polygon `idx` (node indices, in order) of a polygon
/// whose geometry is `g`; the triangles come back as the polygon's node indices.
template <class Geometry>
std::vector<std::array<uint32_t, 3>> ear_clip_subset(const Geometry& g,
                                                     const std::vector<uint32_t>& idx,
                                                     int64_t& forced) {
  struct Sub {
    const Geometry& g;
    const std::vector<uint32_t>& idx;
    int orient(uint32_t i, uint32_t j, uint32_t k) const {
      return g.orient(idx[i], idx[j], idx[k]);
    }
    uint32_t id(uint32_t i) const { return g.id(idx[i]); }
    bool thin(uint32_t i, uint32_t j, uint32_t k) const { return g.thin(idx[i], idx[j], idx[k]); }
    std::array<double, 4> bounds(uint32_t i) const { return g.bounds(idx[i]); }
    bool box_may_contain(uint32_t p, uint32_t a, uint32_t c, uint32_t d) const {
      return g.box_may_contain(idx[p], idx[a], idx[c], idx[d]);
    }
  } sub{g, idx};
  std::vector<std::array<uint32_t, 3>> tris;
  for (const auto& t : ear_clip(static_cast<uint32_t>(idx.size()), sub, forced))
    tris.push_back({idx[t[0]], idx[t[1]], idx[t[2]]});
  return tris;
}

struct Node {
  uint32_t slot;  ///< exact point
  uint32_t vid;   ///< mesh vertex
  uint32_t he;    ///< mesh half-edge to the next node
};

struct Ring {
  std::vector<Node> nodes;
  int orientation = 0;  ///< sign of the area in the side's frame (> 0 outer, < 0 hole)
  /// Bounds on the extremes: [min x lower, min x upper, min y lower, min y upper,
  /// max x lower, max x upper, max y lower, max y upper].
  std::array<double, 8> box{};
  std::vector<uint32_t> sorted_vids;
  int depth = 0;
  int parent = -1;
};

class CapBuilder {
 public:
  CapBuilder(HalfedgeMesh& m, CapContext& c) : m_(m), c_(c), slot_of_(m.vertex_slots(), kNone) {}

  void run(CapStats& stats) {
    std::vector<std::pair<uint32_t, uint32_t>> borders[2];  // (origin, half-edge) per side
    for (uint32_t h = 0; h < m_.halfedge_slots(); ++h)
      if (!m_.edge_deleted(h) && m_.is_border(h))
        borders[c_.face_side[m_.face(h ^ 1)]].push_back({m_.origin(h), h});
    for (int side = 0; side < 2; ++side) {
      side_ = side;
      // Frame: swap (u, w) when the cap normal (−n above, +n below) points to −k.
      const bool n_pos = c_.plane.normal[c_.axis] > 0;
      swap_ = side == 0 ? n_pos : !n_pos;
      std::sort(borders[side].begin(), borders[side].end());
      std::vector<Ring> rings = walk(borders[side]);
      stats.rings[side] = static_cast<int64_t>(rings.size());
      nest(rings);
      for (size_t r = 0; r < rings.size(); ++r) {
        if (rings[r].orientation < 0) continue;
        std::vector<const Ring*> holes;
        for (const Ring& h : rings)
          if (h.parent == static_cast<int>(r)) holes.push_back(&h);
        std::vector<Node> polygon = bridge(rings[r], holes);
        stats.cap_faces[side] += decompose(polygon, stats.forced_ears);
      }
    }
    // Constructed vertices: exact point rounded to nearest (every one lies on a ring).
    for (uint32_t i = 0; i < c_.constructed_from.size(); ++i)
      m_.set_position(c_.original_vertices + i, rounded_[slot(c_.original_vertices + i)]);
  }

 private:
  // --- exact points ------------------------------------------------------------------------
  FT parameter(uint32_t a, uint32_t b) const {
    const Vec3& pa = c_.input_points[a];
    const Vec3& pb = c_.input_points[b];
    if (c_.through) {  // plane through p0, p1, p2: det[p1 − p0, p2 − p0, x − p0] is affine in x
      const auto& [p0, p1, p2] = *c_.through;
      const FT ux = FT(p1.x) - p0.x, uy = FT(p1.y) - p0.y, uz = FT(p1.z) - p0.z;
      const FT vx = FT(p2.x) - p0.x, vy = FT(p2.y) - p0.y, vz = FT(p2.z) - p0.z;
      const FT nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
      const FT da = nx * (FT(pa.x) - p0.x) + ny * (FT(pa.y) - p0.y) + nz * (FT(pa.z) - p0.z);
      const FT db = nx * (FT(pb.x) - p0.x) + ny * (FT(pb.y) - p0.y) + nz * (FT(pb.z) - p0.z);
      return da / (da - db);
    }
    const Vec3& n = c_.plane.normal;
    const FT na = FT(n.x) * pa.x + FT(n.y) * pa.y + FT(n.z) * pa.z;
    const FT nb = FT(n.x) * pb.x + FT(n.y) * pb.y + FT(n.z) * pb.z;
    return (FT(c_.plane.offset) - na) / (nb - na);
  }

  /// Constructed vertex v's exact point rounded to the nearest double per coordinate. Filter:
  /// the point is first evaluated in long double with a running error bound (unit roundoff u,
  /// every operation's error bounded by u times its magnitude, doubled for safety); when the
  /// interval value ± bound lies strictly between the two midpoints around its rounding, that
  /// rounding is the nearest double of the exact value. Otherwise the exact rational decides.
  Vec3 round_point(uint32_t v) const {
    const auto [a, b] = c_.constructed_from[v - c_.original_vertices];
    const Vec3& n = c_.plane.normal;
    const Vec3& pa = c_.input_points[a];
    const Vec3& pb = c_.input_points[b];
    using L = long double;
    constexpr L u = std::numeric_limits<L>::epsilon() / 2;
    const L ma = std::abs(L(n.x) * pa.x) + std::abs(L(n.y) * pa.y) + std::abs(L(n.z) * pa.z);
    const L mb = std::abs(L(n.x) * pb.x) + std::abs(L(n.y) * pb.y) + std::abs(L(n.z) * pb.z);
    const L na = L(n.x) * pa.x + L(n.y) * pa.y + L(n.z) * pa.z;
    const L nb = L(n.x) * pb.x + L(n.y) * pb.y + L(n.z) * pb.z;
    const L num = L(c_.plane.offset) - na, den = nb - na;
    const L err_num = 2 * 6 * u * (ma + std::abs(L(c_.plane.offset)));
    const L err_den = 2 * 8 * u * (ma + mb);
    // A plane through three points has no (n, d) in doubles: its points go the exact way.
    const bool filtered = !c_.through && std::abs(num) > 2 * err_num && std::abs(den) > 2 * err_den;
    const L t = num / den;
    const L rel_t = filtered ? 2 * (err_num / std::abs(num) + err_den / std::abs(den) + u) : 0;
    std::optional<FT> exact_t;
    Vec3 p;
    double* out[3] = {&p.x, &p.y, &p.z};
    for (int k = 0; k < 3; ++k) {
      const double ak = pa[k], bk = pb[k];
      if (ak == bk) {
        *out[k] = ak;
        continue;
      }
      if (!c_.through && n[(k + 1) % 3] == 0 &&
          n[(k + 2) % 3] == 0) {           // plane n_k·x_k = d: x_k = d/n_k exactly
        *out[k] = c_.plane.offset / n[k];  // (IEEE division rounds to nearest)
        continue;
      }
      if (filtered) {
        const L step = t * (L(bk) - L(ak));
        const L x = L(ak) + step;
        const L err = std::abs(step) * (rel_t + 4 * u) + 2 * u * std::abs(x);
        const double r = static_cast<double>(x);
        const L lo = (L(r) + L(std::nextafter(r, -INFINITY))) / 2;
        const L hi = (L(r) + L(std::nextafter(r, INFINITY))) / 2;
        if (x - err > lo && x + err < hi) {
          *out[k] = r;
          continue;
        }
      }
      if (!exact_t) exact_t = parameter(a, b);
      *out[k] = nearest_double(FT(ak) + *exact_t * (FT(bk) - FT(ak)));
    }
    return p;
  }

  /// The slot of vertex v's exact point (computed once, shared by both sides).
  uint32_t slot(uint32_t v) {
    if (slot_of_[v] != kNone) return slot_of_[v];
    const int u = c_.axis == 2 ? 0 : c_.axis + 1, w = c_.axis == 0 ? 2 : (c_.axis == 1 ? 0 : 1);
    FT pu, pw;
    if (v < c_.original_vertices) {
      pu = c_.input_points[v][u];
      pw = c_.input_points[v][w];
    } else {
      const auto [a, b] = c_.constructed_from[v - c_.original_vertices];
      const FT t = parameter(a, b);
      const Vec3& pa = c_.input_points[a];
      const Vec3& pb = c_.input_points[b];
      pu = pa[u] == pb[u] ? FT(pa[u]) : FT(pa[u]) + t * (FT(pb[u]) - FT(pa[u]));
      pw = pa[w] == pb[w] ? FT(pa[w]) : FT(pa[w]) + t * (FT(pb[w]) - FT(pa[w]));
    }
    slot_of_[v] = static_cast<uint32_t>(frame_[0].size());
    rounded_.push_back(v < c_.original_vertices ? c_.input_points[v] : round_point(v));
    frame_[0].emplace_back(pu, pw);
    frame_[1].emplace_back(pw, pu);
    // The lazy numbers' own intervals (CGAL::to_interval would refine them exactly near 0).
    const auto &iu = pu.approx(), &iw = pw.approx();
    interval_[0].push_back({iu.inf(), iu.sup(), iw.inf(), iw.sup()});
    interval_[1].push_back({iw.inf(), iw.sup(), iu.inf(), iu.sup()});
    return slot_of_[v];
  }
  const Point2& pt(uint32_t s) const { return frame_[swap_][s]; }
  const std::array<double, 4>& iv(uint32_t s) const { return interval_[swap_][s]; }
  int orient(uint32_t a, uint32_t b, uint32_t c) const {
    return static_cast<int>(CGAL::orientation(pt(a), pt(b), pt(c)));
  }
  /// Quality hint for ear clipping: the rounded corner a, b, c turns by less than ~1e-9 rad.
  bool thin(uint32_t a, uint32_t b, uint32_t c) const {
    const int u = c_.axis == 2 ? 0 : c_.axis + 1, w = c_.axis == 0 ? 2 : (c_.axis == 1 ? 0 : 1);
    const Vec3 &pa = rounded_[a], &pb = rounded_[b], &pc = rounded_[c];
    const double x1 = pb[u] - pa[u], y1 = pb[w] - pa[w], x2 = pc[u] - pb[u], y2 = pc[w] - pb[w];
    const double cross = x1 * y2 - y1 * x2;
    return std::abs(cross) <= 1e-9 * std::sqrt((x1 * x1 + y1 * y1) * (x2 * x2 + y2 * y2));
  }
  /// The orientation where the exact and the rounded points agree, else 0.
  int orient_both(uint32_t a, uint32_t b, uint32_t c) const {
    const int e = orient(a, b, c);
    const int r = (swap_ ? -1 : 1) * orient2d(rounded_[a], rounded_[b], rounded_[c], c_.axis);
    return e == r ? e : 0;
  }

  /// A corner a, b, c that a convex face may have: left turn in both geometries, or straight in
  /// both (a node on a side, e.g. where an earlier wall split the side: merging across it keeps
  /// the face convex and spares a diagonal that later walls would cross).
  bool convex_corner(uint32_t a, uint32_t b, uint32_t c) const {
    const int e = orient(a, b, c);
    const int r = (swap_ ? -1 : 1) * orient2d(rounded_[a], rounded_[b], rounded_[c], c_.axis);
    return e == r && e >= 0;
  }

  // --- §3: rings ---------------------------------------------------------------------------
  /// Clockwise angle from direction (ref − v) to (q − v) is smaller for q1 than for q2.
  bool cw_before(uint32_t v, uint32_t ref, uint32_t q1, uint32_t q2) const {
    auto half = [&](uint32_t q) {
      const int o = orient(v, ref, q);
      if (o < 0) return 1;  // (0, π) clockwise
      if (o > 0) return 3;  // (π, 2π)
      return CGAL::collinear_are_ordered_along_line(pt(ref), pt(v), pt(q)) ? 2 : 0;
    };
    const int h1 = half(q1), h2 = half(q2);
    if (h1 != h2) return h1 < h2;
    return orient(v, q1, q2) < 0;
  }

  std::vector<Ring> walk(const std::vector<std::pair<uint32_t, uint32_t>>& borders) {
    std::vector<Ring> rings;
    std::vector<uint8_t> visited(borders.size(), 0);
    auto position = [&](uint32_t h) {
      return static_cast<size_t>(
          std::lower_bound(borders.begin(), borders.end(), std::make_pair(m_.origin(h), h)) -
          borders.begin());
    };
    for (size_t i = 0; i < borders.size(); ++i) {
      if (visited[i]) continue;
      Ring ring;
      size_t j = i;
      do {
        if (visited[j])
          throw NotComputable("clip: inconsistent cut rings (self-intersecting input?)");
        visited[j] = 1;
        const uint32_t h = borders[j].second;
        ring.nodes.push_back({slot(m_.origin(h)), m_.origin(h), h});
        const uint32_t v = m_.head(h);
        auto [lo, hi] =
            std::equal_range(borders.begin(), borders.end(), std::make_pair(v, 0u),
                             [](const auto& x, const auto& y) { return x.first < y.first; });
        if (lo == hi) throw NotComputable("clip: open cut ring (self-intersecting input?)");
        auto best = lo;
        if (hi - lo > 1) {  // pinched vertex: tightest clockwise turn keeps rings from crossing
          const uint32_t sv = slot(v), sref = slot(m_.origin(h));
          for (auto it = lo + 1; it != hi; ++it)
            if (cw_before(sv, sref, slot(m_.head(it->second)), slot(m_.head(best->second))))
              best = it;
        }
        j = position(best->second);
      } while (j != i);
      finish(ring);
      rings.push_back(std::move(ring));
    }
    return rings;
  }

  void finish(Ring& r) const {
    FT twice_area = 0;
    r.box = {INFINITY, INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < r.nodes.size(); ++i) {
      const Point2& p = pt(r.nodes[i].slot);
      const Point2& q = pt(r.nodes[(i + 1) % r.nodes.size()].slot);
      twice_area += p.x() * q.y() - p.y() * q.x();
      const auto& b = iv(r.nodes[i].slot);
      for (int k = 0; k < 2; ++k) {
        r.box[2 * k] = std::min(r.box[2 * k], b[2 * k]);
        r.box[2 * k + 1] = std::min(r.box[2 * k + 1], b[2 * k + 1]);
        r.box[4 + 2 * k] = std::max(r.box[4 + 2 * k], b[2 * k]);
        r.box[5 + 2 * k] = std::max(r.box[5 + 2 * k], b[2 * k + 1]);
      }
      r.sorted_vids.push_back(r.nodes[i].vid);
    }
    r.orientation = static_cast<int>(CGAL::sign(twice_area));
    if (r.orientation == 0)
      throw NotComputable("clip: cut ring of zero area (self-touching input?)");
    std::sort(r.sorted_vids.begin(), r.sorted_vids.end());
  }

  // --- §5: ring hierarchy ------------------------------------------------------------------
  /// Is ring r inside ring s? Tested at a vertex of r that is not on s (exact).
  bool inside(const Ring& r, const Ring& s) {
    // Conservative box test: r ⊂ s needs min(r) ≥ min(s) and max(r) ≤ max(s) per axis.
    const auto &rb = r.box, &sb = s.box;
    if (rb[1] < sb[0] || rb[3] < sb[2] || rb[4] > sb[5] || rb[6] > sb[7]) return false;
    std::vector<Point2>& poly = scratch_;
    poly.clear();
    for (const Node& n : s.nodes) poly.push_back(pt(n.slot));
    for (const Node& n : r.nodes) {
      if (std::binary_search(s.sorted_vids.begin(), s.sorted_vids.end(), n.vid)) continue;
      const CGAL::Bounded_side b = CGAL::bounded_side_2(poly.begin(), poly.end(), pt(n.slot), K());
      if (b != CGAL::ON_BOUNDARY) return b == CGAL::ON_BOUNDED_SIDE;
    }
    return false;
  }

  void nest(std::vector<Ring>& rings) {
    const size_t n = rings.size();
    std::vector<std::vector<int>> containers(n);
    for (size_t r = 0; r < n; ++r)
      for (size_t s = 0; s < n; ++s)
        if (r != s && inside(rings[r], rings[s])) containers[r].push_back(static_cast<int>(s));
    for (size_t r = 0; r < n; ++r) rings[r].depth = static_cast<int>(containers[r].size());
    for (size_t r = 0; r < n; ++r) {
      for (int s : containers[r])
        if (rings[s].depth == rings[r].depth - 1) rings[r].parent = s;
      // Even depth: outer boundary (counter-clockwise); odd: hole (clockwise).
      if ((rings[r].depth % 2 == 0) != (rings[r].orientation > 0) ||
          (rings[r].depth > 0 && rings[r].parent < 0))
        throw NotComputable(
            "clip: cut ring nesting contradicts orientation (self-intersecting input?)");
    }
  }

  // --- §6: split-and-merge -----------------------------------------------------------------
  /// O'Rourke's InCone: is the direction a → target strictly inside the polygon's wedge at node
  /// `at` of `poly` (counter-clockwise)?
  bool in_cone(const std::vector<Node>& poly, size_t at, uint32_t target) const {
    const size_t n = poly.size();
    const uint32_t a = poly[at].slot, a0 = poly[(at + n - 1) % n].slot,
                   a1 = poly[(at + 1) % n].slot;
    if (orient(a, a1, a0) >= 0) return orient(a, target, a0) > 0 && orient(target, a, a1) > 0;
    return !(orient(a, target, a1) >= 0 && orient(target, a, a0) >= 0);
  }

  bool boxes_apart(uint32_t a, uint32_t b, uint32_t c, uint32_t d) const {
    const auto &pa = iv(a), &pb = iv(b), &pc = iv(c), &pd = iv(d);
    return std::max(pa[1], pb[1]) < std::min(pc[0], pd[0]) ||
           std::max(pc[1], pd[1]) < std::min(pa[0], pb[0]) ||
           std::max(pa[3], pb[3]) < std::min(pc[2], pd[2]) ||
           std::max(pc[3], pd[3]) < std::min(pa[2], pb[2]);
  }

  std::vector<Node> bridge(const Ring& outer, std::vector<const Ring*> holes) {
    std::vector<Node> poly = outer.nodes;
    // Leftmost vertex of each hole; holes are merged left to right ([Erleben2006 §6]).
    std::vector<std::pair<size_t, const Ring*>> order;
    for (const Ring* h : holes) {
      size_t best = 0;
      for (size_t i = 1; i < h->nodes.size(); ++i)
        if (CGAL::compare_xy(pt(h->nodes[i].slot), pt(h->nodes[best].slot)) == CGAL::SMALLER)
          best = i;
      order.push_back({best, h});
    }
    std::sort(order.begin(), order.end(), [&](const auto& x, const auto& y) {
      return CGAL::compare_xy(pt(x.second->nodes[x.first].slot),
                              pt(y.second->nodes[y.first].slot)) == CGAL::SMALLER;
    });
    for (const auto& [leftmost, hole] : order) {
      const std::vector<Node>& hn = hole->nodes;
      const uint32_t sb = hn[leftmost].slot, vb = hn[leftmost].vid;
      // Occurrences of B in the hole (a hole ring may pass a pinched vertex twice).
      std::vector<size_t> b_nodes;
      for (size_t i = 0; i < hn.size(); ++i)
        if (hn[i].vid == vb) b_nodes.push_back(i);
      // Candidates A strictly left of B, nearest first.
      const auto& ib = iv(sb);
      const double bx = (ib[0] + ib[1]) / 2, by = (ib[2] + ib[3]) / 2;
      std::vector<std::pair<double, size_t>> cands;
      for (size_t i = 0; i < poly.size(); ++i)
        if (CGAL::compare_x(pt(poly[i].slot), pt(sb)) == CGAL::SMALLER) {
          const auto& ia = iv(poly[i].slot);
          const double dx = (ia[0] + ia[1]) / 2 - bx, dy = (ia[2] + ia[3]) / 2 - by;
          cands.push_back({dx * dx + dy * dy, i});
        }
      std::sort(cands.begin(), cands.end());
      size_t ia = SIZE_MAX, ibn = SIZE_MAX;
      for (const auto& cand : cands) {
        const size_t i = cand.second;
        const uint32_t sa = poly[i].slot, va = poly[i].vid;
        if (!in_cone(poly, i, sb)) continue;
        size_t occ = SIZE_MAX;
        for (size_t k : b_nodes)
          if (in_cone(hn, k, sa)) occ = k;
        if (occ == SIZE_MAX) continue;
        bool clear = true;
        for (size_t e = 0; e < poly.size() && clear; ++e) {
          const Node& p = poly[e];
          const Node& q = poly[(e + 1) % poly.size()];
          if (p.vid == va || q.vid == va || boxes_apart(sa, sb, p.slot, q.slot)) continue;
          clear = !CGAL::do_intersect(K::Segment_2(pt(sa), pt(sb)),
                                      K::Segment_2(pt(p.slot), pt(q.slot)));
        }
        if (clear) {
          ia = i;
          ibn = occ;
          break;
        }
      }
      if (ia == SIZE_MAX) throw NotComputable("clip: no bridge from a hole to its outer ring");
      // New polygon: …, A —(A→B)→ B, the hole from B around to B, —(B→A)→ A, … (§6 Fig. 17).
      const uint32_t x = m_.insert_edge(poly[ia].vid, vb);
      std::vector<Node> merged(poly.begin(), poly.begin() + static_cast<long>(ia));
      merged.push_back({poly[ia].slot, poly[ia].vid, x});
      for (size_t k = 0; k < hn.size(); ++k) merged.push_back(hn[(ibn + k) % hn.size()]);
      merged.push_back({sb, vb, x ^ 1});
      merged.insert(merged.end(), poly.begin() + static_cast<long>(ia), poly.end());
      poly = std::move(merged);
    }
    return poly;
  }

  // --- §4: convex decomposition ------------------------------------------------------------
  /// orient in the exact (rounded = false) or the rounded (true) geometry.
  int orient_in(bool rounded, uint32_t a, uint32_t b, uint32_t c) const {
    return rounded ? (swap_ ? -1 : 1) * orient2d(rounded_[a], rounded_[b], rounded_[c], c_.axis)
                   : orient(a, b, c);
  }

  /// Is the diagonal from node i to node j of the polygon `idx` (node indices into poly) valid in
  /// both geometries: inside both corners' wedges and meeting no polygon side (conservatively:
  /// any touch or collinear overlap counts)?
  bool diagonal_ok(const std::vector<Node>& poly, const std::vector<uint32_t>& idx, size_t i,
                   size_t j) const {
    const size_t n = idx.size();
    const uint32_t si = poly[idx[i]].slot, sj = poly[idx[j]].slot;
    const uint32_t vi = poly[idx[i]].vid, vj = poly[idx[j]].vid;
    for (bool r : {true, false}) {  // the rounded (double) geometry first: cheaper
      for (auto [at, to] : {std::pair{i, sj}, std::pair{j, si}}) {
        const uint32_t a = poly[idx[at]].slot, a0 = poly[idx[(at + n - 1) % n]].slot,
                       a1 = poly[idx[(at + 1) % n]].slot;
        const bool ok = orient_in(r, a, a1, a0) > 0
                            ? orient_in(r, a, to, a0) > 0 && orient_in(r, to, a, a1) > 0
                            : !(orient_in(r, a, to, a1) >= 0 && orient_in(r, to, a, a0) >= 0);
        if (!ok) return false;
      }
      for (size_t e = 0; e < n; ++e) {
        const Node& p = poly[idx[e]];
        const Node& q = poly[idx[(e + 1) % n]];
        if (p.vid == vi || p.vid == vj || q.vid == vi || q.vid == vj) continue;
        if (boxes_apart(si, sj, p.slot, q.slot)) continue;  // conservative for both geometries
        const int o1 = orient_in(r, si, sj, p.slot), o2 = orient_in(r, si, sj, q.slot);
        const int o3 = orient_in(r, p.slot, q.slot, si), o4 = orient_in(r, p.slot, q.slot, sj);
        if (o1 * o2 <= 0 && o3 * o4 <= 0) return false;
      }
    }
    return true;
  }

  /// The constrained Delaunay triangulation of `poly` on its rounded points (its inside
  /// triangles, counter-clockwise, as node indices); false when the rounded ring is not simple
  /// with n distinct points, or when the result is not n − 2 triangles.
  /// Is the closed polyline q simple: distinct points, consecutive sides meeting only at their
  /// common point, other sides disjoint (exact predicates on the doubles)? Quadratic: rings
  /// longer than kMaxSimpleRing are reported as not simple.
  static bool simple_ring(const std::vector<KI::Point_2>& q) {
    constexpr size_t kMaxSimpleRing = 4096;
    const size_t n = q.size();
    if (n < 3 || n > kMaxSimpleRing) return false;
    std::vector<KI::Segment_2> side(n);
    for (size_t i = 0; i < n; ++i) {
      if (q[i] == q[(i + 1) % n]) return false;
      side[i] = KI::Segment_2(q[i], q[(i + 1) % n]);
    }
    for (size_t i = 0; i < n; ++i) {
      // Consecutive sides i and i + 1 share q[i + 1]: they must not fold back along one line.
      const KI::Point_2 &a = q[i], &b = q[(i + 1) % n], &c = q[(i + 2) % n];
      if (CGAL::orientation(a, b, c) == CGAL::COLLINEAR &&
          (side[i].has_on(c) || side[(i + 1) % n].has_on(a)))
        return false;
      for (size_t j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1) continue;  // consecutive through q[0]
        if (CGAL::do_intersect(side[i], side[j])) return false;
      }
    }
    return true;
  }

  bool rounded_cdt(const std::vector<Node>& poly, std::vector<std::array<uint32_t, 3>>& out) const {
    using Vb = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, KI>;
    using Fb = CGAL::Constrained_triangulation_face_base_2<KI>;
    using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
    using Cdt = CGAL::Constrained_Delaunay_triangulation_2<
        KI, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;
    const uint32_t n = static_cast<uint32_t>(poly.size());
    const int u = c_.axis == 2 ? 0 : c_.axis + 1, w = c_.axis == 0 ? 2 : (c_.axis == 1 ? 0 : 1);
    // CGAL's constrained triangulation is only given a simple ring: crossing or overlapping
    // constraints (a rounded ring that folds) are refused here, not inside the insertion.
    std::vector<KI::Point_2> q(n);
    for (uint32_t i = 0; i < n; ++i) {
      const Vec3& r = rounded_[poly[i].slot];
      q[i] = swap_ ? KI::Point_2(r[w], r[u]) : KI::Point_2(r[u], r[w]);
    }
    if (!simple_ring(q)) return false;
    Cdt cdt;
    std::vector<Cdt::Vertex_handle> vh(n);
    try {
      for (uint32_t i = 0; i < n; ++i) {
        vh[i] = cdt.insert(q[i]);
        if (cdt.number_of_vertices() != i + 1) return false;  // a repeated point
        vh[i]->info() = i;
      }
      for (uint32_t i = 0; i < n; ++i) cdt.insert_constraint(vh[i], vh[(i + 1) % n]);
    } catch (const std::exception&) {
      return false;  // constraints cross: the rounded ring is not simple
    }
    if (cdt.number_of_vertices() != n) return false;
    // Inside: faces reached from the infinite face across an odd number of constraints.
    std::unordered_map<Cdt::Face_handle, int> level;
    std::vector<std::pair<Cdt::Face_handle, int>> stack{{cdt.infinite_face(), 0}};
    while (!stack.empty()) {
      auto [f, l] = stack.back();
      stack.pop_back();
      if (!level.emplace(f, l).second) continue;
      for (int k = 0; k < 3; ++k) {
        const Cdt::Face_handle g = f->neighbor(k);
        if (!level.count(g)) stack.push_back({g, cdt.is_constrained({f, k}) ? l + 1 : l});
      }
    }
    out.clear();
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
      if (level[f] % 2 == 1)
        out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
    return out.size() + 2 == n;
  }

  /// Triangles of `poly` (node indices): ear clipping of the whole polygon, and where that needs
  /// forced ears, split_and_clip if it needs fewer.
  template <class Geometry>
  std::vector<std::array<uint32_t, 3>> triangulate(const std::vector<Node>& poly, const Geometry& g,
                                                   int64_t& forced) const {
    // A method's cost: its forced ears, or (more honest, as a forced ear can still give a valid
    // triangle while the final remainder is never tested) its triangles that are not strictly
    // counter-clockwise on the rounded points, if more.
    auto folded = [&](const std::vector<std::array<uint32_t, 3>>& t, int64_t ears) {
      int64_t bad = 0;
      for (const auto& x : t)
        if (rounded_[poly[x[1]].slot] != rounded_[poly[x[2]].slot] &&
            orient_in(true, poly[x[0]].slot, poly[x[1]].slot, poly[x[2]].slot) <= 0)
          ++bad;
      return std::max(bad, ears);
    };
    int64_t whole = 0;
    auto tris = ear_clip(static_cast<uint32_t>(poly.size()), g, whole);
    whole = folded(tris, whole);
    if (whole > 0) {
      int64_t parts = 0;
      auto other = split_and_clip(poly, g, parts);
      parts = folded(other, parts);
      if (parts < whole) {
        tris = std::move(other);
        whole = parts;
      }
    }
    if (whole > 0) {
      // No triangulation valid on both the exact and the rounded points was found: the written
      // (rounded) points decide alone, so that the cap as written is valid.
      struct Rounded {
        const CapBuilder& b;
        const Geometry& g;
        const std::vector<Node>& poly;
        std::array<double, 2> at(uint32_t i) const {
          const Vec3& r = b.rounded_[poly[i].slot];
          const int u = b.c_.axis == 2 ? 0 : b.c_.axis + 1,
                    w = b.c_.axis == 0 ? 2 : (b.c_.axis == 1 ? 0 : 1);
          return b.swap_ ? std::array<double, 2>{r[w], r[u]} : std::array<double, 2>{r[u], r[w]};
        }
        int orient(uint32_t i, uint32_t j, uint32_t k) const {
          return b.orient_in(true, poly[i].slot, poly[j].slot, poly[k].slot);
        }
        uint32_t id(uint32_t i) const { return g.id(i); }
        bool thin(uint32_t i, uint32_t j, uint32_t k) const { return g.thin(i, j, k); }
        std::array<double, 4> bounds(uint32_t i) const {
          const auto p = at(i);
          return {p[0], p[0], p[1], p[1]};
        }
        bool box_may_contain(uint32_t p, uint32_t a, uint32_t c, uint32_t d) const {
          const auto q = at(p), x = at(a), y = at(c), z = at(d);
          return !(q[0] < std::min({x[0], y[0], z[0]}) || q[0] > std::max({x[0], y[0], z[0]}) ||
                   q[1] < std::min({x[1], y[1], z[1]}) || q[1] > std::max({x[1], y[1], z[1]}));
        }
      } rounded{*this, g, poly};
      // Consecutive nodes at one rounded point (distinct exact points that round alike) bound
      // no triangle on the rounded points: the polygon without the first of each such pair is
      // clipped, and each dropped node d between p and e gets the zero-area triangle (p, d, e)
      // on the diagonal p–e (the rounding repair later collapses d–e, cells.h).
      const uint32_t n = static_cast<uint32_t>(poly.size());
      std::vector<uint32_t> keep;
      std::vector<uint8_t> dropped(n, 0);
      for (uint32_t i = 0; i < n; ++i) {
        const uint32_t e = (i + 1) % n;
        if (rounded_[poly[i].slot] == rounded_[poly[e].slot] && !dropped[e] &&
            keep.size() + (n - i) > 3)
          dropped[i] = 1;
        else
          keep.push_back(i);
      }
      int64_t alone = 0;
      std::vector<std::array<uint32_t, 3>> other;
      if (keep.size() >= 3) {
        other = ear_clip_subset(rounded, keep, alone);
        // Dropped nodes, last first: each fills between its kept (or refilled) neighbours.
        for (uint32_t i = 0; i < n; ++i) {
          if (!dropped[i]) continue;
          uint32_t p = (i + n - 1) % n;
          while (dropped[p]) p = (p + n - 1) % n;
          uint32_t e = (i + 1) % n;
          other.push_back({p, i, e});
        }
      } else {
        alone = whole + 1;
      }
      alone = folded(other, alone);
      if (alone < whole) {
        tris = std::move(other);
        whole = alone;
      }
    }
    if (whole > 0) {
      // Ear clipping on the rounded points can still corner itself on long exactly collinear
      // chains (a cell edge crossing an earlier cap: every node on one line). A constrained
      // Delaunay triangulation of the rounded polygon never does (exact predicates on the
      // doubles); it needs distinct rounded points, a simple rounded ring and no repeated node.
      std::vector<std::array<uint32_t, 3>> other;
      if (rounded_cdt(poly, other)) {
        const int64_t bad = folded(other, 0);
        if (bad < whole) {
          tris = std::move(other);
          whole = bad;
        }
      }
    }
    forced += whole;
    return tris;
  }

  /// A corner whose turn the exact and the rounded points disagree on can be no ear's tip, and
  /// ear clipping can end with it as the tip of the last triangle (a forced ear: folded in the
  /// rounded output). Here each such corner first gets a diagonal valid in both geometries,
  /// nearest candidates first, which splits the polygon in two; then each part is ear-clipped.
  template <class Geometry>
  std::vector<std::array<uint32_t, 3>> split_and_clip(const std::vector<Node>& poly,
                                                      const Geometry& g, int64_t& forced) const {
    std::vector<std::array<uint32_t, 3>> tris;
    std::vector<std::vector<uint32_t>> parts(1);
    parts[0].resize(poly.size());
    std::iota(parts[0].begin(), parts[0].end(), 0u);
    // Corners that disagree in the whole polygon (a part keeps each node's neighbours except at
    // its diagonal's ends, which are re-tested there).
    const size_t m = poly.size();
    std::vector<uint8_t> disagree(m, 0);
    for (size_t i = 0; i < m; ++i) {
      const uint32_t sa = poly[(i + m - 1) % m].slot, sb = poly[i].slot,
                     sc = poly[(i + 1) % m].slot;
      disagree[i] = orient_in(false, sa, sb, sc) != orient_in(true, sa, sb, sc);
    }
    while (!parts.empty()) {
      std::vector<uint32_t> idx = std::move(parts.back());
      parts.pop_back();
      const size_t n = idx.size();
      bool split = false;
      for (size_t i = 0; i < n && n > 3 && !split; ++i) {
        if (!disagree[idx[i]]) continue;
        const uint32_t sa = poly[idx[(i + n - 1) % n]].slot, sb = poly[idx[i]].slot,
                       sc = poly[idx[(i + 1) % n]].slot;
        if (orient_in(false, sa, sb, sc) == orient_in(true, sa, sb, sc)) continue;
        const auto& bi = iv(poly[idx[i]].slot);
        std::vector<std::pair<double, size_t>> cands;
        for (size_t j = 0; j < n; ++j) {
          if (j == i || j == (i + 1) % n || j == (i + n - 1) % n) continue;
          if (poly[idx[j]].vid == poly[idx[i]].vid) continue;
          const auto& bj = iv(poly[idx[j]].slot);
          const double dx = bj[0] - bi[0], dy = bj[2] - bi[2];
          cands.push_back({dx * dx + dy * dy, j});
        }
        // The nearest few only: a corner that disagrees is nearly flat, so a near node sees it;
        // each candidate costs O(n) exact tests.
        constexpr size_t kCandidates = 16;
        if (cands.size() > kCandidates) {
          std::nth_element(cands.begin(), cands.begin() + kCandidates, cands.end());
          cands.resize(kCandidates);
        }
        std::sort(cands.begin(), cands.end());
        for (const auto& [d2, j] : cands) {
          if (!diagonal_ok(poly, idx, i, j)) continue;
          std::vector<uint32_t> a, b;
          for (size_t k = i;; k = (k + 1) % n) {
            a.push_back(idx[k]);
            if (k == j) break;
          }
          for (size_t k = j;; k = (k + 1) % n) {
            b.push_back(idx[k]);
            if (k == i) break;
          }
          parts.push_back(std::move(a));
          parts.push_back(std::move(b));
          split = true;
          break;
        }
      }
      if (split) continue;
      for (const auto& t : ear_clip_subset(g, idx, forced)) tris.push_back(t);
    }
    return tris;
  }

  /// Ear-clips the polygon, removes diagonals while both ends stay convex (Hertel–Mehlhorn)
  /// unless triangulating, and makes the cap faces. Returns the number of faces made.
  int64_t decompose(const std::vector<Node>& poly, int64_t& forced) {
    const uint32_t n = static_cast<uint32_t>(poly.size());
    struct Geometry {
      const CapBuilder& b;
      const std::vector<Node>& poly;
      int orient(uint32_t i, uint32_t j, uint32_t k) const {
        return b.orient_both(poly[i].slot, poly[j].slot, poly[k].slot);
      }
      uint32_t id(uint32_t i) const { return poly[i].vid; }
      bool thin(uint32_t i, uint32_t j, uint32_t k) const {
        return b.thin(poly[i].slot, poly[j].slot, poly[k].slot);
      }
      std::array<double, 4> bounds(uint32_t i) const { return b.iv(poly[i].slot); }
      bool box_may_contain(uint32_t p, uint32_t a, uint32_t c, uint32_t d) const {
        const auto &q = b.iv(poly[p].slot), &x = b.iv(poly[a].slot), &y = b.iv(poly[c].slot),
                   &z = b.iv(poly[d].slot);
        return !(q[1] < std::min({x[0], y[0], z[0]}) || q[0] > std::max({x[1], y[1], z[1]}) ||
                 q[3] < std::min({x[2], y[2], z[2]}) || q[2] > std::max({x[3], y[3], z[3]}));
      }
    } geometry{*this, poly};
    const auto tris = triangulate(poly, geometry, forced);
    // Local half-edges: 3 per triangle; a side from node i to node i+1 is a ring side, any other
    // is a diagonal shared (reversed) by two triangles.
    const uint32_t nl = static_cast<uint32_t>(3 * tris.size());
    std::vector<uint32_t> from(nl), next(nl), prev(nl), twin(nl, kNone);
    std::unordered_map<uint64_t, uint32_t> open;
    for (uint32_t t = 0; t < tris.size(); ++t)
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t l = 3 * t + k, a = tris[t][k], b = tris[t][(k + 1) % 3];
        from[l] = a;
        next[l] = 3 * t + (k + 1) % 3;
        prev[l] = 3 * t + (k + 2) % 3;
        if (b == (a + 1) % n) continue;
        const auto it = open.find(uint64_t{b} << 32 | a);
        if (it == open.end()) {
          open.emplace(uint64_t{a} << 32 | b, l);
        } else {
          twin[l] = it->second;
          twin[it->second] = l;
          open.erase(it);
        }
      }
    std::vector<uint8_t> removed(nl, 0);
    if (!c_.triangulate) {
      for (uint32_t d = 0; d < nl; ++d) {
        const uint32_t t = twin[d];
        if (t == kNone || t < d) continue;
        const uint32_t u = from[d], v = from[t];
        if (!convex_corner(poly[from[prev[d]]].slot, poly[u].slot,
                           poly[from[next[next[t]]]].slot) ||
            !convex_corner(poly[from[prev[t]]].slot, poly[v].slot, poly[from[next[next[d]]]].slot))
          continue;
        const uint32_t pd = prev[d], nd = next[d], pt = prev[t], nt = next[t];
        next[pd] = nt;
        prev[nt] = pd;
        next[pt] = nd;
        prev[nd] = pt;
        removed[d] = removed[t] = 1;
      }
    }
    // Cap faces: ring sides use the ring's border half-edges, kept diagonals new edges.
    std::vector<uint32_t> mesh_he(nl, kNone), loop;
    std::vector<uint8_t> done(nl, 0);
    int64_t faces = 0;
    for (uint32_t l = 0; l < nl; ++l) {
      if (removed[l] || done[l]) continue;
      loop.clear();
      for (uint32_t k = l; !done[k]; k = next[k]) {
        done[k] = 1;
        if (twin[k] == kNone) {
          mesh_he[k] = poly[from[k]].he;
        } else if (mesh_he[k] == kNone) {
          mesh_he[k] = m_.insert_edge(poly[from[k]].vid, poly[from[twin[k]]].vid);
          mesh_he[twin[k]] = mesh_he[k] ^ 1;
        }
        loop.push_back(mesh_he[k]);
      }
      m_.make_face(loop);
      c_.face_side.push_back(static_cast<uint8_t>(side_));
      ++faces;
    }
    return faces;
  }

  HalfedgeMesh& m_;
  CapContext& c_;
  std::vector<uint32_t> slot_of_;
  std::vector<Point2> frame_[2];                    // (u, w) and (w, u) per slot
  std::vector<std::array<double, 4>> interval_[2];  // [xlo, xhi, ylo, yhi] per frame
  std::vector<Vec3> rounded_;                       // output position per slot
  std::vector<Point2> scratch_;
  int side_ = 0;
  bool swap_ = false;
};

}  // namespace

CapStats add_caps(HalfedgeMesh& mesh, CapContext& context) {
  CapStats stats;
  CapBuilder(mesh, context).run(stats);
  return stats;
}

}  // namespace cover::brep::detail
