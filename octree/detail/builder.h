#pragma once
// The octree builder (octree.cpp): one class whose phases live in one file each, as the
// notation below names them: (A) the triangles meeting each cell (meet.cpp), (B) the points to
// classify and their sharing (represent.cpp), (C)–(D) classification, states and child links,
// and the level loop (octree.cpp). Internal to octree/, not installed.

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/covering/gwn.h"
#include "cover/octree/detail/box_overlap.h"
#include "cover/octree/octree.h"
#include "cover/solid/large_vector.h"

// Notation
//   D        maximum depth; h = size/2^D the finest cell size. Grid plane m (0 ≤ m ≤ 2^D) of axis a
//            is the double bounds.min[a] + m·h, the same for every level, so children tile their
//            parent exactly.
//   coord    integer corner (i, j, k) of a cell at depth d: it spans planes i·2^(D−d) ..
//            (i+1)·2^(D−d) along x, and so on.
//   T_C      the covering triangles that meet the interior of cell C (exact); C is crossed if
//            T_C ≠ ∅. A surface that only touches C's boundary (C beside a box face) leaves C
//            uncrossed: C's interior is connected and no surface meets it, so C is full or empty.
//   rank     index of a crossed cell among the crossed cells of its level (in node order); its
//            children are the cells 8·rank .. 8·rank + 7 of the next level, in Morton order.
// One level at a time, in blocks of cells:
//   (A) T_C for every cell, testing the parent's list (the root: the BVH's candidates) with the
//       exact triangle / open-box test; a triangle whose box lies inside one child's open box
//       crosses that child alone, untested (most triangles above the last levels). At the last
//       level below a short parent list only T_C ≠ ∅ is used: one witness triangle per cell;
//       there (A) and (B) run in one pass per sibling set (last_level), sharing each triangle's
//       plane signs, and no lists are stored;
//   (B) the points to classify. Uncrossed siblings: each interior is connected and meets no
//       surface; the parent's centre p is a corner of each, so when no surface passes through p,
//       a small ball around p joins them all into one connected set no surface meets, where
//       every leaf's winding — hence membership — is constant: one centre is classified for all
//       of them (otherwise one per cell).
//       Partial cells: the samples³ sub-points, grouped by their sides of the planes of T_C;
//       every surface in the cell lies in those planes, so a side class is a convex region no
//       surface meets: one point per class is classified, and a point ON a plane alone (it may
//       be on a surface). When the parent's list T_P is short, the same grouping runs over a
//       whole sibling set at once, with the planes of T_P (every surface in the parent lies in
//       them): the sub-points of its partial cells and the centres of its uncrossed cells share
//       one side class per region of the parent. With closed leaves only one class per set is
//       classified (a reference, by its leaves' windings); the others add the signed crossings
//       of the segment from the reference with T_P's triangles (sibling_masks), and the
//       references of the sets under one grandparent G add those of their segments from one
//       anchor reference with T_G's (Anchor): one ray per grandparent. Above the last level
//       the uncrossed cells' centres are derived from an anchor the same way;
//   (C) one classify() and one leaf_windings() call per block; (D) states, occupancies and
//       child links.
// Node order, ranks and results depend only on the input: every parallel step writes per cell or
// per fixed chunk, and chunks are concatenated in order.

namespace cover::octree_build {

constexpr int kMaxDepth = 16;       // OctoMap's depth, and 2^16 cells per axis
constexpr int kMaxSamples = 32;     // 32³ sub-points per partial cell
constexpr size_t kInheritMax = 64;  // centre_on_surface: longer parent lists go through the BVH
constexpr size_t kGroupMax = 64;    // planes up to which points are grouped by sides
constexpr size_t kExactKey = 40;    // side vectors up to this length are exact base-3 keys
constexpr size_t kAnchorMax = 64;   // grandparent lists up to this length anchor (Anchor)
constexpr size_t kSiblingMax = 16;  // last level: parent lists up to this length group a whole
                                    // sibling set's points at once
constexpr size_t kGrain = 512;  // cells per parallel chunk (a multiple of 8: whole sibling sets)
constexpr size_t kTableLeaves = 10;         // expressions of up to this many leaves are tabulated
constexpr size_t kBlock = size_t{1} << 18;  // cells per classification batch (multiple of kGrain)
// Memory per node of a build: the node array (sizeof(Node) = 16 bytes), the per-cell triangle
// lists, the next level's parents and the block buffers. Measured: bunny00 at depth 10 peaks at
// about 230 MB for 9.5 M nodes (24 bytes per node).
constexpr double kBytesPerNode = 32;

using Coord = std::array<uint32_t, 3>;

/// "--depth D: the octree", the subject of the memory refusals.
std::string octree_subject(int depth);

/// One list of triangle indices per cell (compressed rows).
struct Lists {
  LargeVector<uint64_t> start{0};
  LargeVector<uint32_t> tris;

