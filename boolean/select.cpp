// Steps 4–5 of evaluate() (boolean/evaluate.h): patches, exact classification, keep rule.
//
// Notation
//   patch      pieces of one leaf connected across edges that are not cut edges, where exactly
//              two pieces of that leaf meet (at a non-manifold edge of a self-intersecting leaf
//              the sheets stay apart), and, for a solo tri (one overlapping a coplanar tri of its
//              own leaf), only within that tri; no surface — of another leaf or, for a
//              self-intersecting leaf, of its own — crosses a patch, so each leaf's winding
//              number on either side of the patch is constant over it.
//   c          the exact centroid of the patch's first piece (interior to that piece, so on no
//              cut edge); t its tri, n_t the tri's outward normal; sides −/+ of n_t are the
//              tri's inner / outer side.
//   ray        c + s·D, s ∈ (0, 1], D one of a fixed list of generic double directions, long
//              enough to leave the scene box. All patches' rays are shot in one batch per
//              direction: one pass over the tris projects each along D (doubles, boxes widened
//              far above the rounding) and finds the rays whose projected origins its box holds
//              (a grid over those origins); only those tri–ray pairs are tested, each with exact
//              Epeck predicates. (A BVH over all tris cost 10× the rays themselves: a scene has
//              few patches, hundreds against 10⁵–10⁶ tris.)
//
// Winding numbers at both sides (nonzero rule per leaf, then the CSG tree):
//   * a triangle containing c is coplanar with t (any other would cross t through c, making an
//     intersection segment through the piece's interior); it contributes σ = ±1 (same /
//     opposite orientation as t) to S_L of its leaf L: w_L(+) = w_L(−) − S_L. Tri t itself is one.
//   * every other triangle crossed by the ray adds +1 when the ray leaves through it (c on its
//     negative side), −1 when it enters: this is w_L on the side of t that D points to.
//   * exact degeneracies — the ray through a triangle's edge or vertex, D parallel to t, the
//     segment lying in a triangle's plane — re-shoot with the next direction; c on the edge of a
//     containing triangle (possible only where a coplanar face of another leaf is non-convex and
//     its tiling differs) retries with another interior point of the piece.
// Membership is the nonzero rule on these windings (docs/cli.md#semantics), so a
// self-intersecting leaf (winding 2 where two of its sheets overlap, 0 inside a hole of a
// figure-eight) is its nonzero-winding set, as in `cover classify`.
// Keep rule (regularized): keep the piece iff E(−) ≠ E(+); oriented as t when E(−) is inside,
// reversed otherwise. Coincident pieces: when a leaf with a lower index, or a tri of t's own leaf
// with a lower index than t, also contains c, those pieces represent the region and this patch
// is dropped (the lowest tri among the coincident ones speaks for all; a solo tri's patches lie
// within it, so the same tris contain every point of such a patch).
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cover/boolean/detail/arrangement.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover::boolean_detail {
namespace {

struct Degenerate {};  // the ray met an edge / vertex / plane exactly: re-shoot
struct BadPoint {};    // c lies on the boundary of a coplanar triangle: take another point

constexpr double kDirections[][3] = {
    {1.0, 0.3183098861837907, 0.1428571428571429},
    {-0.2718281828459045, 1.0, -0.5772156649015329},
    {0.4142135623730951, -0.7071067811865476, 1.0},
    {-1.0, -0.1618033988749895, 0.2236067977499790},
    {0.3010299956639812, 0.4771212547196624, -1.0},
    {-0.6931471805599453, -1.0, -0.0909090909090909},
    {0.5403023058681398, 0.8414709848078965, 0.1732050807568877},
    {-0.1234567890123457, 0.9876543210987654, -0.3333333333333333},
};
constexpr int kDirectionCount = sizeof kDirections / sizeof kDirections[0];

/// Interior points of a piece: barycentric weights (w0, w1, w2)/sum, all positive.
constexpr int kWeights[][3] = {{1, 1, 1}, {2, 3, 5}, {7, 3, 2}, {3, 11, 5}, {13, 2, 7}};
constexpr int kWeightCount = sizeof kWeights / sizeof kWeights[0];

struct Sides {
  std::vector<int> minus, plus;     ///< winding per leaf on the − / + side of n_t
  std::vector<uint8_t> coincident;  ///< leaf has a triangle containing c
  bool lower_own = false;           ///< a tri of t's leaf with a lower index contains c
};

/// One ray of the batch: patch `root`'s piece, its interior point number `weight`, direction
/// number `dir`; c, c2 = c + D and the side of n_t that D points to.
struct Query {
  uint32_t root = 0;
  uint8_t weight = 0, dir = 0;
  Point c, c2;
  CGAL::Sign side = CGAL::ZERO;
  double o[3] = {0, 0, 0};  ///< c rounded
};

/// Adds tri w's contribution to the ray c → c2 of a point c on tri t (normal nt) to the counts
/// (see notation); throws Degenerate / BadPoint.
void ray_test(const Arrangement& arr, uint32_t w, const Query& q, const K::Vector_3& nt, uint32_t t,
              std::vector<int>& count, std::vector<int>& s, std::vector<uint8_t>& coincident,
              bool& lower_own) {
  const Tri& wt = arr.tris[w];
  const Point& a = arr.points[wt.v[0]];
  const Point& b = arr.points[wt.v[1]];
  const Point& e = arr.points[wt.v[2]];
  const Point& c = q.c;
  const CGAL::Orientation o1 = CGAL::orientation(a, b, e, c);
  const CGAL::Orientation o2 = CGAL::orientation(a, b, e, q.c2);
  if (o1 == CGAL::COPLANAR) {
    if (o2 == CGAL::COPLANAR) {
      if (K::Triangle_3(a, b, e).has_on(c)) throw BadPoint{};
      throw Degenerate{};  // D lies in the plane: cannot tell
    }
    const K::Triangle_3 tw(a, b, e);
    if (!tw.has_on(c)) return;
    // c inside or on the boundary of w: interior only is usable.
    if (CGAL::collinear(a, b, c) || CGAL::collinear(b, e, c) || CGAL::collinear(e, a, c))
      throw BadPoint{};
    const CGAL::Sign sigma = CGAL::sign(CGAL::cross_product(b - a, e - a) * nt);
    s[wt.leaf] += sigma == CGAL::POSITIVE ? 1 : -1;
    coincident[wt.leaf] = 1;
    lower_own = lower_own || (wt.leaf == arr.tris[t].leaf && w < t);
    return;
  }
  if (o2 == CGAL::COPLANAR || o1 == o2) return;
  const CGAL::Orientation s1 = CGAL::orientation(c, q.c2, a, b);
  const CGAL::Orientation s2 = CGAL::orientation(c, q.c2, b, e);
  const CGAL::Orientation s3 = CGAL::orientation(c, q.c2, e, a);
  const bool has_pos = s1 == CGAL::POSITIVE || s2 == CGAL::POSITIVE || s3 == CGAL::POSITIVE;
  const bool has_neg = s1 == CGAL::NEGATIVE || s2 == CGAL::NEGATIVE || s3 == CGAL::NEGATIVE;
  if (has_pos && has_neg) return;  // the line passes beside the triangle
  if (s1 == CGAL::COPLANAR || s2 == CGAL::COPLANAR || s3 == CGAL::COPLANAR)
    throw Degenerate{};  // through an edge or a vertex
  count[wt.leaf] += o1 == CGAL::NEGATIVE ? 1 : -1;
}

/// The tris each ray of `qs` (all with direction `dir`) may meet, as (query, tri) pairs sorted:
/// a conservative filter in doubles — tri and ray projected along D onto a plane orthogonal to
/// it, boxes widened by `pad` (far above the rounding of the projections) — over one pass of all
/// tris, the rays bucketed in a grid of their projected points.
std::vector<std::pair<uint32_t, uint32_t>> ray_candidates(const Arrangement& arr,
                                                          const std::vector<Query>& qs,
                                                          const std::vector<uint32_t>& members,
                                                          int dir, double reach, size_t grain) {
  const double* d0 = kDirections[dir];
  const double dn = std::sqrt(d0[0] * d0[0] + d0[1] * d0[1] + d0[2] * d0[2]);
  const double D[3] = {d0[0] / dn, d0[1] / dn, d0[2] / dn};
  const int k = std::abs(D[0]) < std::abs(D[1]) ? (std::abs(D[0]) < std::abs(D[2]) ? 0 : 2)
                                                : (std::abs(D[1]) < std::abs(D[2]) ? 1 : 2);
  double U[3] = {0, 0, 0};  // U = normalize(D × e_k), V = D × U
  U[(k + 1) % 3] = D[(k + 2) % 3];
  U[(k + 2) % 3] = -D[(k + 1) % 3];
  const double un = std::sqrt(U[0] * U[0] + U[1] * U[1] + U[2] * U[2]);
  for (double& x : U) x /= un;
  const double V[3] = {D[1] * U[2] - D[2] * U[1], D[2] * U[0] - D[0] * U[2],
                       D[0] * U[1] - D[1] * U[0]};
  auto dot = [](const double* a, const double* b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  const double length = reach * dn, pad = 1e-7 * reach;
  // Rays: projected origin (u, v) and extent [d, d + length] along D; a grid over (u, v).
  const size_t m = members.size();
  std::vector<double> ru(m), rv(m), rd(m);
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (size_t i = 0; i < m; ++i) {
    const double* o = qs[members[i]].o;
    ru[i] = dot(o, U), rv[i] = dot(o, V), rd[i] = dot(o, D);
    lo[0] = std::min(lo[0], ru[i]), hi[0] = std::max(hi[0], ru[i]);
    lo[1] = std::min(lo[1], rv[i]), hi[1] = std::max(hi[1], rv[i]);
  }
  const int g = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(m))), 1, 256);
  const double cu = std::max((hi[0] - lo[0]) / g, 1e-300),
               cv = std::max((hi[1] - lo[1]) / g, 1e-300);
  // The cell of coordinate x, clamped in doubles before the conversion: a tri box widened by
  // `pad` reaches far beyond a grid over tiny rays (a feature 1e-20 wide), where the quotient
  // overflows an int.
  auto cell = [&](double x, double l, double w) {
    return static_cast<int>(std::clamp(std::floor((x - l) / w), 0.0, static_cast<double>(g - 1)));
  };
  std::vector<uint32_t> start(static_cast<size_t>(g) * g + 1, 0), order(m);
  for (size_t i = 0; i < m; ++i) ++start[cell(ru[i], lo[0], cu) * g + cell(rv[i], lo[1], cv) + 1];
  for (size_t x = 1; x < start.size(); ++x) start[x] += start[x - 1];
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < m; ++i)
      order[fill[cell(ru[i], lo[0], cu) * g + cell(rv[i], lo[1], cv)]++] = static_cast<uint32_t>(i);
  }
  const size_t n = arr.tris.size(), chunk = grain * 64;
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> found((n + chunk - 1) / chunk);
  parallel_for(found.size(), 1, [&](size_t c0, size_t c1) {
    for (size_t c = c0; c < c1; ++c)
      for (size_t t = c * chunk; t < std::min(n, (c + 1) * chunk); ++t) {
        double bl[3] = {INFINITY, INFINITY, INFINITY}, bh[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t v : arr.tris[t].v) {
          const Vec3& p = arr.originals[v];
          const double xyz[3] = {p.x, p.y, p.z};
          const double pr[3] = {dot(xyz, U), dot(xyz, V), dot(xyz, D)};
          for (int a = 0; a < 3; ++a)
            bl[a] = std::min(bl[a], pr[a]), bh[a] = std::max(bh[a], pr[a]);
        }
        for (double& x : bl) x -= pad;
        for (double& x : bh) x += pad;
        if (bh[0] < lo[0] || bl[0] > hi[0] || bh[1] < lo[1] || bl[1] > hi[1]) continue;
        const int i0 = cell(bl[0], lo[0], cu), i1 = cell(bh[0], lo[0], cu);
        const int j0 = cell(bl[1], lo[1], cv), j1 = cell(bh[1], lo[1], cv);
        for (int i = i0; i <= i1; ++i)
          for (int j = j0; j <= j1; ++j)
            for (uint32_t x = start[i * g + j]; x < start[i * g + j + 1]; ++x) {
              const uint32_t r = order[x];
              if (ru[r] < bl[0] || ru[r] > bh[0] || rv[r] < bl[1] || rv[r] > bh[1]) continue;
              if (bh[2] < rd[r] || bl[2] > rd[r] + length) continue;
              found[c].emplace_back(members[r], static_cast<uint32_t>(t));
            }
      }
  });
  std::vector<std::pair<uint32_t, uint32_t>> out;
  for (const auto& f : found) out.insert(out.end(), f.begin(), f.end());
  std::sort(out.begin(), out.end());
  return out;
}

