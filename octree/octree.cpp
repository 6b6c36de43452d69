#include "cover/octree/octree.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <string>

#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/covering/detail/bvh_walk.h"
#include "cover/octree/detail/box_overlap.h"
#include "cover/solid/errors.h"
#include "cover/solid/large_vector.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"

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

namespace cover {
namespace {

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
void bvh_candidates(const Bvh& bvh, const Bbox& box, std::vector<uint32_t>& out) {
  walk(
      bvh,
      [&](const Bvh::Node& node) {
        for (int a = 0; a < 3; ++a)
          if (node.lo[a] > box.max[a] || node.hi[a] < box.min[a]) return false;
        return true;
      },
      [&](const Bvh::Tri&, uint32_t i) { out.push_back(i); });
}

/// Groups the sub-points of `grid` (all in `box`) by their sides of the planes of `tris`: equal
/// side vectors without a zero share a group; a point on some plane gets a group of its own, and
/// so does every point when there are more than kGroupMax planes. Fills s.first and s.weight.
void group_by_sides(const Bvh& bvh, std::span<const uint32_t> tris, const Bbox& box,
                    const SubGrid& grid, Scratch& s) {
  const size_t n = grid.size(), k = tris.size();
  s.first.clear();
  s.weight.clear();
  if (k > kGroupMax) {
    for (size_t i = 0; i < n; ++i) s.first.push_back(static_cast<uint32_t>(i));
    s.weight.assign(n, 1);
    return;
  }
  s.sides.resize(n * k);
  for (size_t j = 0; j < k; ++j) {
    const Bvh::Tri tri = bvh.triangle(tris[j]);
    detail::PlaneSide(tri.a, tri.b, tri.c, box)
        .grid_signs(grid.xs, grid.ys, grid.zs, grid.n, s.sides.data() + j, k);
  }
  s.keys.clear();
  for (size_t i = 0; i < n; ++i) {
    const int8_t* side = s.sides.data() + i * k;
    bool on_plane = false;
    uint64_t key = 0;  // base 3: exact up to kExactKey planes, a hash beyond
    for (size_t j = 0; j < k; ++j) {
      on_plane |= side[j] == 0;
      key = 3 * key + static_cast<uint64_t>(side[j] + 1);
    }
    uint32_t g = static_cast<uint32_t>(s.first.size());
    if (!on_plane)
      for (uint32_t q = 0; q < s.first.size(); ++q)
        if (s.keys[q] == key &&
            (k <= kExactKey ||
             std::memcmp(side, s.sides.data() + size_t{s.first[q]} * k, k) == 0)) {
          g = q;
          break;
        }
    if (g == s.first.size()) {
      s.first.push_back(static_cast<uint32_t>(i));
      s.weight.push_back(0);
      s.keys.push_back(key);
    }
    ++s.weight[g];
  }
}

Vec3 centre(const Bbox& b) {
  return {b.min.x + 0.5 * (b.max.x - b.min.x), b.min.y + 0.5 * (b.max.y - b.min.y),
          b.min.z + 0.5 * (b.max.z - b.min.z)};
}

/// Σ of the covering triangles' areas |(vi − v0) × (vi+1 − v0)|/2.
double covering_area(const Solid& solid) {
  double area = 0;
  for (size_t f = 0; f < solid.face_count(); ++f) {
    const std::span<const uint32_t> face = solid.face(f);
    const Vec3 a = solid.vertices[face[0]];
    for (size_t i = 1; i + 1 < face.size(); ++i) {
      const Vec3 n = cross(solid.vertices[face[i]] - a, solid.vertices[face[i + 1]] - a);
      area += 0.5 * std::sqrt(dot(n, n));
    }
  }
  return area;
}

/// The nodes a build of `depth` levels over a cube of side `size` is expected to create: level
/// d + 1 has 8 cells per crossed cell of level d, and a surface of area A meets about 1.5·A/h²
/// cells of side h (A times the mean width of a cube, 1.5·h, over its volume h³), at most all
/// of the level's cells. Within a few percent of the real count on bunny00 at depths 8 and 10.
double expected_nodes(double area, double size, int depth) {
  double cells = 1, nodes = 0;
  for (int d = 0; d <= depth; ++d) {
    nodes += cells;
    const double h = std::ldexp(size, -d);
    cells = 8 * std::min(cells, 1.5 * area / (h * h));
  }
  return nodes;
}

/// "--depth D: the octree", the subject of the memory refusals.
std::string octree_subject(int depth) {
  return parameter("depth") + " " + std::to_string(depth) + ": the octree";
}

/// How the segment rq, whose ends lie strictly on opposite sides of a triangle's plane, meets
/// the triangle: it crosses the interior where the three orient3d(r, q, edge) agree strictly,
/// passes by where two disagree strictly, and otherwise goes through an edge or vertex.
enum class Crossing { kPasses, kCrosses, kThroughEdge };

Crossing segment_crossing(const Vec3& r, const Vec3& q, const Bvh::Tri& tri) {
  int o[3];
  detail::edge_orientations(r, q, tri.a, tri.b, tri.c, o);
  const int o0 = o[0], o1 = o[1], o2 = o[2];
  const bool some_neg = o0 < 0 || o1 < 0 || o2<0, some_pos = o0> 0 || o1 > 0 || o2 > 0;
  if (some_neg && some_pos) return Crossing::kPasses;
  return o0 == 0 || o1 == 0 || o2 == 0 ? Crossing::kThroughEdge : Crossing::kCrosses;
}

/// std::popcount without a call: the x86-64 baseline has no POPCNT instruction, and GCC's
/// library fallback (a call per word) showed in sibling_masks' profile. SWAR, a dozen operations.
inline uint32_t popcount(uint64_t x) {
  x -= (x >> 1) & 0x5555555555555555u;
  x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);
  x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Fu;
  return static_cast<uint32_t>((x * 0x0101010101010101u) >> 56);
}

/// Twice the weight of a class in an occupancy: inside 2, on the surface 1, outside 0.
uint32_t halves(PointClass c) {
  if (c == PointClass::kInside) return 2;
  return c == PointClass::kOutside ? 0 : 1;
}

class Builder {
 public:
  Builder(const Solid& solid, const Bvh& bvh, const VoxelBounds& bounds,
          const OctreeOptions& options)
      : solid_(solid),
        bvh_(bvh),
        bounds_(bounds),
        depth_(options.depth),
        samples_(options.samples),
        h_(std::ldexp(bounds.size, -options.depth)),
        max_bytes_(options.max_bytes),
        progress_(options.progress),
        open_(solid.has_open_leaf()) {
    if (open_ && options.gwn == nullptr) own_gwn_ = build_gwn(solid);
    if (solid.leaves.size() <= kTableLeaves) table_ = solid.tree.truth_table(solid.leaves.size());
    const int n = samples_;
    for (int p = 0; p < std::min(n * n * n, 64); ++p)
      sub_index_[p] = {static_cast<uint8_t>(p % n), static_cast<uint8_t>(p / n % n),
                       static_cast<uint8_t>(p / n / n)};
    gwn_ = options.gwn != nullptr ? options.gwn : (own_gwn_ ? &*own_gwn_ : nullptr);
  }

