// Step 2 of evaluate() (boolean/evaluate.h): candidate pairs and exact pairwise triangle
// intersections. The exactness scheme is described in boolean/detail/arrangement.h, the notation
// in boolean/detail/arrangement_steps.h.
#include <CGAL/intersections.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <compare>

#include "cover/boolean/detail/arrangement_steps.h"
#include "cover/mesh/box_pairs.h"
#include "cover/mesh/validate.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"

namespace cover::boolean_detail {
namespace {

// Transversal pairs (the planes of t and u cross) never go through CGAL's generic
// intersection(Triangle_3, Triangle_3): its lazy result is a variant whose exact fallback redoes
// the whole triangle–triangle intersection in rationals each time a later predicate (CDT
// equality of the same point reached from two pairs) is uncertain, which would dominate
// evaluate's time. Instead:
//   * the configuration is decided by exact orient3d on the input doubles (solid/predicates.h);
//   * t ∩ plane(u) is an interval of the line plane(t) ∩ plane(u) whose ends are symbolic: a
//     corner of t lying in plane(u), or the crossing of an edge of t with plane(u) — the latter
//     constructed ONCE per (edge, tri) key (crossings()), so every pair that needs it shares one
//     lazy object and its id (the crossing of edge a–b with plane(u) is reached from both tris
//     of the edge);
//   * the hit is the overlap of t's and u's intervals, ordered by exact compare_xyz (a strictly
//     monotone order along any line).
// Coplanar pairs (rare except in axis-aligned scenes) keep CGAL's intersection.

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

/// The lazy crossing point of line a–b with the plane of p, q, r (input doubles; the line crosses
/// it) as ONE node of CGAL's lazy kernel: its interval approximation computed at once from the
/// doubles, its exact value on demand from the homogeneous Mpzf coordinates (exact_crossing).
/// The same point through the lazy kernel's operators would be a DAG of about a dozen nodes,
/// each allocated, evaluated in rationals when a predicate needs the exact value, and freed node
/// by node (about a tenth of an evaluation for freeing alone).
class CrossingRep final
    : public CGAL::Lazy_rep<K::Approximate_kernel::Point_3, K::Exact_kernel::Point_3, K::E2A> {
  using Base = CGAL::Lazy_rep<K::Approximate_kernel::Point_3, K::Exact_kernel::Point_3, K::E2A>;
  std::array<Vec3, 5> in_;  // a, b, p, q, r

 public:
  CrossingRep(const K::Approximate_kernel::Point_3& approx, const std::array<Vec3, 5>& in)
      : Base(approx), in_(in) {}
  void update_exact() const override {
    const ExactCrossing e = exact_crossing(in_[0], in_[1], in_[2], in_[3], in_[4]);
    using Q = K::Exact_kernel::FT;
    const Q w(e.w);
    auto* p = new typename Base::Indirect(
        K::Exact_kernel::Point_3(Q(e.x[0]) / w, Q(e.x[1]) / w, Q(e.x[2]) / w));
    this->set_at(p);
    this->set_ptr(p);
  }
};

/// a + (b − a)·dₐ/(dₐ − d_b), d_x = n·(x − p), n = (q − p)×(r − p), in interval arithmetic.
K::Approximate_kernel::Point_3 approximate_crossing(const std::array<Vec3, 5>& in) {
  using I = CGAL::Interval_nt<false>;
  const CGAL::Protect_FPU_rounding<true> rounding;  // Interval_nt<false> needs it set
  auto diff = [](const Vec3& x, const Vec3& y) {
    return std::array<I, 3>{I(x.x) - I(y.x), I(x.y) - I(y.y), I(x.z) - I(y.z)};
  };
  const auto [a, b, p, q, r] = in;
  std::array<I, 3> u = diff(q, p), v = diff(r, p), ap = diff(a, p), bp = diff(b, p);
  const std::array<I, 3> ab = diff(b, a);
  // t is invariant under scaling u, v, ap, bp by one factor: a power of two 2^-e (exact) that
  // brings them to magnitude ≤ 1, so that d_a, d_b (cubic) do not underflow for a tiny
  // triangle (side 1e-200), which would leave t = [0, tiny]/[−tiny, tiny] unbounded.
  double m = 0;
  for (const auto* w : {&u, &v, &ap, &bp})
    for (const I& x : *w) m = std::max({m, std::abs(x.inf()), std::abs(x.sup())});
  if (m > 0 && std::isfinite(m)) {
    const double s = std::ldexp(1.0, -std::ilogb(m));
    for (auto* w : {&u, &v, &ap, &bp})
      for (I& x : *w) x = x * s;
  }
  const std::array<I, 3> n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                           u[0] * v[1] - u[1] * v[0]};
  const I da = n[0] * ap[0] + n[1] * ap[1] + n[2] * ap[2];
  const I db = n[0] * bp[0] + n[1] * bp[1] + n[2] * bp[2];
  const I t = da / (da - db);
  return {I(a.x) + ab[0] * t, I(a.y) + ab[1] * t, I(a.z) + ab[2] * t};
}

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

}  // namespace

