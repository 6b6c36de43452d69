#pragma once
// Internal to the translation units of build_arrangement() (boolean/detail/arrangement.h):
// what one step hands the next.
//   arrangement.cpp  step 1 (leaf triangulation), point identity by value, the driver
//   intersect.cpp    step 2 (candidate pairs, exact pairwise intersections)
//   split.cpp        step 3 (per-tri re-triangulation)
// Notation
//   t, u        tris of different leaves whose closed double boxes meet (candidate pair)
//   hit         the exact intersection t ∩ u: nothing, a point, a segment, or (coplanar) the
//               overlap polygon, whose boundary segments become constraints of both t and u
//   local ids   per tri: 0..2 are its corners, then constraint endpoints and points created by
//               the triangulation (constraint crossings), in insertion order

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "cover/boolean/detail/arrangement.h"

namespace cover::boolean_detail {

/// Where a point of tri t lies on t: kCorner + i (corner i), kEdge + i (on the open edge from
/// corner i to corner i + 1), kInside (the open triangle), kUnknown (not established).
enum : uint8_t { kCorner = 0, kEdge = 3, kInside = 6, kUnknown = 7 };

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

/// Step 2: tri pairs (t < u) of different leaves whose closed double boxes meet, sorted.
/// Precondition: tris grouped by leaf, leaves in increasing order.
std::vector<std::pair<uint32_t, uint32_t>> candidate_pairs(const std::vector<Tri>& tris,
                                                           const std::vector<Vec3>& pos);

/// candidate_pairs(), and in the same grid pass the leaf self-intersection test: self[l] (one
/// flag per leaf, already set for leaves known to intersect themselves) is set when two tris of
/// leaf l from different faces meet by self_intersects()' rules (mesh/validate.h: tiles_meet,
/// exact). Shared vertices are decided by point id, i.e. by exact value.
std::vector<std::pair<uint32_t, uint32_t>> candidate_pairs_and_self(const std::vector<Tri>& tris,
                                                                    const std::vector<Vec3>& pos,
                                                                    std::vector<uint8_t>& self);

/// Step 2: the exact hit of every candidate pair (in pair order). `points` holds the input
/// vertices (ids as in tris) and gets the edge–plane crossings the hits refer to appended, each
/// constructed once; `crossings` gets {a, b, tri} for each of them, in the same order.
/// Deterministic for any thread count.
std::vector<Hit> intersect_pairs(const std::vector<Tri>& tris, const std::vector<Vec3>& pos,
                                 const std::vector<std::pair<uint32_t, uint32_t>>& pairs,
                                 std::vector<Point>& points,
                                 std::vector<std::array<uint32_t, 3>>& crossings, size_t grain);

/// Step 2 for self-intersecting leaves (self_pairs.cpp): tri pairs (t < u) of one leaf l with
/// self[l] set whose closed double boxes meet, less those sharing an edge whose planes differ
/// (they meet exactly in that edge), sorted.
std::vector<std::pair<uint32_t, uint32_t>> same_leaf_pairs(const std::vector<Tri>& tris,
                                                           const std::vector<Vec3>& pos,
                                                           const std::vector<uint8_t>& self);

/// Clears the hits of same-leaf pairs that are only the pair's shared vertices / shared edge.
void drop_shared(const std::vector<Tri>& tris,
                 const std::vector<std::pair<uint32_t, uint32_t>>& pairs,
                 const std::vector<Point>& points, std::vector<Hit>& hits);

/// Step 3's result for one tri.
struct Local {
  std::vector<uint32_t> ids;  ///< per local point: its point id, kNone when only its value is known
  std::vector<Point> points;  ///< values of the local points with ids[q] == kNone (in order)
  std::vector<std::array<uint32_t, 3>> tris;        ///< local ids, the tri's orientation
  std::vector<std::pair<uint32_t, uint32_t>> cuts;  ///< local id pairs on intersections
};

/// One hit as seen from its tri: the ends' ids and positions on this tri.
struct TriHit {
  const Hit* hit;
  bool first;      ///< this tri is the pair's t
  uint32_t other;  ///< the pair's other tri
  uint32_t id(int e) const { return hit->ends[e].id; }
  uint8_t on(int e) const { return first ? hit->ends[e].on_t : hit->ends[e].on_u; }
};

/// Step 3: the pieces of one intersected tri (its hits in pair order) and the cut edges among
/// them, in local ids. `arr` holds the points, tris and crossings built so far; `self` (as for
/// build_arrangement) tells whether a hit's other leaf intersects itself.
Local split_tri(const Tri& tri, const std::vector<TriHit>& hits, const Arrangement& arr,
                const std::vector<uint8_t>& self);

}  // namespace cover::boolean_detail