  std::span<const uint32_t> operator[](size_t i) const {
    return {tris.data() + start[i], static_cast<size_t>(start[i + 1] - start[i])};
  }
};

/// A classification request: cell `cell` (index in its block) gets `weight` times the class of
/// representative point `rep` (Requests::points), or of side class rep & ~kDerived
/// (Requests::derived) when that bit is set.
struct Entry {
  static constexpr uint32_t kDerived = uint32_t{1} << 31;
  uint32_t cell = 0;
  uint32_t rep = 0;
  uint32_t weight = 0;
};

/// A side class of a sibling set whose class follows from its set's reference point: the
/// reference's leaf windings (Requests::refs, classified by leaf_windings) plus the signed
/// crossings deltas[delta_begin .. + delta_count) of the segment from the reference to `point`.
struct Derived {
  Vec3 point;  ///< the class's representative (classified directly should the reference fail)
  uint32_t ref = 0;
  uint32_t delta_begin = 0;
  uint32_t delta_count = 0;
};

/// A crossing of a reference's segment: leaf `leaf`'s winding changes by `delta`.
struct Delta {
  uint32_t leaf = 0;
  int32_t delta = 0;
};

/// The classification requests of one chunk of cells.
struct Requests {
  std::vector<Vec3> points;  ///< classified one by one (classify)
  std::vector<Entry> entries;
  std::vector<Vec3> refs;  ///< classified by their leaves' windings (leaf_windings)
  std::vector<Derived> derived;
  std::vector<Delta> deltas;
};

/// A reference point classified by its leaves' windings and shared by the sibling sets of level
/// d ≥ 2 under one grandparent G (level d − 2), through whose interior both it and those sets'
/// points lie. A later point r (a set's reference at the last level, an uncrossed cell's centre
/// above it) takes the anchor's windings plus the signed crossings of the segment from the
/// anchor to r with T_G (the triangles that meet G's interior: the segment lies there, G being
/// convex), tested as within a set; one ray per grandparent instead of one per sibling set.
struct Anchor {
  size_t grand = SIZE_MAX;  ///< the grandparent's rank; SIZE_MAX: none
  size_t parent = 0;        ///< the parent (by rank) of the set being processed, G's child
  int level = 0;            ///< d, the level of the sets' cells
  bool valid = false;       ///< `point` is a reference strictly off every plane of T_G
  bool planes_ready = false;
  Vec3 point;
  uint32_t ref = 0;                       ///< its index in Requests::refs
  std::span<const uint32_t> tris;         ///< T_G
  std::vector<detail::PlaneSide> planes;  ///< their planes over G's box
  std::vector<int8_t> sides;              ///< the anchor's side of each
};

/// The samples³ sub-points of a cell (the centres of a regular sub-grid): their coordinates per
/// axis, and the points, x fastest.
struct SubGrid {
  int n = 0;
  double xs[kMaxSamples], ys[kMaxSamples], zs[kMaxSamples];

  void set(const Bbox& b, int s) {
    n = s;
    const Vec3 step{(b.max.x - b.min.x) / s, (b.max.y - b.min.y) / s, (b.max.z - b.min.z) / s};
    for (int i = 0; i < s; ++i) {
      xs[i] = b.min.x + (i + 0.5) * step.x;
      ys[i] = b.min.y + (i + 0.5) * step.y;
      zs[i] = b.min.z + (i + 0.5) * step.z;
    }
  }
  size_t size() const { return size_t(n) * n * n; }
  /// Sub-point p = (k·n + j)·n + i.
  Vec3 point(size_t p) const { return {xs[p % n], ys[(p / n) % n], zs[p / n / n]}; }
};

/// The grid planes of a cell's 8 children, per axis: the low face, the split plane, the high
/// face (octant o spans planes[a][bit] .. planes[a][bit + 1], bit = (o >> a) & 1).
struct Lattice {
  double planes[3][3];