  Octree run() {
    Octree tree;
    tree.bounds = bounds_;
    tree.depth = depth_;
    size_t level_start = 0;
    // Progress: crossed cells grow about 4× per level, so level d weighs 4^d.
    const double weight_total = (std::ldexp(1.0, 2 * depth_ + 2) - 1) / 3;
    double weight_done = 0;
    // The node array at its expected size at once (within a few percent; it grows past that if
    // need be), on huge pages, so that no level's resize copies the old nodes or faults in the
    // new ones a 4 KiB page at a time (bunny00 at depth 10 has 9.5M nodes).
    reserve_huge(tree.nodes, static_cast<size_t>(std::min(
                                 1.05 * expected_nodes(covering_area(solid_), bounds_.size, depth_),
                                 static_cast<double>(UINT32_MAX))));
    for (int d = 0; d <= depth_; ++d) {
      const size_t n = d == 0 ? 1 : 8 * parents_.size();
      if (n == 0) break;
      if (level_start + n > UINT32_MAX)
        throw NotComputable("octree: more than 2^32 nodes; use a smaller depth");
      check_memory(kBytesPerNode * static_cast<double>(level_start + n), max_bytes_,
                   octree_subject(depth_));
      tree.nodes.resize(level_start + n);
      // At most every cell is crossed: reserved (address space; pages are touched as used)
      // so that growing never copies, and on huge pages like every per-level array here.
      // Fresh pages are dear on virtual machines: on 4 KiB pages these arrays would take about
      // 10,000 page faults per bunny00 depth-10 build, most of them in the serial pass; on huge
      // pages about 200.
      LargeVector<Coord> next;
      Lists next_lists;
      if (d < depth_) {
        next.reserve(n);
        if (d >= 1) next_grand_.reserve(n);
        next_lists.start.reserve(n + 1);
        // Each parent triangle lies in at most 8 children's lists (address space only).
        next_lists.tris.reserve(8 * parent_lists_.tris.size());
      }
      for (size_t b0 = 0; b0 < n; b0 += kBlock) {
        const size_t b1 = std::min(n, b0 + kBlock);
        block(d, b0, b1, tree.nodes.data() + level_start, level_start + n, next, next_lists);
        if (progress_)
          progress_((weight_done + std::ldexp(1.0, 2 * d) * static_cast<double>(b1) / n) /
                    weight_total);
      }
      weight_done += std::ldexp(1.0, 2 * d);
      if (d >= 1) {  // the next level's grandparents
        grand_lists_ = std::move(parent_lists_);
        grand_rank_ = std::move(next_grand_);
      }
      parents_ = std::move(next);
      parent_lists_ = std::move(next_lists);
      level_start += n;
    }
    // Inner nodes: the mean occupancy of their children (children follow their parent).
    for (size_t i = tree.nodes.size(); i-- > 0;) {
      Octree::Node& node = tree.nodes[i];
      if (node.first_child == 0) continue;
      double sum = 0;
      for (uint32_t c = 0; c < 8; ++c) sum += tree.nodes[node.first_child + c].occupancy;
      node.occupancy = static_cast<float>(sum / 8);
    }
    return tree;
  }

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
  Lists meeting(int d, size_t b0, size_t m) const {
    std::vector<std::vector<uint32_t>> chunk_tris((m + kGrain - 1) / kGrain);
    LargeVector<uint32_t> count(m);
    parallel_for(m, kGrain, [&](size_t begin, size_t end) {
      std::vector<uint32_t>& out = chunk_tris[begin / kGrain];
      std::vector<uint32_t> candidates;
      std::array<std::vector<uint32_t>, 8> octant;
      const size_t siblings = d == 0 ? 1 : 8;
      for (size_t g0 = begin; g0 < end; g0 += siblings) {
        const size_t parent = (b0 + g0) / 8;
        if (d > 0) {
          // The parent's triangles against its 8 octants at once.
          const Lattice lattice = lattice_of(parent, d);
          for (auto& list : octant) list.clear();
          for (uint32_t t : parent_lists_[parent]) {
            const Bvh::Tri tri = bvh_.triangle(t);
            // A triangle whose box lies inside one octant's open box crosses that octant and
            // no other (no exact test): most triangles, above the last levels.
            if (const int o = inside_octant(tri, lattice.planes); o >= 0) {
              octant[o].push_back(t);
              continue;
            }
            const uint8_t crossed =
                detail::crossed_octants(tri.a, tri.b, tri.c, lattice.planes, 0xFF);
            for (uint8_t c = crossed; c != 0; c &= static_cast<uint8_t>(c - 1))
              octant[std::countr_zero(c)].push_back(t);
          }
          for (int c = 0; c < 8; ++c) {
            out.insert(out.end(), octant[c].begin(), octant[c].end());
            count[g0 + c] = static_cast<uint32_t>(octant[c].size());
          }
          continue;
        }
        for (size_t i = g0; i < g0 + siblings; ++i) {
          const Bbox b = box(coord(d, b0 + i), d);
          candidates.clear();
          bvh_candidates(bvh_, b, candidates);
          const size_t before = out.size();
          const double planes[3][3] = {{b.min.x, b.max.x, b.max.x},
                                       {b.min.y, b.max.y, b.max.y},
                                       {b.min.z, b.max.z, b.max.z}};
          for (uint32_t t : candidates) {
            const Bvh::Tri tri = bvh_.triangle(t);
            if (inside_octant(tri, planes) == 0 ||
                detail::triangle_crosses_box(tri.a, tri.b, tri.c, b))
              out.push_back(t);
          }
          count[i] = static_cast<uint32_t>(out.size() - before);
        }
      }
    });
    Lists lists;
    lists.start.resize(m + 1, 0);
    for (size_t i = 0; i < m; ++i) lists.start[i + 1] = lists.start[i] + count[i];
    lists.tris.reserve(lists.start[m]);
    for (auto& c : chunk_tris) {
      lists.tris.insert(lists.tris.end(), c.begin(), c.end());
      std::vector<uint32_t>().swap(c);
    }
    return lists;
  }

