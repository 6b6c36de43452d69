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
//              enough to leave the scene box; only triangles whose float BVH boxes the segment
//              may meet (conservative slab test) are tested, each with exact Epeck predicates.
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
// Membership is the nonzero rule on these windings (CONTRACT.md), so a self-intersecting leaf
// (winding 2 where two of its sheets overlap, 0 inside a hole of a figure-eight) is its
// nonzero-winding set, as in `cover classify`.
// Keep rule (regularized): keep the piece iff E(−) ≠ E(+); oriented as t when E(−) is inside,
// reversed otherwise. Coincident pieces: when a leaf with a lower index, or a tri of t's own leaf
// with a lower index than t, also contains c, those pieces represent the region and this patch
// is dropped (the lowest tri among the coincident ones speaks for all; a solo tri's patches lie
// within it, so the same tris contain every point of such a patch).
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "boolean/detail/arrangement.h"
#include "covering/bvh.h"
#include "covering/detail/bvh_walk.h"
#include "solid/parallel.h"
#include "solid/errors.h"

namespace cover::boolean_detail {
namespace {

/// A Solid whose faces are the arrangement's tris (leaf orientation, sign +1), so the covering
/// BVH over it holds exactly those triangles with face = tri index.
Solid tri_solid(const Solid& solid, const Arrangement& arr) {
  Solid s;
  s.vertices.assign(arr.originals.begin(), arr.originals.end());
  s.leaves.resize(solid.leaves.size());
  s.tree = solid.tree;
  s.face_vertices.reserve(arr.tris.size() * 3);
  for (const Tri& t : arr.tris) {
    s.face_vertices.insert(s.face_vertices.end(), t.v.begin(), t.v.end());
    s.face_start.push_back(static_cast<uint32_t>(s.face_vertices.size()));
    s.face_leaf.push_back(t.leaf);
    s.face_sign.push_back(1);
  }
  return s;
}

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

struct Sides {
  std::vector<int> minus, plus;     ///< winding per leaf on the − / + side of n_t
  std::vector<uint8_t> coincident;  ///< leaf has a triangle containing c
  bool lower_own = false;           ///< a tri of t's leaf with a lower index contains c
};

/// Windings of every leaf on both sides of tri `t` at the exact point c (see notation).
Sides windings(const Arrangement& arr, const Bvh& bvh, size_t leaves, uint32_t t, const Point& c,
               double reach) {
  const Tri& tri = arr.tris[t];
  const Point& ta = arr.points[tri.v[0]];
  const Point& tb = arr.points[tri.v[1]];
  const Point& tc = arr.points[tri.v[2]];
  const K::Vector_3 nt = CGAL::cross_product(tb - ta, tc - ta);
  const double cx = CGAL::to_double(c.x()), cy = CGAL::to_double(c.y()),
               cz = CGAL::to_double(c.z());
  for (const auto& dir : kDirections) {
    const K::Vector_3 d(reach * dir[0], reach * dir[1], reach * dir[2]);
    const CGAL::Sign side = CGAL::sign(d * nt);
    if (side == CGAL::ZERO) continue;
    const Point c2 = c + d;
    std::vector<int> count(leaves, 0), s(leaves, 0);
    std::vector<uint8_t> coincident(leaves, 0);
    bool lower_own = false;
    const double o[3] = {cx, cy, cz};
    const double dd[3] = {reach * dir[0], reach * dir[1], reach * dir[2]};
    // Conservative segment–box test: the box widened by a margin far above the rounding of c.
    auto meets = [&](const Bvh::Node& node) {
      double lo = 0, hi = 1;
      for (int a = 0; a < 3; ++a) {
        const double pad = 1e-7 * (std::abs(node.lo[a]) + std::abs(node.hi[a]) + reach);
        const double t0 = (node.lo[a] - pad - o[a]) / dd[a], t1 = (node.hi[a] + pad - o[a]) / dd[a];
        lo = std::max(lo, std::min(t0, t1));
        hi = std::min(hi, std::max(t0, t1));
      }
      return lo <= hi;
    };
    try {
      walk(bvh, meets, [&](const Bvh::Tri& w, uint32_t) {
        const Tri& wt = arr.tris[w.face];
        const Point& a = arr.points[wt.v[0]];
        const Point& b = arr.points[wt.v[1]];
        const Point& e = arr.points[wt.v[2]];
        const CGAL::Orientation o1 = CGAL::orientation(a, b, e, c);
        const CGAL::Orientation o2 = CGAL::orientation(a, b, e, c2);
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
          s[w.leaf] += sigma == CGAL::POSITIVE ? 1 : -1;
          coincident[w.leaf] = 1;
          lower_own = lower_own || (w.leaf == tri.leaf && w.face < t);
          return;
        }
        if (o2 == CGAL::COPLANAR || o1 == o2) return;
        const CGAL::Orientation s1 = CGAL::orientation(c, c2, a, b);
        const CGAL::Orientation s2 = CGAL::orientation(c, c2, b, e);
        const CGAL::Orientation s3 = CGAL::orientation(c, c2, e, a);
        const bool has_pos = s1 == CGAL::POSITIVE || s2 == CGAL::POSITIVE || s3 == CGAL::POSITIVE;
        const bool has_neg = s1 == CGAL::NEGATIVE || s2 == CGAL::NEGATIVE || s3 == CGAL::NEGATIVE;
        if (has_pos && has_neg) return;  // the line passes beside the triangle
        if (s1 == CGAL::COPLANAR || s2 == CGAL::COPLANAR || s3 == CGAL::COPLANAR)
          throw Degenerate{};  // through an edge or a vertex
        count[w.leaf] += o1 == CGAL::NEGATIVE ? 1 : -1;
      });
    } catch (const Degenerate&) {
      continue;
    }
    Sides r;
    r.coincident = coincident;
    r.lower_own = lower_own;
    r.minus.resize(leaves);
    r.plus.resize(leaves);
    for (size_t l = 0; l < leaves; ++l) {
      // w(+) = w(−) − S
      if (side == CGAL::POSITIVE) {
        r.plus[l] = count[l];
        r.minus[l] = count[l] + s[l];
      } else {
        r.minus[l] = count[l];
        r.plus[l] = count[l] - s[l];
      }
    }
    return r;
  }
  throw InternalError("evaluate: every ray direction was degenerate");
}

}  // namespace

