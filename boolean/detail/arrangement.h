#pragma once
// Internal to cover_boolean (included by the CGAL translation units only): the exact
// arrangement of the leaves' surfaces.
//
// Notation
//   point id     index into Arrangement::points; [0, originals) are the input vertices
//                deduplicated by exact double value (shared by every leaf), the rest are
//                constructed points (exact, CGAL Epeck).
//   tri          a triangle of one leaf (the leaf faces triangulated by triangulate_face,
//                mesh/triangulate.h: fan when convex in the face's dominant projection, else a
//                constrained triangulation of its loops), vertices in the LEAF's own orientation
//                (outward); collinear ones are dropped.
//   piece        a triangle of the arrangement: a sub-triangle of one tri (the whole tri when no
//                other leaf meets it), same orientation as its tri.
//   cut edge     an edge (point-id pair) lying on an intersection of two leaves' surfaces.
//
// Exactness scheme (constructed points keep every predicate consistent)
//   * Input coordinates are doubles and exact. The configuration of a triangle pair (apart,
//     transversal, coplanar) and which corner / edge of each triangle bounds the intersection are
//     decided by exact orient3d on those doubles (solid/predicates.h), no construction.
//   * Every constructed point is a CGAL Epeck point: a lazy exact rational, evaluated with
//     interval arithmetic and recomputed in exact rationals whenever a sign is uncertain, so every
//     predicate on constructed points is exact. Transversal intersection ends are built
//     canonically — the crossing of edge a–b with the plane of tri w is constructed once per
//     (edge, w) key and shared by every pair that needs it — so the same point reached from the
//     two tris of an edge is one object with one id, and never needs an exact comparison.
//   * Points are then identified by exact VALUE as well, for the points that several
//     constructions can reach (an edge crossing another leaf's edge exactly, a vertex on another
//     leaf's face, triple points made by the per-tri triangulation, coplanar overlaps, which keep
//     CGAL's intersection(Triangle_3, Triangle_3)): equal values merge to the smallest id,
//     candidates found by hashing each point's interval box into a fine grid, then compared
//     exactly. So both sides of every edge see identical split points and the pieces conform.
//   * Per tri, the 2D constrained Delaunay triangulation works in the projection that drops the
//     dominant axis of the tri's normal (an affine bijection of the plane, so 2D intersections
//     are the projections of the 3D ones); points it creates are lifted back onto the tri's
//     plane exactly (X_k = (n·a − n_i X_i − n_j X_j) / n_k).
//   * Output coordinates are the exact values rounded to the nearest double, once, at the end;
//     every decision (classification, angular order at non-manifold edges) is taken on exact
//     values before that.

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "cover/boolean/evaluate.h"
#include "cover/solid/parallel.h"
#include "cover/solid/solid.h"
#include "cover/solid/union_find.h"

namespace cover::boolean_detail {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_3;

inline constexpr uint32_t kNone = 0xffffffffu;

inline uint64_t edge_key(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t{a} << 32) | b : (uint64_t{b} << 32) | a;
}