  /// True when some covering triangle passes through the centre of crossed cell `parent` (by
  /// rank) of the previous level: its list holds every triangle through its interior.
  bool centre_on_surface(size_t parent, int d, std::vector<uint32_t>& candidates) const {
    double x[3];  // the children's common corner: the same grid planes as their boxes
    for (int a = 0; a < 3; ++a)
      x[a] = plane(a, (2 * uint64_t{parents_[parent][a]} + 1) << (depth_ - d));
    Bbox point;
    point.min = point.max = {x[0], x[1], x[2]};
    std::span<const uint32_t> tris = parent_lists_[parent];
    if (tris.size() > kInheritMax) {
      candidates.clear();
      bvh_candidates(bvh_, point, candidates);
      tris = candidates;
    }
    const Vec3 p{x[0], x[1], x[2]};
    for (uint32_t t : tris) {
      const Bvh::Tri tri = bvh_.triangle(t);
      // Off the triangle's plane (the common case, one filtered orient3d) it is off the triangle.
      if (orient3d(tri.a, tri.b, tri.c, p) == 0 &&
          detail::triangle_meets_box(tri.a, tri.b, tri.c, point))
        return true;
    }
    return false;
  }

  /// The anchor for the sibling set of `parent` (by rank) at level d: `anchor`, reset when the
  /// set's grandparent differs from the anchor's; nullptr without grandparents (d < 2), with
  /// open leaves (no windings) or when T_G holds more than kAnchorMax triangles (a ray is
  /// cheaper than that many plane signs per point).
  Anchor* anchor_of(size_t parent, int d, Anchor& anchor) const {
    if (d < 2 || open_) return nullptr;
    const size_t grand = grand_rank_[parent];
    if (grand_lists_[grand].size() > kAnchorMax) return nullptr;
    anchor.parent = parent;
    anchor.level = d;
    if (grand != anchor.grand) {
      anchor.grand = grand;
      anchor.valid = false;
      anchor.tris = grand_lists_[grand];
      anchor.planes.clear();
      anchor.planes_ready = false;
    }
    return &anchor;
  }

  /// Makes reference `point` (Requests::refs[ref], in the interior of a cell of the anchor's
  /// grandparent) the anchor, when it lies strictly off every plane of T_G.
  void set_anchor(Anchor& anchor, const Vec3& point, uint32_t ref) const {
    if (!anchor.planes_ready) {
      anchor.planes_ready = true;
      const Coord& p = parents_[anchor.parent];  // a child of G
      const Bbox g = box({p[0] / 2, p[1] / 2, p[2] / 2}, anchor.level - 2);
      for (uint32_t t : anchor.tris) {
        const Bvh::Tri tri = bvh_.triangle(t);
        anchor.planes.emplace_back(tri.a, tri.b, tri.c, g);
      }
    }
    anchor.sides.clear();
    for (const detail::PlaneSide& plane : anchor.planes) {
      const int side = plane.sign(point);
      if (side == 0) return;
      anchor.sides.push_back(static_cast<int8_t>(side));
    }
    anchor.point = point;
    anchor.ref = ref;
    anchor.valid = true;
  }

  /// Appends to `deltas` the signed crossings of the segment from the anchor to r (a reference
  /// in the interior of another cell of the anchor's grandparent) with T_G, as sibling_masks
  /// does within a set; false (deltas partly written) when r lies on a plane of T_G or the
  /// segment passes through a triangle's edge or vertex.
  bool anchor_deltas(const Anchor& anchor, const Vec3& r, std::vector<Delta>& deltas) const {
    for (size_t j = 0; j < anchor.planes.size(); ++j) {
      const int side = anchor.planes[j].sign(r);
      if (side == 0) return false;
      if (side == anchor.sides[j]) continue;
      const Bvh::Tri tri = bvh_.triangle(anchor.tris[j]);
      const Crossing x = segment_crossing(anchor.point, r, tri);
      if (x == Crossing::kThroughEdge) return false;
      if (x == Crossing::kCrosses) deltas.push_back({tri.leaf, anchor.sides[j] > 0 ? 1 : -1});
    }
    return true;
  }