/// Windings of every leaf on both sides of each root piece's tri at an exact interior point
/// (see notation): all rays of a round in one batch per direction; a ray that meets an edge, a
/// vertex or a plane exactly is shot again in the next direction, a point on the boundary of a
/// coplanar triangle is replaced by the next interior point. Deterministic (tri order).
std::vector<Sides> batch_windings(const Arrangement& arr, const std::vector<uint32_t>& roots,
                                  size_t leaves, double reach, size_t grain) {
  std::vector<Sides> out(roots.size());
  std::vector<Query> qs(roots.size());
  for (uint32_t r = 0; r < roots.size(); ++r) qs[r].root = r;
  std::vector<uint32_t> pending(roots.size());
  for (uint32_t r = 0; r < roots.size(); ++r) pending[r] = r;
  // Sets c, c2 and side for q's weight and direction, skipping directions parallel to t.
  auto prepare = [&](Query& q) {
    const Piece& piece = arr.pieces[roots[q.root]];
    const Tri& tri = arr.tris[piece.tri];
    const K::Vector_3 nt = CGAL::cross_product(arr.points[tri.v[1]] - arr.points[tri.v[0]],
                                               arr.points[tri.v[2]] - arr.points[tri.v[0]]);
    const auto& wgt = kWeights[q.weight];
    const Point& p0 = arr.points[piece.v[0]];
    const Point& p1 = arr.points[piece.v[1]];
    const Point& p2 = arr.points[piece.v[2]];
    q.c =
        CGAL::ORIGIN + ((p0 - CGAL::ORIGIN) * K::FT(wgt[0]) + (p1 - CGAL::ORIGIN) * K::FT(wgt[1]) +
                        (p2 - CGAL::ORIGIN) * K::FT(wgt[2])) /
                           K::FT(wgt[0] + wgt[1] + wgt[2]);
    q.o[0] = CGAL::to_double(q.c.x()), q.o[1] = CGAL::to_double(q.c.y());
    q.o[2] = CGAL::to_double(q.c.z());
    for (; q.dir < kDirectionCount; ++q.dir) {
      const double* dir = kDirections[q.dir];
      const K::Vector_3 d(reach * dir[0], reach * dir[1], reach * dir[2]);
      q.side = CGAL::sign(d * nt);
      if (q.side == CGAL::ZERO) continue;
      q.c2 = q.c + d;
      return;
    }
    throw InternalError("evaluate: every ray direction was degenerate");
  };
  parallel_for(pending.size(), std::max<size_t>(1, grain / 16), [&](size_t b, size_t e) {
    for (size_t x = b; x < e; ++x) prepare(qs[pending[x]]);
  });
  while (!pending.empty()) {
    std::vector<std::pair<uint32_t, uint32_t>> cand;
    for (int dir = 0; dir < kDirectionCount; ++dir) {
      std::vector<uint32_t> members;
      for (uint32_t r : pending)
        if (qs[r].dir == dir) members.push_back(r);
      if (members.empty()) continue;
      const auto c = ray_candidates(arr, qs, members, dir, reach, grain);
      cand.insert(cand.end(), c.begin(), c.end());
    }
    std::sort(cand.begin(), cand.end());
    // 0: done; 1: next direction; 2: next interior point.
    std::vector<uint8_t> outcome(pending.size(), 0);
    parallel_for(pending.size(), std::max<size_t>(1, grain / 16), [&](size_t b, size_t e) {
      std::vector<int> count, s;
      std::vector<uint8_t> coincident;
      for (size_t x = b; x < e; ++x) {
        const Query& q = qs[pending[x]];
        const uint32_t t = arr.pieces[roots[q.root]].tri;
        const Tri& tri = arr.tris[t];
        bool lower_own = false;
        const K::Vector_3 nt = CGAL::cross_product(arr.points[tri.v[1]] - arr.points[tri.v[0]],
                                                   arr.points[tri.v[2]] - arr.points[tri.v[0]]);
        count.assign(leaves, 0), s.assign(leaves, 0), coincident.assign(leaves, 0);
        auto it =
            std::lower_bound(cand.begin(), cand.end(), std::pair<uint32_t, uint32_t>{q.root, 0});
        try {
          for (; it != cand.end() && it->first == q.root; ++it)
            ray_test(arr, it->second, q, nt, t, count, s, coincident, lower_own);
        } catch (const Degenerate&) {
          outcome[x] = 1;
          continue;
        } catch (const BadPoint&) {
          outcome[x] = 2;
          continue;
        }
        Sides& r = out[q.root];
        r.coincident = coincident;
        r.lower_own = lower_own;
        r.minus.resize(leaves);
        r.plus.resize(leaves);
        for (size_t l = 0; l < leaves; ++l) {
          // w(+) = w(−) − S
          if (q.side == CGAL::POSITIVE) {
            r.plus[l] = count[l];
            r.minus[l] = count[l] + s[l];
          } else {
            r.minus[l] = count[l];
            r.plus[l] = count[l] - s[l];
          }
        }
      }
    });
    std::vector<uint32_t> again;
    for (size_t x = 0; x < pending.size(); ++x) {
      if (outcome[x] == 0) continue;
      Query& q = qs[pending[x]];
      if (outcome[x] == 1) {
        ++q.dir;
      } else {
        if (++q.weight == kWeightCount)
          throw InternalError("evaluate: no usable interior point in a patch");
        q.dir = 0;
      }
      if (q.dir == kDirectionCount)
        throw InternalError("evaluate: every ray direction was degenerate");
      again.push_back(pending[x]);
    }
    parallel_for(again.size(), 1, [&](size_t b, size_t e) {
      for (size_t x = b; x < e; ++x) prepare(qs[again[x]]);
    });
    pending = std::move(again);
  }
  return out;
}

}  // namespace