  Bbox box() const {
    Bbox b;
    b.min = {planes[0][0], planes[1][0], planes[2][0]};
    b.max = {planes[0][2], planes[1][2], planes[2][2]};
    return b;
  }
};

/// Per-chunk buffers, reused from cell to cell.
struct Scratch {
  std::vector<int8_t> sides;     ///< points × planes
  std::vector<uint32_t> first;   ///< per group: its first point
  std::vector<uint32_t> weight;  ///< per group: its number of points
  std::vector<uint64_t> keys;    ///< per group: its side vector in base 3
  // Sibling sets of the last level (Builder::sibling_representatives):
  std::vector<detail::PlaneSide> planes;           ///< the parent's planes, over its box
  std::vector<uint32_t> lattice_pos, lattice_neg;  ///< their signs at its 27 lattice points
  std::vector<uint64_t> point_keys;  ///< per point of a cell: its side vector in base 3
  // Builder::sibling_masks: point sets of a sibling set as 9 words (word c < 8: the sub-points
  // of partial cell c, bit p = sub-point p; word 8: bit c = the centre of uncrossed cell c).
  std::vector<std::array<uint64_t, 9>> sets, split;
  std::vector<std::array<uint64_t, 9>> pos;  ///< per plane: the points on its positive side
  std::vector<uint32_t> rep;                 ///< per group: its representative (index in the chunk)
  std::vector<uint32_t> last_cell;           ///< the groups the current cell touches
  std::vector<uint32_t> entry;               ///< per group: its points in the current cell
};

/// Appends every triangle whose box (the BVH's float bounds contain the exact ones) meets the
/// closed box (a superset of those that meet its interior).
void bvh_candidates(const Bvh& bvh, const Bbox& box, std::vector<uint32_t>& out);

/// Groups the sub-points of `grid` (all in `box`) by their sides of the planes of `tris`: equal
/// side vectors without a zero share a group; a point on some plane gets a group of its own, and
/// so does every point when there are more than kGroupMax planes. Fills s.first and s.weight.
void group_by_sides(const Bvh& bvh, std::span<const uint32_t> tris, const Bbox& box,
                    const SubGrid& grid, Scratch& s);

/// The centre of a box.
inline Vec3 centre(const Bbox& b) {
  return {b.min.x + 0.5 * (b.max.x - b.min.x), b.min.y + 0.5 * (b.max.y - b.min.y),
          b.min.z + 0.5 * (b.max.z - b.min.z)};
}

/// How the segment rq, whose ends lie strictly on opposite sides of a triangle's plane, meets
/// the triangle: it crosses the interior where the three orient3d(r, q, edge) agree strictly,
/// passes by where two disagree strictly, and otherwise goes through an edge or vertex.
enum class Crossing { kPasses, kCrosses, kThroughEdge };

Crossing segment_crossing(const Vec3& r, const Vec3& q, const Bvh::Tri& tri);

/// std::popcount without a call: the x86-64 baseline has no POPCNT instruction, and GCC's
/// library fallback (a call per word) showed in sibling_masks' profile. SWAR, a dozen operations.
inline uint32_t popcount(uint64_t x) {
  x -= (x >> 1) & 0x5555555555555555u;
  x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Fu;
  return static_cast<uint32_t>((x * 0x0101010101010101u) >> 56);
}

/// Twice the weight of a class in an occupancy: inside 2, on the surface 1, outside 0.
inline uint32_t halves(PointClass c) {
  if (c == PointClass::kInside) return 2;
  return c == PointClass::kOutside ? 0 : 1;
}

class Builder {
 public:
  Builder(const Prepared& prepared, const VoxelBounds& bounds, const OctreeOptions& options);

  Octree run();

 private:
  double plane(int axis, uint64_t m) const {
    return bounds_.min[axis] + static_cast<double>(m) * h_;
  }