  /// sibling_representatives for samples³ ≤ 64, on bit masks: the side classes are found by
  /// splitting the set of points on no plane by each plane's positive side (a class is an
  /// intersection of sides), each class's weight in a cell is a popcount, and its
  /// representative its first point; the points on some plane are classified one by one.
  void sibling_masks(size_t g0, std::span<const uint32_t> tris, const Lattice& lattice,
                     uint8_t crossed, Anchor* anchor, Scratch& s, Requests& out) const {
    std::vector<Vec3>& points = out.points;
    std::vector<Entry>& entries = out.entries;
    using Set = std::array<uint64_t, 9>;
    const size_t k = tris.size();
    const int n = samples_;
    const int count = n * n * n;
    const uint64_t all = count == 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1;
    Set full{}, on{};
    for (int c = 0; c < 8; ++c) {
      if (crossed >> c & 1)
        full[c] = all;
      else
        full[8] |= uint64_t{1} << c;
    }
    // Sub-point coordinates and centres per half of each axis: the values SubGrid::set and
    // centre() give for the cells' boxes (the same grid planes).
    double sub[3][2][kMaxSamples], mid[3][2];
    const double inv_n = 1.0 / n;
    for (int a = 0; a < 3; ++a)
      for (int h = 0; h < 2; ++h) {
        const double lo = lattice.planes[a][h], hi = lattice.planes[a][h + 1];
        // SubGrid::set's step (hi − lo)/n; for n a power of two the product by 1/n is the same
        // double without a division (6 per set).
        const double step = (n & (n - 1)) == 0 ? (hi - lo) * inv_n : (hi - lo) / n;
        for (int i = 0; i < n; ++i) sub[a][h][i] = lo + (i + 0.5) * step;
        mid[a][h] = lo + 0.5 * (hi - lo);
      }
    const double* const halves[3][2] = {
        {sub[0][0], sub[0][1]}, {sub[1][0], sub[1][1]}, {sub[2][0], sub[2][1]}};
    s.pos.resize(k);
    constexpr uint32_t kAll27 = (uint32_t{1} << 27) - 1;
    for (size_t j = 0; j < k; ++j) {
      const detail::PlaneSide& plane = s.planes[j];
      // A cell whose 8 corners lie strictly on one side has all its points there (the sign of
      // orient3d is affine in the point): no per-point signs.
      const uint32_t some_nonpos = detail::spread27(~s.lattice_pos[j] & kAll27);
      const uint32_t some_nonneg = detail::spread27(~s.lattice_neg[j] & kAll27);
      Set& pos = s.pos[j];
      pos.fill(0);
      uint8_t grid = 0;  // the crossed cells the plane passes through: per-point signs
      for (int c = 0; c < 8; ++c) {
        const int corner = detail::kOctantCorner[c];
        if (!(some_nonpos >> corner & 1)) {
          pos[c] = full[c];
          pos[8] |= full[8] & (uint64_t{1} << c);
          continue;
        }
        if (!(some_nonneg >> corner & 1)) continue;
        if (full[c] != 0) {
          grid |= static_cast<uint8_t>(1u << c);
        } else {
          const int side = plane.sign({mid[0][c & 1], mid[1][(c >> 1) & 1], mid[2][c >> 2]});
          pos[8] |= uint64_t{side > 0} << c;
          on[8] |= uint64_t{side == 0} << c;
        }
      }
      if (grid != 0) {
        uint64_t neg[8];
        plane.cell_masks(halves[0], halves[1], halves[2], n, grid, pos.data(), neg);
        for (uint32_t m = grid; m != 0; m &= m - 1) {
          const int c = std::countr_zero(m);
          on[c] |= full[c] & ~(pos[c] | neg[c]);
        }
      }
    }
    // Side classes of the points on no plane: split by every plane's positive side.
    s.sets.clear();
    Set start;
    for (int w = 0; w < 9; ++w) start[w] = full[w] & ~on[w];
    s.sets.push_back(start);
    for (size_t j = 0; j < k; ++j) {
      s.split.clear();
      for (const Set& set : s.sets) {
        Set in, out;
        uint64_t any_in = 0, any_out = 0;
        for (int w = 0; w < 9; ++w) {
          in[w] = set[w] & s.pos[j][w];
          out[w] = set[w] & ~s.pos[j][w];
          any_in |= in[w];
          any_out |= out[w];
        }
        if (any_in) s.split.push_back(in);
        if (any_out) s.split.push_back(out);
      }
      std::swap(s.sets, s.split);
    }
    const auto point = [&](int w, int bit) {
      if (w == 8) return Vec3{mid[0][bit & 1], mid[1][(bit >> 1) & 1], mid[2][bit >> 2]};
      const std::array<uint8_t, 3>& ijk = sub_index_[bit];
      return Vec3{sub[0][w & 1][ijk[0]], sub[1][(w >> 1) & 1][ijk[1]], sub[2][w >> 2][ijk[2]]};
    };
    // A class's representative: its first point, (word, bit).
    const auto first = [](const Set& set) {
      int w = 0;
      while (set[w] == 0) ++w;
      return std::pair<int, int>{w, std::countr_zero(set[w])};
    };
    const auto add_entries = [&](const Set& set, uint32_t rep) {
      for (int c = 0; c < 8; ++c)
        if (set[c] != 0)
          entries.push_back(
              {static_cast<uint32_t>(g0 + c), rep, static_cast<uint32_t>(popcount(set[c]))});
      for (uint64_t m = set[8]; m != 0; m &= m - 1)
        entries.push_back({static_cast<uint32_t>(g0 + std::countr_zero(m)), rep, 1});
    };
    const auto add = [&](const Set& set) {
      const auto [w, bit] = first(set);
      add_entries(set, static_cast<uint32_t>(points.size()));
      points.push_back(point(w, bit));
    };
    // The side classes. With closed leaves, the first class's representative r is the set's
    // reference, classified by its leaves' windings; another class's representative q differs
    // from r by the signed crossings of the segment rq with the triangles of T_P: both points
    // lie in the parent's interior on no plane of T_P, so the segment meets only T_P's
    // triangles, and a triangle whose plane separates r and q is crossed where the three
    // orient3d(r, q, edge) agree strictly (crossing from its outer side, the side its normal
    // points to, adds 1 to its leaf's winding). A segment through a triangle's edge or vertex
    // (some orient3d zero, none disagreeing) leaves q to classify().
    // With an anchor (last_level), r itself may be derived from the anchor's windings: the
    // deltas base_begin .. + base_count, which every other class of the set then starts with.
    int ref_w = -1, ref_bit = 0;
    Vec3 r;
    uint32_t ref = 0, base_begin = 0, base_count = 0;
    for (const Set& set : s.sets) {
      if (!std::any_of(set.begin(), set.end(), [](uint64_t x) { return x != 0; })) continue;
      if (open_) {
        add(set);
        continue;
      }
      const auto [w, bit] = first(set);
      const Vec3 q = point(w, bit);
      const uint32_t delta_begin = static_cast<uint32_t>(out.deltas.size());
      if (ref_w < 0) {
        ref_w = w;
        ref_bit = bit;
        r = q;
        if (anchor != nullptr && anchor->valid && anchor_deltas(*anchor, r, out.deltas)) {
          ref = anchor->ref;
          base_begin = delta_begin;
          base_count = static_cast<uint32_t>(out.deltas.size()) - delta_begin;
        } else {
          out.deltas.resize(delta_begin);
          ref = static_cast<uint32_t>(out.refs.size());
          out.refs.push_back(r);
          if (anchor != nullptr && !anchor->valid) set_anchor(*anchor, r, ref);
        }
      } else {
        for (uint32_t i = 0; i < base_count; ++i) out.deltas.push_back(out.deltas[base_begin + i]);
        bool through_edge = false;
        for (size_t j = 0; j < k && !through_edge; ++j) {
          const bool r_pos = s.pos[j][ref_w] >> ref_bit & 1, q_pos = s.pos[j][w] >> bit & 1;
          if (r_pos == q_pos) continue;
          const Bvh::Tri tri = bvh_.triangle(tris[j]);
          const Crossing x = segment_crossing(r, q, tri);
          if (x == Crossing::kThroughEdge) through_edge = true;
          if (x == Crossing::kCrosses) out.deltas.push_back({tri.leaf, r_pos ? 1 : -1});
        }
        if (through_edge) {
          out.deltas.resize(delta_begin);
          add(set);
          continue;
        }
      }
      add_entries(set, static_cast<uint32_t>(out.derived.size()) | Entry::kDerived);
      out.derived.push_back(
          {q, ref, delta_begin, static_cast<uint32_t>(out.deltas.size()) - delta_begin});
    }
    // Points on some plane (they may be on a surface): one by one.
    for (int w = 0; w < 9; ++w)
      for (uint64_t m = on[w]; m != 0; m &= m - 1) {
        Set one{};
        one[w] = m & (~m + 1);
        add(one);
      }
  }