/// The half-edges h < 3·m of m triangles (h = 3·t + e: edge e of triangle t, from(h) → to(h),
/// point ids < n) grouped by undirected edge, in increasing (p, q) with p < q, each group in
/// increasing h (the order of a stable sort by edge_key), into `order`; `start` is scratch.
/// Used by select_pieces (patches) and assemble (pairing): one counting pass by p
/// (stable, so each bucket is in increasing h), then each bucket sorted by q, stably. A vertex
/// is the smaller end of about three edges, six half-edges: those buckets take an insertion
/// sort; a large one (a pole of many fans) std::stable_sort. One pass moves 4-byte ids once,
/// where sorting (key, h) pairs by q and then by p would write and read 16-byte items twice over
/// arrays of 3·m, mostly fresh pages. The counting runs over kParts fixed parts of the half-edges
/// in parallel (each part's counts per bucket, placed after the earlier parts' in the bucket: the
/// serial order), and the buckets sort in parallel ranges.
template <class From, class To>
void group_half_edges(size_t m, size_t n, From from, To to, std::vector<uint32_t>& order,
                      std::vector<uint32_t>& start) {
  constexpr size_t kParts = 4;
  const uint32_t count = static_cast<uint32_t>(3 * m);
  const uint32_t part = (count + kParts - 1) / kParts;
  // at[k·(n + 1) + a]: part k's first slot in bucket a (its count, before the prefix sums).
  std::vector<uint32_t> at(kParts * (n + 1), 0);
  // visit(slots of part k, h) for every half-edge h of each part k, the parts in parallel.
  auto each_part = [&](auto&& visit) {
    parallel_for(kParts, 1, [&](size_t k0, size_t k1) {
      for (size_t k = k0; k < k1; ++k) {
        const uint32_t end =
            static_cast<uint32_t>(std::min<uint64_t>(count, (k + 1) * uint64_t{part}));
        for (uint32_t h = static_cast<uint32_t>(k * part); h < end; ++h)
          visit(at.data() + k * (n + 1), h);
      }
    });
  };
  each_part([&](uint32_t* c, uint32_t h) { ++c[std::min(from(h), to(h))]; });
  start.assign(n + 1, 0);
  uint32_t sum = 0;
  for (size_t a = 0; a < n; ++a) {
    start[a] = sum;
    for (size_t k = 0; k < kParts; ++k) {
      const uint32_t c = at[k * (n + 1) + a];
      at[k * (n + 1) + a] = sum;
      sum += c;
    }
  }
  start[n] = sum;
  order.resize(count);
  each_part([&](uint32_t* fill, uint32_t h) { order[fill[std::min(from(h), to(h))]++] = h; });
  auto q_of = [&](uint32_t h) { return std::max(from(h), to(h)); };
  parallel_for(n, 4096, [&](size_t a0, size_t a1) {
    for (size_t a = a0; a < a1; ++a) {
      uint32_t* first = order.data() + start[a];
      uint32_t* last = order.data() + start[a + 1];
      if (last - first > 32) {
        std::stable_sort(first, last, [&](uint32_t x, uint32_t y) { return q_of(x) < q_of(y); });
        continue;
      }
      for (uint32_t* i = first + 1; i < last; ++i) {
        const uint32_t h = *i, q = q_of(h);
        uint32_t* j = i;
        for (; j > first && q_of(*(j - 1)) > q; --j) *j = *(j - 1);
        *j = h;
      }
    }
  });
}

struct Tri {
  std::array<uint32_t, 3> v;  ///< point ids (originals), leaf orientation
  uint32_t leaf = 0;
  uint32_t face = 0;  ///< the solid's face it tiles
};

struct Piece {
  std::array<uint32_t, 3> v;  ///< point ids, orientation of its tri
  uint32_t tri = 0;
};

struct Arrangement {
  std::vector<Point> points;    ///< exact points (see notation)
  std::vector<Vec3> originals;  ///< the input vertices' doubles, points[i] == originals[i]
  std::vector<Tri> tris;        ///< grouped by leaf, leaves in order
  std::vector<Piece> pieces;    ///< in tri order
  std::vector<uint64_t> cuts;   ///< sorted, unique edge keys of cut edges
  /// Points [first_crossing, first_crossing + crossings.size()) are edge × plane crossings:
  /// {a, b, tri}, the crossing of line a–b with the plane of tris[tri] (all input vertices), so
  /// that assemble() rounds them from the input doubles (round_crossing, assemble.cpp).
  uint32_t first_crossing = 0;
  std::vector<std::array<uint32_t, 3>> crossings;
  std::vector<uint8_t> solo;      ///< per tri: overlaps a coplanar tri of its own leaf (its
                                  ///< pieces form patches of their own, select.cpp)
  size_t candidate_pairs = 0;     ///< tri pairs with meeting boxes (different leaves, and
                                  ///< same-leaf pairs of self-intersecting leaves)
  size_t intersecting_pairs = 0;  ///< pairs whose triangles meet
};