/// Tri pairs of different leaves whose closed double boxes meet, sorted: one grid pass over all
/// tris coloured by leaf (mesh/box_pairs.h), cells of one leaf skipped: one pass for all leaves,
/// where CGAL's box intersection would sweep each leaf against the later ones in x-slabs.
namespace {
/// Each tri's double box and its leaf (the colour for box_pairs_between).
void boxes_and_leaves(const std::vector<Tri>& tris, const std::vector<Vec3>& pos,
                      std::vector<Bbox>& boxes, std::vector<uint32_t>& leaf) {
  boxes.assign(tris.size(), Bbox{});
  leaf.resize(tris.size());
  for (size_t i = 0; i < tris.size(); ++i) {
    for (uint32_t v : tris[i].v) boxes[i].add(pos[v]);
    leaf[i] = tris[i].leaf;
  }
}
}  // namespace

std::vector<std::pair<uint32_t, uint32_t>> candidate_pairs(const std::vector<Tri>& tris,
                                                           const std::vector<Vec3>& pos) {
  std::vector<Bbox> boxes;
  std::vector<uint32_t> leaf;
  boxes_and_leaves(tris, pos, boxes, leaf);
  return box_pairs_between(boxes, leaf);
}

std::vector<std::pair<uint32_t, uint32_t>> candidate_pairs_and_self(const std::vector<Tri>& tris,
                                                                    const std::vector<Vec3>& pos,
                                                                    std::vector<uint8_t>& self) {
  std::vector<Bbox> boxes;
  std::vector<uint32_t> leaf;
  boxes_and_leaves(tris, pos, boxes, leaf);
  // Each tri's normal axis once, for tiles_meet's projection filters (a tri is in about seven
  // of the check's pairs, so computing it per pair would repeat the work).
  std::vector<uint8_t> axis(tris.size());
  parallel_for(tris.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i)
      axis[i] = static_cast<uint8_t>(
          normal_axis(pos[tris[i].v[0]], pos[tris[i].v[1]], pos[tris[i].v[2]]));
  });
  // Vertices whose fan within their leaf is a flat star: tris sharing one never meet (the scan
  // drops those pairs itself, so their tris and flags are not read here per pair).
  std::vector<std::array<uint32_t, 3>> corners(tris.size());
  for (size_t i = 0; i < tris.size(); ++i) corners[i] = tris[i].v;
  const std::vector<BoxCorners> marked = marked_corners(corners, star_vertices(corners, leaf, pos));
  // One flag per leaf, set from several threads; a leaf found self-intersecting skips the rest
  // of its pairs.
  std::vector<std::atomic<uint8_t>> found(self.size());
  for (size_t l = 0; l < self.size(); ++l) found[l] = self[l];
  auto pairs = box_pairs_between(boxes, leaf, marked, [&](uint32_t t, uint32_t u) {
    const Tri& a = tris[t];
    const Tri& b = tris[u];
    if (a.face == b.face || found[a.leaf].load(std::memory_order_relaxed)) return;
    if (tiles_meet(a.v, b.v, pos, axis[t], axis[u]))
      found[a.leaf].store(1, std::memory_order_relaxed);
  });
  for (size_t l = 0; l < self.size(); ++l) self[l] = found[l].load();
  return pairs;
}

Point crossing_point(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r) {
  const std::array<Vec3, 5> in{a, b, p, q, r};
  return Point(K::Kernel_base::Point_3(new CrossingRep(approximate_crossing(in), in)));
}