  /// Twice the class (halves()) of a derived side class: its reference's windings plus its
  /// deltas, the expression evaluated on them; classified directly should the reference lie on
  /// a surface (it cannot: it is on no plane of T_P, in the parent's interior). `refs_begin`:
  /// the chunk's first reference in `windings`.
  uint32_t derived_class(const Derived& x, const LeafWindings& windings, size_t refs_begin,
                         const std::vector<Delta>& deltas, std::vector<int>& winding) const {
    const size_t leaves = windings.leaves;
    const size_t at = (refs_begin + x.ref) * leaves;
    bool on_surface = false;
    winding.assign(windings.winding.begin() + at, windings.winding.begin() + at + leaves);
    for (size_t l = 0; l < leaves; ++l) on_surface |= windings.on_surface[at + l] != 0;
    if (on_surface) {
      ClassifyOptions options;
      options.gwn = gwn_;
      return halves(classify(solid_, bvh_, std::span<const Vec3>(&x.point, 1), options)[0]);
    }
    for (uint32_t i = x.delta_begin; i < x.delta_begin + x.delta_count; ++i)
      winding[deltas[i].leaf] += deltas[i].delta;
    if (!table_.empty()) {
      uint32_t mask = 0;
      for (size_t l = 0; l < leaves; ++l) mask |= uint32_t{winding[l] != 0} << l;
      return table_[mask] ? 2 : 0;
    }
    std::vector<uint8_t> inside(leaves);
    for (size_t l = 0; l < leaves; ++l) inside[l] = winding[l] != 0;
    return solid_.tree.evaluate(inside) ? 2 : 0;
  }

  /// (B) at the last level, for the sibling set g0 .. g0 + 7 (cells of the block) whose parent's
  /// list T_P is short (s.planes: its planes over the parent's box; `crossed`: bit c for each
  /// crossed cell g0 + c): the sub-points of its partial cells and the centres of its uncrossed
  /// cells, grouped by their sides of the planes of T_P. T_P holds every triangle that meets
  /// the parent's interior, so a side class is a convex part of it no surface meets, where
  /// membership is constant: one point per class is classified for all the set's cells, and a
  /// point ON a plane alone (it may be on a surface).
  void sibling_representatives(int d, size_t b0, size_t g0, uint8_t crossed, Scratch& s,
                               SubGrid& subs, std::vector<Vec3>& points,
                               std::vector<Entry>& entries) const {
    const size_t k = s.planes.size();
    s.keys.clear();  // per group: its side vector in base 3 (exact: k ≤ kExactKey), or
    s.rep.clear();   // kOnPlane for a point on some plane, never matched
    s.entry.clear();
    constexpr uint64_t kOnPlane = UINT64_MAX;
    const size_t sub_count = size_t(samples_) * samples_ * samples_;
    s.sides.resize(sub_count * k);
    std::vector<uint64_t>& key = s.point_keys;
    for (uint32_t cell = static_cast<uint32_t>(g0); cell < g0 + 8; ++cell) {
      const Bbox b = box(coord(d, b0 + cell), d);
      const bool partial = crossed >> (cell - g0) & 1;
      Vec3 c;
      size_t count = 1;
      if (partial) {
        subs.set(b, samples_);
        count = sub_count;
        for (size_t j = 0; j < k; ++j)
          s.planes[j].grid_signs(subs.xs, subs.ys, subs.zs, subs.n, s.sides.data() + j * count, 1);
      } else {
        c = centre(b);
        for (size_t j = 0; j < k; ++j) s.sides[j] = static_cast<int8_t>(s.planes[j].sign(c));
      }
      key.assign(count, 0);
      for (size_t j = 0; j < k; ++j) {
        const int8_t* side = s.sides.data() + j * count;
        for (size_t p = 0; p < count; ++p)
          key[p] = side[p] == 0 ? kOnPlane
                                : (key[p] == kOnPlane ? kOnPlane : 3 * key[p] + (side[p] + 1));
      }
      // Runs of equal keys (neighbouring sub-points) skip the search; each group's weight in
      // this cell is counted in s.entry (reset below), its first touch listed in s.last_cell.
      s.last_cell.clear();  // the groups this cell touches, in order of first touch
      uint32_t g = UINT32_MAX;
      uint64_t last = kOnPlane;
      for (size_t p = 0; p < count; ++p) {
        const uint64_t kp = key[p];
        if (kp == kOnPlane || kp != last) {
          g = static_cast<uint32_t>(s.keys.size());
          if (kp != kOnPlane)
            for (uint32_t q = 0; q < s.keys.size(); ++q)
              if (s.keys[q] == kp) {
                g = q;
                break;
              }
          if (g == s.keys.size()) {
            s.keys.push_back(kp);
            s.rep.push_back(static_cast<uint32_t>(points.size()));
            points.push_back(partial ? subs.point(p) : c);
            s.entry.push_back(0);
          }
          last = kp;
        }
        if (s.entry[g]++ == 0) s.last_cell.push_back(g);
      }
      for (uint32_t q : s.last_cell) {
        entries.push_back({cell, s.rep[q], s.entry[q]});
        s.entry[q] = 0;
      }
    }
  }