std::vector<std::array<uint32_t, 3>> select_pieces(const Solid& solid, const Arrangement& arr,
                                                   size_t grain, std::vector<uint32_t>& leaves_of,
                                                   size_t& patches,
                                                   std::vector<uint32_t>& grouped) {
  const size_t n = arr.pieces.size();
  // Patches: union pieces of one leaf across non-cut edges (their half-edges grouped by edge,
  // group_half_edges: linear, where sorting all 3n (edge, piece) pairs cost most of this step
  // on large scenes).
  auto from = [&](uint32_t h) { return arr.pieces[h / 3].v[h % 3]; };
  auto to = [&](uint32_t h) { return arr.pieces[h / 3].v[(h % 3 + 1) % 3]; };
  std::vector<uint32_t> hs, scratch;
  group_half_edges(n, arr.points.size(), from, to, hs, scratch);
  UnionFind uf(n);
  // Edges come in increasing key, as arr.cuts is sorted: one walk through the cuts instead of
  // a search per edge.
  size_t next_cut = 0;
  for (size_t i = 0, j; i < hs.size(); i = j) {
    const uint64_t key = edge_key(from(hs[i]), to(hs[i]));
    for (j = i + 1; j < hs.size() && edge_key(from(hs[j]), to(hs[j])) == key;) ++j;
    while (next_cut < arr.cuts.size() && arr.cuts[next_cut] < key) ++next_cut;
    if (next_cut < arr.cuts.size() && arr.cuts[next_cut] == key) continue;
    for (size_t x = i; x != j; ++x)
      for (size_t y = x + 1; y != j; ++y) {
        const uint32_t px = hs[x] / 3, py = hs[y] / 3;
        const uint32_t tx = arr.pieces[px].tri, ty = arr.pieces[py].tri;
        const uint32_t leaf = arr.tris[tx].leaf;
        if (arr.tris[ty].leaf != leaf) continue;
        if (tx != ty && !arr.solo.empty() && (arr.solo[tx] || arr.solo[ty])) continue;
        size_t same = 0;  // pieces of this leaf at the edge: two on one sheet, more across sheets
        for (size_t z = i; z != j; ++z) same += arr.tris[arr.pieces[hs[z] / 3].tri].leaf == leaf;
        if (same == 2) uf.unite(px, py);
      }
  }
  std::vector<uint32_t> roots;
  std::vector<uint32_t> patch_of(n);
  for (uint32_t p = 0; p < n; ++p) {
    if (uf.find(p) == p) roots.push_back(p);
  }
  patches = roots.size();

  double reach = 1;
  for (const Vec3& p : arr.originals)
    reach = std::max({reach, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  reach *= 8;  // |D| ≥ reach ≥ 4·(scene diameter): c + D leaves the box

  // Decision per patch: 0 drop, 1 keep, 2 keep reversed.
  const size_t leaves = solid.leaves.size();
  const std::vector<Sides> all = batch_windings(arr, roots, leaves, reach, grain);
  std::vector<uint8_t> decision(roots.size(), 0);
  parallel_for(roots.size(), std::max<size_t>(1, grain / 16), [&](size_t begin, size_t end) {
    std::vector<uint8_t> in_minus(leaves), in_plus(leaves);
    for (size_t r = begin; r < end; ++r) {
      const Piece& piece = arr.pieces[roots[r]];
      const Sides& sides = all[r];
      const uint32_t leaf = arr.tris[piece.tri].leaf;
      bool lower = false;
      for (size_t l = 0; l < leaf; ++l) lower = lower || sides.coincident[l];
      if (lower || sides.lower_own) continue;
      for (size_t l = 0; l < leaves; ++l) {
        in_minus[l] = sides.minus[l] != 0;
        in_plus[l] = sides.plus[l] != 0;
      }
      const bool e_minus = solid.tree.evaluate(in_minus), e_plus = solid.tree.evaluate(in_plus);
      if (e_minus != e_plus) decision[r] = e_minus ? 1 : 2;
    }
  });
  for (size_t r = 0; r < roots.size(); ++r) patch_of[roots[r]] = static_cast<uint32_t>(r);
  std::vector<std::array<uint32_t, 3>> kept;
  leaves_of.clear();
  std::vector<uint32_t> kept_as(n, kNone);  // per piece: 2·(its kept index) + reversed, or kNone
  for (uint32_t p = 0; p < n; ++p) {
    const uint8_t d = decision[patch_of[uf.find(p)]];
    if (d == 0) continue;
    const auto& v = arr.pieces[p].v;
    kept_as[p] = 2 * static_cast<uint32_t>(kept.size()) + (d == 2);
    leaves_of.push_back(arr.tris[arr.pieces[p].tri].leaf);
    kept.push_back(d == 1 ? v : std::array<uint32_t, 3>{v[0], v[2], v[1]});
  }
  // The kept half-edges in the pieces' grouping order. Kept indices increase with the pieces', a
  // piece has one half-edge per edge, and a reversed piece (v0, v2, v1) has its edge e at
  // 2 − e: the order group_half_edges gives over the kept triangles (stable within an edge).
  grouped.clear();
  grouped.reserve(3 * kept.size());
  for (uint32_t h : hs) {
    const uint32_t k = kept_as[h / 3];
    if (k == kNone) continue;
    grouped.push_back(3 * (k >> 1) + (k & 1 ? 2 - h % 3 : h % 3));
  }
  return kept;
}

}  // namespace cover::boolean_detail