std::vector<Hit> intersect_pairs(const std::vector<Tri>& tris, const std::vector<Vec3>& pos,
                                 const std::vector<std::pair<uint32_t, uint32_t>>& pairs,
                                 std::vector<Point>& points,
                                 std::vector<std::array<uint32_t, 3>>& crossings, size_t grain) {
  // Phase A: exact configuration of every pair (doubles only), and per chunk of pairs the
  // crossings its cuts need.
  const size_t grain_a = grain * 4;
  std::vector<PairCut> cuts(pairs.size());
  std::vector<std::vector<CrossKey>> chunk_keys((pairs.size() + grain_a - 1) / grain_a);
  parallel_for(pairs.size(), grain_a, [&](size_t begin, size_t end) {
    std::vector<CrossKey>& out = chunk_keys[begin / grain_a];
    for (size_t p = begin; p < end; ++p) {
      cuts[p] = cut_pair(tris[pairs[p].first], tris[pairs[p].second], pos);
      if (cuts[p].kind != PairCut::kTransversal) continue;
      for (int e = 0; e < cuts[p].t.n; ++e)
        if (cuts[p].t.end[e].a != cuts[p].t.end[e].b)
          out.push_back({edge_key(cuts[p].t.end[e].a, cuts[p].t.end[e].b), pairs[p].second});
      for (int e = 0; e < cuts[p].u.n; ++e)
        if (cuts[p].u.end[e].a != cuts[p].u.end[e].b)
          out.push_back({edge_key(cuts[p].u.end[e].a, cuts[p].u.end[e].b), pairs[p].first});
    }
  });
  // The crossings needed, each constructed once (key order: deterministic ids). Each half sorted
  // on its own thread, then merged: a serial sort would be a quarter of this step on cheese ∪
  // fandisk.
  std::vector<CrossKey> all;
  for (const auto& c : chunk_keys) all.insert(all.end(), c.begin(), c.end());
  chunk_keys = {};
  const auto mid = all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2);
  parallel_invoke([&] { std::sort(all.begin(), mid); }, [&] { std::sort(mid, all.end()); });
  std::vector<CrossKey> keys(all.size());
  std::merge(all.begin(), mid, mid, all.end(), keys.begin());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  const size_t first_crossing = points.size();
  crossings.resize(keys.size());
  for (size_t x = 0; x < keys.size(); ++x)
    crossings[x] = {static_cast<uint32_t>(keys[x].edge >> 32),
                    static_cast<uint32_t>(keys[x].edge & 0xffffffffu), keys[x].tri};
  // The nodes are made in parallel and handed to their points in one serial pass: assigning them
  // in parallel released default points, which all share one node, from both threads at once
  // (its count's cache line went back and forth: the step took longer on two threads than on
  // one).
  std::vector<CrossingRep*> made(keys.size());
  points.reserve(first_crossing + keys.size());  // before the nodes: the hand-over cannot throw
  parallel_for(keys.size(), grain * 4, [&](size_t begin, size_t end) {
    for (size_t x = begin; x < end; ++x) {
      const uint32_t a = static_cast<uint32_t>(keys[x].edge >> 32),
                     b = static_cast<uint32_t>(keys[x].edge & 0xffffffffu);
      const Tri& w = tris[keys[x].tri];
      const std::array<Vec3, 5> in{pos[a], pos[b], pos[w.v[0]], pos[w.v[1]], pos[w.v[2]]};
      made[x] = new CrossingRep(approximate_crossing(in), in);
    }
  });
  for (CrossingRep* rep : made) points.emplace_back(K::Kernel_base::Point_3(rep));
  // Phase B: the hits.
  std::vector<Hit> hits(pairs.size());
  parallel_for(pairs.size(), grain, [&](size_t begin, size_t end) {
    for (size_t p = begin; p < end; ++p) {
      const auto [t, u] = pairs[p];
      if (cuts[p].kind == PairCut::kCoplanar) {
        hits[p] = coplanar_hit(tris[t], tris[u], points);
      } else if (cuts[p].kind == PairCut::kTransversal) {
        hits[p] = transversal_hit(cuts[p], points, [&](const Sym& s, bool of_t) {
          if (s.a == s.b) return s.a;
          const CrossKey key{edge_key(s.a, s.b), of_t ? u : t};
          return static_cast<uint32_t>(
              first_crossing + (std::lower_bound(keys.begin(), keys.end(), key) - keys.begin()));
        });
      }
    }
  });
  return hits;
}

}  // namespace cover::boolean_detail