  /// (B) The points to classify for the sibling set g0 .. g0 + siblings − 1 of level d (cells
  /// of the block starting at b0; cell i's triangles list(i)): one centre for its uncrossed
  /// cells (one per cell when the parent's centre is on a surface) and, at the last level, one
  /// sub-point per side class of each partial cell. With an anchor (anchor_of) the centres are
  /// derived from its windings, or become references (leaf_windings): an uncrossed cell's
  /// centre is on no surface.
  template <typename CellList>
  void cells_representatives(int d, size_t b0, size_t g0, size_t siblings, CellList list,
                             Scratch& s, SubGrid& subs, std::vector<uint32_t>& candidates,
                             Anchor* anchor, Requests& out) const {
    std::vector<Vec3>& points = out.points;
    std::vector<Entry>& entries = out.entries;
    size_t uncrossed = 0;
    for (size_t i = g0; i < g0 + siblings; ++i) uncrossed += list(i).empty();
    const bool shared = uncrossed > 1 && !open_ && !centre_on_surface((b0 + g0) / 8, d, candidates);
    // An uncrossed cell's centre c: an entry's `rep`.
    const auto request = [&](const Vec3& c) {
      if (anchor == nullptr) {
        points.push_back(c);
        return static_cast<uint32_t>(points.size() - 1);
      }
      const uint32_t delta_begin = static_cast<uint32_t>(out.deltas.size());
      uint32_t ref = 0;
      if (anchor->valid && anchor_deltas(*anchor, c, out.deltas)) {
        ref = anchor->ref;
      } else {
        out.deltas.resize(delta_begin);
        ref = static_cast<uint32_t>(out.refs.size());
        out.refs.push_back(c);
        if (!anchor->valid) set_anchor(*anchor, c, ref);
      }
      out.derived.push_back(
          {c, ref, delta_begin, static_cast<uint32_t>(out.deltas.size()) - delta_begin});
      return static_cast<uint32_t>(out.derived.size() - 1) | Entry::kDerived;
    };
    uint32_t rep = UINT32_MAX;
    for (size_t i = g0; i < g0 + siblings; ++i) {
      if (!list(i).empty()) continue;
      if (rep == UINT32_MAX || !shared) rep = request(centre(box(coord(d, b0 + i), d)));
      entries.push_back({static_cast<uint32_t>(i), rep, 1});
    }
    if (d < depth_) return;
    for (size_t i = g0; i < g0 + siblings; ++i) {
      if (list(i).empty()) continue;
      const Bbox b = box(coord(d, b0 + i), d);
      subs.set(b, samples_);
      group_by_sides(bvh_, list(i), b, subs, s);
      const uint32_t base = static_cast<uint32_t>(points.size());
      for (uint32_t g = 0; g < s.first.size(); ++g) {
        points.push_back(subs.point(s.first[g]));
        entries.push_back({static_cast<uint32_t>(i), base + g, s.weight[g]});
      }
    }
  }

  /// (B) The points to classify for the cells [b0, b0 + m) of level d (below the last level,
  /// or the root), per chunk: cells_representatives per sibling set.
  void representatives(int d, size_t b0, size_t m, const Lists& lists,
                       std::vector<Requests>& requests) const {
    parallel_for(m, kGrain, [&](size_t begin, size_t end) {
      Requests& out = requests[begin / kGrain];
      Scratch s;
      SubGrid subs;
      std::vector<uint32_t> candidates;
      Anchor anchor;
      const size_t siblings = d == 0 ? 1 : 8;
      for (size_t g0 = begin; g0 < end; g0 += siblings)
        cells_representatives(
            d, b0, g0, siblings, [&](size_t i) { return lists[i]; }, s, subs, candidates,
            d == 0 ? nullptr : anchor_of((b0 + g0) / 8, d, anchor), out);
    });
  }