  Bbox box(const Coord& c, int d) const {
    const int shift = depth_ - d;
    Bbox b;
    b.min = {plane(0, uint64_t{c[0]} << shift), plane(1, uint64_t{c[1]} << shift),
             plane(2, uint64_t{c[2]} << shift)};
    b.max = {plane(0, (uint64_t{c[0]} + 1) << shift), plane(1, (uint64_t{c[1]} + 1) << shift),
             plane(2, (uint64_t{c[2]} + 1) << shift)};
    return b;
  }

  /// Corner of cell `cell` of level d ≥ 1: child cell % 8 of the crossed parent cell / 8.
  Coord coord(int d, size_t cell) const {
    if (d == 0) return {0, 0, 0};
    const Coord& p = parents_[cell / 8];
    const uint32_t c = static_cast<uint32_t>(cell % 8);
    return {2 * p[0] + (c & 1), 2 * p[1] + ((c >> 1) & 1), 2 * p[2] + ((c >> 2) & 1)};
  }

  /// The lattice of the children (level d) of crossed cell `parent` (by rank) of level d − 1:
  /// the same grid planes as their boxes.
  Lattice lattice_of(size_t parent, int d) const {
    Lattice l;
    for (int a = 0; a < 3; ++a)
      for (uint64_t t = 0; t < 3; ++t)
        l.planes[a][t] = plane(a, (2 * uint64_t{parents_[parent][a]} + t) << (depth_ - d));
    return l;
  }

  /// The octant (offset (o&1, (o>>1)&1, (o>>2)&1)) of the lattice `planes` whose open box
  /// contains the triangle's box, or −1.
  static int inside_octant(const Bvh::Tri& tri, const double (&planes)[3][3]) {
    int o = 0;
    for (int a = 0; a < 3; ++a) {
      const double lo = std::min({tri.a[a], tri.b[a], tri.c[a]});
      const double hi = std::max({tri.a[a], tri.b[a], tri.c[a]});
      if (lo > planes[a][0] && hi < planes[a][1]) continue;
      if (lo > planes[a][1] && hi < planes[a][2]) {
        o |= 1 << a;
        continue;
      }
      return -1;
    }
    return o;
  }

  /// (A) The triangles that meet the interior of each cell of [b0, b0 + m) at level d, one list
  /// per cell (levels above the last, and the root; the last level runs last_level).
  Lists meeting(int d, size_t b0, size_t m) const;

  /// True when some covering triangle passes through the centre of crossed cell `parent` (by
  /// rank) of the previous level: its list holds every triangle through its interior.
  bool centre_on_surface(size_t parent, int d, std::vector<uint32_t>& candidates) const;

  /// The anchor for the sibling set of `parent` (by rank) at level d: `anchor`, reset when the
  /// set's grandparent differs from the anchor's; nullptr without grandparents (d < 2), with
  /// open leaves (no windings) or when T_G holds more than kAnchorMax triangles (a ray is
  /// cheaper than that many plane signs per point).
  Anchor* anchor_of(size_t parent, int d, Anchor& anchor) const;

  /// Makes reference `point` (Requests::refs[ref], in the interior of a cell of the anchor's
  /// grandparent) the anchor, when it lies strictly off every plane of T_G.
  void set_anchor(Anchor& anchor, const Vec3& point, uint32_t ref) const;

  /// Appends to `deltas` the signed crossings of the segment from the anchor to r (a reference
  /// in the interior of another cell of the anchor's grandparent) with T_G, as sibling_masks
  /// does within a set; false (deltas partly written) when r lies on a plane of T_G or the
  /// segment passes through a triangle's edge or vertex.
  bool anchor_deltas(const Anchor& anchor, const Vec3& r, std::vector<Delta>& deltas) const;

  /// sibling_representatives for samples³ ≤ 64, on bit masks: the side classes are found by
  /// splitting the set of points on no plane by each plane's positive side (a class is an
  /// intersection of sides), each class's weight in a cell is a popcount, and its
  /// representative its first point; the points on some plane are classified one by one.
  void sibling_masks(size_t g0, std::span<const uint32_t> tris, const Lattice& lattice,
                     uint8_t crossed, Anchor* anchor, Scratch& s, Requests& out) const;