/// Steps 1–3 of evaluate(): triangulation, exact pairwise intersections, per-tri constrained
/// triangulations, global point identity. Deterministic for any thread count. With
/// `check_leaves`, `self` gets one flag per leaf: set when the leaf intersects itself (a tile
/// pair of different faces meeting by self_intersects()' rules, mesh/validate.h, tested in the
/// same grid pass as the candidate pairs, or a face that does not tile simply); such leaves also
/// have their own tri pairs intersected (self_pairs.cpp). Without it `self` is left empty (no
/// leaf intersects itself, by the caller's word). Throws InputError naming the leaf and face
/// when a face's boundary crosses itself. `seconds` gets the check, triangulate, pairs,
/// intersect, split and identify times.
Arrangement build_arrangement(const Solid& solid, bool check_leaves, size_t grain,
                              EvaluatePhases& seconds, std::vector<uint8_t>& self);

/// Steps 4–5: patches, exact classification, the regularized keep rule and de-duplication of
/// coincident pieces. Returns the kept triangles (point ids), oriented outward; `leaves` gets
/// the leaf of each (the leaf of its tri), `patches` the number of classified patches, and
/// `grouped` the kept triangles' half-edges h = 3·f + e (edge e of kept triangle f) in
/// group_half_edges' order: the pieces' grouping, which this step makes, filtered to the kept
/// ones (what group_half_edges over the kept triangles gives, without grouping them again).
std::vector<std::array<uint32_t, 3>> select_pieces(const Solid& solid, const Arrangement& arr,
                                                   size_t grain, std::vector<uint32_t>& leaves,
                                                   size_t& patches, std::vector<uint32_t>& grouped);

/// The exact volume enclosed by the kept triangles `tris` (outward) on the exact points, as
/// Σ det(a, b, c)/6 in rationals, rounded to the nearest double once.
double exact_volume(const Arrangement& arr, const std::vector<std::array<uint32_t, 3>>& tris);

/// The crossing of line a–b with the plane of (p, q, r) (input doubles) in exact homogeneous
/// coordinates X = x / w: with d_v = ((q − p) × (r − p)) · (v − p), x = b·d_a − a·d_b and
/// w = d_a − d_b (0 when the line does not cross the plane). Sums of products of doubles, exact
/// in CGAL::Mpzf (a binary float with an unbounded mantissa: no division, no gcd, no
/// allocation for short numbers), unlike the lazy point's exact value (GMP rationals over its
/// construction DAG, a gcd per operation).
struct ExactCrossing {
  std::array<CGAL::Mpzf, 3> x;
  CGAL::Mpzf w;
};
ExactCrossing exact_crossing(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q,
                             const Vec3& r);

/// The exact crossing of line a–b with the plane of (p, q, r) (input doubles; the line crosses
/// the plane) as one lazy-kernel node: interval approximation from the doubles, exact value on
/// demand from exact_crossing (intersect.cpp). Equal to a + (b − a)·dₐ/(dₐ − d_b) built with the
/// kernel's operators, without that expression's dozen nodes.
Point crossing_point(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r);

/// The crossing of line a–b with the plane of (p, q, r) (input doubles; the line crosses the
/// plane), each coordinate rounded to the nearest double (ties to even) from the doubles, in
/// exact CGAL::Mpzf arithmetic; `box` is an interval box of the exact point (its lazy
/// approximation). False when it cannot decide cheaply (box not finite or wide): then the
/// caller rounds the exact rational. Used by assemble().
bool round_crossing(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r,
                    const K::Approximate_kernel::Point_3& box, Vec3& out);

/// Step 6: pairs faces around edges with more than two faces by exact angular order, splits
/// vertices per fan, rounds the exact points to the nearest doubles. Face f of the mesh is
/// tris[f], except that faces split at a doubled edge append their second halves at the end;
/// `labels` (one per tri, when given) gets their labels appended likewise. `rounded_vertex`
/// (when given) gets one flag per output vertex: set where its coordinates were rounded (a
/// constructed point or a midpoint), not an input vertex's own doubles. `grouped` (when given):
/// the half-edges of `tris` in group_half_edges' order (select_pieces makes it).
PolygonMesh assemble(const Arrangement& arr, const std::vector<std::array<uint32_t, 3>>& tris,
                     std::vector<uint32_t>* labels = nullptr,
                     std::vector<uint8_t>* rounded_vertex = nullptr,
                     const std::vector<uint32_t>* grouped = nullptr);

}  // namespace cover::boolean_detail