  /// (A) and (B) at the last level D ≥ 1, per sibling set of the cells [b0, b0 + m), in one
  /// pass: which cells a triangle of the parent's list T_P crosses (bit c of crossed[set] for
  /// cell c of the set), and the points to classify. A short T_P (at most kSiblingMax) needs
  /// only one witness triangle per cell and shares each triangle's plane signs between the
  /// octant tests and the side classes (sibling_masks); a longer one gets full per-cell lists
  /// (group_by_sides).
  void last_level(size_t b0, size_t m, std::vector<Requests>& requests,
                  std::vector<uint8_t>& crossed) const {
    const int d = depth_;
    parallel_for(m, kGrain, [&](size_t begin, size_t end) {
      Requests& out = requests[begin / kGrain];
      Scratch s;
      SubGrid subs;
      std::vector<uint32_t> candidates;
      Lists local;  // long lists: the set's per-cell lists
      Anchor anchor;
      std::array<std::vector<uint32_t>, 8> octant;
      for (size_t g0 = begin; g0 < end; g0 += 8) {
        const size_t parent = (b0 + g0) / 8;
        const std::span<const uint32_t> tris = parent_lists_[parent];
        const Lattice lattice = lattice_of(parent, d);
        uint8_t open = 0xFF;  // the octants without a witness yet
        if (tris.size() <= kSiblingMax) {
          const Bbox parent_box = lattice.box();
          s.planes.clear();
          s.lattice_pos.clear();
          s.lattice_neg.clear();
          for (uint32_t t : tris) {
            const Bvh::Tri tri = bvh_.triangle(t);
            const detail::PlaneSide& plane = s.planes.emplace_back(tri.a, tri.b, tri.c, parent_box);
            uint32_t pos = 0, neg = 0;
            plane.lattice_masks(lattice.planes, pos, neg);
            s.lattice_pos.push_back(pos);
            s.lattice_neg.push_back(neg);
            if (open == 0) continue;
            // A triangle whose box lies inside one octant's open box crosses that octant alone.
            const int o = inside_octant(tri, lattice.planes);
            open &= static_cast<uint8_t>(
                ~(o >= 0 ? 1u << o
                         : detail::crossed_octants(tri.a, tri.b, tri.c, lattice.planes, pos, neg,
                                                   open)));
          }
          const uint8_t cross = static_cast<uint8_t>(~open);
          crossed[g0 / 8] = cross;
          if (samples_ * samples_ * samples_ <= 64)
            sibling_masks(g0, tris, lattice, cross, anchor_of(parent, d, anchor), s, out);
          else
            sibling_representatives(d, b0, g0, cross, s, subs, out.points, out.entries);
          continue;
        }
        for (auto& list : octant) list.clear();
        for (uint32_t t : tris) {
          const Bvh::Tri tri = bvh_.triangle(t);
          const int o = inside_octant(tri, lattice.planes);
          const uint8_t cross =
              o >= 0 ? static_cast<uint8_t>(1u << o)
                     : detail::crossed_octants(tri.a, tri.b, tri.c, lattice.planes, 0xFF);
          for (uint8_t c = cross; c != 0; c &= static_cast<uint8_t>(c - 1))
            octant[std::countr_zero(c)].push_back(t);
        }
        local.start.assign(1, 0);
        local.tris.clear();
        uint8_t cross = 0;
        for (int c = 0; c < 8; ++c) {
          local.tris.insert(local.tris.end(), octant[c].begin(), octant[c].end());
          local.start.push_back(local.tris.size());
          cross |= static_cast<uint8_t>(!octant[c].empty()) << c;
        }
        crossed[g0 / 8] = cross;
        cells_representatives(
            d, b0, g0, 8, [&](size_t i) { return local[i - g0]; }, s, subs, candidates,
            anchor_of(parent, d, anchor), out);
      }
    });
  }

  /// Cells [b0, b1) of level d; `nodes` is the level's first node, `next_start` the next level's.
  /// Appends the crossed cells (d < D) and their triangles to `next` / `next_lists`.
  void block(int d, size_t b0, size_t b1, Octree::Node* nodes, size_t next_start,
             LargeVector<Coord>& next, Lists& next_lists) {
    const size_t m = b1 - b0;
    const size_t chunks = (m + kGrain - 1) / kGrain;
    const bool last = d == depth_ && d > 0;
    std::vector<Requests> requests(chunks);
    Lists lists;                   // below the last level: per cell, T_C
    std::vector<uint8_t> crossed;  // the last level: per sibling set, bit c for crossed cell c
    if (last) {
      crossed.resize(m / 8);
      last_level(b0, m, requests, crossed);
    } else {
      lists = meeting(d, b0, m);
    }
    LargeVector<uint32_t> rank;  // d < D: per crossed cell, its rank among the level's
    // The crossed cells above the maximum depth are the next level's parents, in rank order.
    if (d < depth_) {
      // The crossed cells' lists are all of `lists` (the others are empty), in cell order.
      next_lists.tris.insert(next_lists.tris.end(), lists.tris.begin(), lists.tris.end());
      const uint64_t base = next_lists.start.back();
      rank.resize(m);
      for (size_t i = 0; i < m; ++i) {
        if (lists[i].empty()) continue;
        rank[i] = static_cast<uint32_t>(next.size());
        next.push_back(coord(d, b0 + i));
        if (d >= 1) next_grand_.push_back(static_cast<uint32_t>((b0 + i) / 8));
        next_lists.start.push_back(base + lists.start[i + 1]);
      }
    }
    if (!last) representatives(d, b0, m, lists, requests);
    // (C) Classify the representatives of the whole block at once: the points one by one, the
    // references by their leaves' windings.
    std::vector<size_t> offset(chunks + 1, 0), ref_offset(chunks + 1, 0);
    for (size_t c = 0; c < chunks; ++c) {
      offset[c + 1] = offset[c] + requests[c].points.size();
      ref_offset[c + 1] = ref_offset[c] + requests[c].refs.size();
    }
    std::vector<Vec3> points, refs;
    points.reserve(offset[chunks]);
    refs.reserve(ref_offset[chunks]);
    for (Requests& r : requests) {
      points.insert(points.end(), r.points.begin(), r.points.end());
      refs.insert(refs.end(), r.refs.begin(), r.refs.end());
      std::vector<Vec3>().swap(r.points);
      std::vector<Vec3>().swap(r.refs);
    }
    ClassifyOptions options;
    options.grid_min_points = std::numeric_limits<size_t>::max();  // near-surface points only
    options.gwn = gwn_;
    const std::vector<PointClass> classes = classify(solid_, bvh_, points, options);
    const LeafWindings windings = leaf_windings(solid_, bvh_, refs, options);
    // (D) States and occupancies (a cell's entries all lie in its own chunk).
    LargeVector<uint32_t> sum(m, 0);
    parallel_for(chunks, 1, [&](size_t begin, size_t end) {
      std::vector<uint32_t> derived_halves;
      std::vector<int> winding;
      for (size_t c = begin; c < end; ++c) {
        derived_halves.clear();
        for (const Derived& x : requests[c].derived)
          derived_halves.push_back(
              derived_class(x, windings, ref_offset[c], requests[c].deltas, winding));
        for (const Entry& e : requests[c].entries)
          sum[e.cell] +=
              e.weight * (e.rep & Entry::kDerived ? derived_halves[e.rep & ~Entry::kDerived]
                                                  : halves(classes[offset[c] + e.rep]));
      }
    });
    const double total = 2.0 * samples_ * samples_ * samples_;
    parallel_for(m, kGrain, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        Octree::Node& node = nodes[b0 + i];
        node.depth = static_cast<uint8_t>(d);
        const Coord c = coord(d, b0 + i);
        node.cell = {static_cast<uint16_t>(c[0]), static_cast<uint16_t>(c[1]),
                     static_cast<uint16_t>(c[2])};
        const bool is_crossed = last ? (crossed[i / 8] >> (i % 8) & 1) != 0 : !lists[i].empty();
        if (!is_crossed) {  // the centre of an uncrossed cell is on no surface: 0 or 2
          node.state = sum[i] == 2 ? CellState::kFull : CellState::kEmpty;
          node.occupancy = sum[i] == 2 ? 1.0f : 0.0f;
        } else {
          node.state = CellState::kPartial;
          if (d == depth_) node.occupancy = static_cast<float>(sum[i] / total);
          // Crossed cells above the maximum depth are split: their children come next, in
          // rank order.
          if (d < depth_) node.first_child = static_cast<uint32_t>(next_start + 8 * rank[i]);
        }
      }
    });
  }

  const Solid& solid_;
  const Bvh& bvh_;
  VoxelBounds bounds_;
  int depth_;
  int samples_;
  double h_;
  uint64_t max_bytes_;
  std::function<void(double)> progress_;
  bool open_ = false;                 ///< some leaf is open: no shared centres
  std::optional<GwnForest> own_gwn_;  ///< built here when options.gwn is null
  std::vector<uint8_t> table_;  ///< membership per set of inside leaves (≤ kTableLeaves leaves)
  /// Sub-point p = (k·n + j)·n + i of a cell (samples³ ≤ 64): (i, j, k), without divisions.
  std::array<std::array<uint8_t, 3>, 64> sub_index_{};
  const GwnForest* gwn_ = nullptr;
  LargeVector<Coord> parents_;  ///< crossed cells of the previous level, by rank
  Lists parent_lists_;          ///< their triangles, by rank
  /// Levels d ≥ 2: per parent (by rank), its own parent's rank at level d − 2, and the
  /// triangles of those grandparents, by rank (see Anchor).
  LargeVector<uint32_t> grand_rank_, next_grand_;
  Lists grand_lists_;
};