  /// Twice the class (halves()) of a derived side class: its reference's windings plus its
  /// deltas, the expression evaluated on them; classified directly should the reference lie on
  /// a surface (it cannot: it is on no plane of T_P, in the parent's interior). `refs_begin`:
  /// the chunk's first reference in `windings`.
  uint32_t derived_class(const Derived& x, const LeafWindings& windings, size_t refs_begin,
                         const std::vector<Delta>& deltas, std::vector<int>& winding) const;

  /// (B) at the last level, for the sibling set g0 .. g0 + 7 (cells of the block) whose parent's
  /// list T_P is short (s.planes: its planes over the parent's box; `crossed`: bit c for each
  /// crossed cell g0 + c): the sub-points of its partial cells and the centres of its uncrossed
  /// cells, grouped by their sides of the planes of T_P. T_P holds every triangle that meets
  /// the parent's interior, so a side class is a convex part of it no surface meets, where
  /// membership is constant: one point per class is classified for all the set's cells, and a
  /// point ON a plane alone (it may be on a surface).
  void sibling_representatives(int d, size_t b0, size_t g0, uint8_t crossed, Scratch& s,
                               SubGrid& subs, std::vector<Vec3>& points,
                               std::vector<Entry>& entries) const;

  /// (B) The points to classify for the sibling set g0 .. g0 + siblings − 1 of level d (cells
  /// of the block starting at b0; cell i's triangles list(i)): one centre for its uncrossed
  /// cells (one per cell when the parent's centre is on a surface) and, at the last level, one
  /// sub-point per side class of each partial cell. With an anchor (anchor_of) the centres are
  /// derived from its windings, or become references (leaf_windings): an uncrossed cell's
  /// centre is on no surface.
  template <typename CellList>
  void cells_representatives(int d, size_t b0, size_t g0, size_t siblings, CellList list,
                             Scratch& s, SubGrid& subs, std::vector<uint32_t>& candidates,
                             Anchor* anchor, Requests& out) const;

  /// (B) The points to classify for the cells [b0, b0 + m) of level d (below the last level,
  /// or the root), per chunk: cells_representatives per sibling set.
  void representatives(int d, size_t b0, size_t m, const Lists& lists,
                       std::vector<Requests>& requests) const;

  /// (A) and (B) at the last level D ≥ 1, per sibling set of the cells [b0, b0 + m), in one
  /// pass: which cells a triangle of the parent's list T_P crosses (bit c of crossed[set] for
  /// cell c of the set), and the points to classify. A short T_P (at most kSiblingMax) needs
  /// only one witness triangle per cell and shares each triangle's plane signs between the
  /// octant tests and the side classes (sibling_masks); a longer one gets full per-cell lists
  /// (group_by_sides).
  void last_level(size_t b0, size_t m, std::vector<Requests>& requests,
                  std::vector<uint8_t>& crossed) const;

  /// Cells [b0, b1) of level d; `nodes` is the level's first node, `next_start` the next level's.
  /// Appends the crossed cells (d < D) and their triangles to `next` / `next_lists`.
  void block(int d, size_t b0, size_t b1, Octree::Node* nodes, size_t next_start,
             LargeVector<Coord>& next, Lists& next_lists);

  const Prepared& prepared_;
  const Solid& solid_;
  const Bvh& bvh_;
  VoxelBounds bounds_;
  int depth_;
  int samples_;
  double h_;
  uint64_t max_bytes_;
  std::function<void(double)> progress_;
  bool open_ = false;           ///< some leaf is open: no shared centres
  std::vector<uint8_t> table_;  ///< membership per set of inside leaves (≤ kTableLeaves leaves)
  /// Sub-point p = (k·n + j)·n + i of a cell (samples³ ≤ 64): (i, j, k), without divisions.
  std::array<std::array<uint8_t, 3>, 64> sub_index_{};
  LargeVector<Coord> parents_;  ///< crossed cells of the previous level, by rank
  Lists parent_lists_;          ///< their triangles, by rank
  /// Levels d ≥ 2: per parent (by rank), its own parent's rank at level d − 2, and the
  /// triangles of those grandparents, by rank (see Anchor).
  LargeVector<uint32_t> grand_rank_, next_grand_;
  Lists grand_lists_;
};

}  // namespace cover::octree_build