std::vector<std::array<uint32_t, 3>> select_pieces(const Solid& solid, const Arrangement& arr,
                                                   size_t grain, std::vector<uint32_t>& leaves_of,
                                                   size_t& patches) {
  const size_t n = arr.pieces.size();
  // Patches: union pieces of one leaf across non-cut edges.
  std::vector<std::pair<uint64_t, uint32_t>> edges;
  edges.reserve(3 * n);
  for (uint32_t p = 0; p < n; ++p)
    for (int e = 0; e < 3; ++e)
      edges.emplace_back(edge_key(arr.pieces[p].v[e], arr.pieces[p].v[(e + 1) % 3]), p);
  std::sort(edges.begin(), edges.end());
  UnionFind uf(n);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    if (!std::binary_search(arr.cuts.begin(), arr.cuts.end(), edges[i].first))
      for (size_t x = i; x < j; ++x)
        for (size_t y = x + 1; y < j; ++y) {
          const uint32_t px = edges[x].second, py = edges[y].second;
          const uint32_t tx = arr.pieces[px].tri, ty = arr.pieces[py].tri;
          const uint32_t leaf = arr.tris[tx].leaf;
          if (arr.tris[ty].leaf != leaf) continue;
          if (tx != ty && !arr.solo.empty() && (arr.solo[tx] || arr.solo[ty])) continue;
          size_t same = 0;  // pieces of this leaf at the edge: two on one sheet, more across sheets
          for (size_t z = i; z < j; ++z) same += arr.tris[arr.pieces[edges[z].second].tri].leaf == leaf;
          if (same == 2) uf.unite(px, py);
        }
    i = j;
  }
  std::vector<uint32_t> roots;
  std::vector<uint32_t> patch_of(n);
  for (uint32_t p = 0; p < n; ++p) {
    if (uf.find(p) == p) roots.push_back(p);
  }
  patches = roots.size();

  const Solid ts = tri_solid(solid, arr);
  const Bvh bvh(ts);
  const Bbox box = bvh.bounds();
  double reach = 1;
  for (int a = 0; a < 3; ++a) reach = std::max({reach, std::abs(box.min[a]), std::abs(box.max[a])});
  reach *= 8;  // |D| ≥ reach ≥ 4·(scene diameter): c + D leaves the box

  // Decision per patch: 0 drop, 1 keep, 2 keep reversed.
  const size_t leaves = solid.leaves.size();
  std::vector<uint8_t> decision(roots.size(), 0);
  parallel_for(roots.size(), std::max<size_t>(1, grain / 16), [&](size_t begin, size_t end) {
    std::vector<uint8_t> in_minus(leaves), in_plus(leaves);
    for (size_t r = begin; r < end; ++r) {
      const Piece& piece = arr.pieces[roots[r]];
      const Point& p0 = arr.points[piece.v[0]];
      const Point& p1 = arr.points[piece.v[1]];
      const Point& p2 = arr.points[piece.v[2]];
      // Interior points of the piece: barycentric weights (w0, w1, w2)/sum, all positive.
      constexpr int kWeights[][3] = {{1, 1, 1}, {2, 3, 5}, {7, 3, 2}, {3, 11, 5}, {13, 2, 7}};
      Sides sides;
      bool found = false;
      for (const auto& wgt : kWeights) {
        const K::FT sum(wgt[0] + wgt[1] + wgt[2]);
        const Point c = CGAL::ORIGIN +
                        ((p0 - CGAL::ORIGIN) * K::FT(wgt[0]) + (p1 - CGAL::ORIGIN) * K::FT(wgt[1]) +
                         (p2 - CGAL::ORIGIN) * K::FT(wgt[2])) /
                            sum;
        try {
          sides = windings(arr, bvh, leaves, piece.tri, c, reach);
          found = true;
          break;
        } catch (const BadPoint&) {
        }
      }
      if (!found) throw InternalError("evaluate: no usable interior point in a patch");
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
  for (uint32_t p = 0; p < n; ++p) {
    const uint8_t d = decision[patch_of[uf.find(p)]];
    if (d == 0) continue;
    const auto& v = arr.pieces[p].v;
    leaves_of.push_back(arr.tris[arr.pieces[p].tri].leaf);
    kept.push_back(d == 1 ? v : std::array<uint32_t, 3>{v[0], v[2], v[1]});
  }
  return kept;
}

}  // namespace cover::boolean_detail