/// Checks the options and the bounds and refuses builds beyond options.max_bytes (see octree.h).
void check_octree_request(const Solid& solid, const VoxelBounds& bounds,
                          const OctreeOptions& options) {
  if (options.depth < 0 || options.depth > kMaxDepth)
    throw InputError(parameter("depth") + ": expected a whole number from 0 to " +
                     std::to_string(kMaxDepth) + ", got " + std::to_string(options.depth));
  if (options.samples < 1 || options.samples > kMaxSamples)
    throw InputError("octree samples: expected 1 to " + std::to_string(kMaxSamples) + ", got " +
                     std::to_string(options.samples));
  const bool finite = std::isfinite(bounds.min.x) && std::isfinite(bounds.min.y) &&
                      std::isfinite(bounds.min.z) && std::isfinite(bounds.size);
  if (!finite || !(bounds.size > 0))
    throw InputError(parameter("bounds") + ": expected a finite cube of positive size");
  check_memory(kBytesPerNode * expected_nodes(covering_area(solid), bounds.size, options.depth),
               options.max_bytes, octree_subject(options.depth));
}

}  // namespace

double Octree::cell_size(int d) const { return std::ldexp(bounds.size, -d); }

double Octree::plane(int axis, uint64_t m) const {
  return bounds.min[axis] + static_cast<double>(m) * cell_size(depth);
}

Vec3 Octree::min(const Node& node) const {
  const int shift = depth - node.depth;
  return {plane(0, uint64_t{node.cell[0]} << shift), plane(1, uint64_t{node.cell[1]} << shift),
          plane(2, uint64_t{node.cell[2]} << shift)};
}

Bbox Octree::box(const Node& node) const {
  const int shift = depth - node.depth;
  Bbox b;
  b.min = min(node);
  b.max = {plane(0, (uint64_t{node.cell[0]} + 1) << shift),
           plane(1, (uint64_t{node.cell[1]} + 1) << shift),
           plane(2, (uint64_t{node.cell[2]} + 1) << shift)};
  return b;
}

std::array<uint64_t, 3> Octree::leaf_counts() const {
  std::array<uint64_t, 3> counts{0, 0, 0};
  for (const Node& node : nodes)
    if (node.first_child == 0) ++counts[static_cast<size_t>(node.state)];
  return counts;
}

namespace {
/// The octree of a solid with no leaf, the empty set: the root alone, empty (as a cube that no
/// leaf reaches gives).
Octree empty_octree(const VoxelBounds& bounds, const OctreeOptions& options) {
  Octree tree;
  tree.bounds = bounds;
  tree.depth = options.depth;
  tree.nodes.push_back(Octree::Node{});
  return tree;
}
}  // namespace

Octree build_octree(const Solid& solid, const VoxelBounds& bounds, const OctreeOptions& options) {
  check_octree_request(solid, bounds, options);
  if (solid.leaves.empty()) return empty_octree(bounds, options);
  const Bvh bvh(solid);
  return Builder(solid, bvh, bounds, options).run();
}

Octree build_octree(const Solid& solid, const Bvh& bvh, const VoxelBounds& bounds,
                    const OctreeOptions& options) {
  check_octree_request(solid, bounds, options);
  if (solid.leaves.empty()) return empty_octree(bounds, options);
  return Builder(solid, bvh, bounds, options).run();
}

}  // namespace cover
