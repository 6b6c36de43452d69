#pragma once
// Direct octree generation from a non-evaluated CSG solid ([Segura2004 §7]), exact and
// conservative: a cell is kFull / kEmpty only if truly so — no leaf surface meets the cell's
// INTERIOR (exact triangle–open-box overlap against every covering triangle that may meet the
// cell, found through the BVH or the parent cell's list) and its centre classifies inside /
// outside (covering/classify.h). A surface that only touches the cell's boundary (a cell beside
// a box face, from outside or inside) leaves it kEmpty / kFull. Crossed cells
// split down to `depth`; crossed cells at that depth are kPartial with an occupancy fraction
// (the share of `samples`³ regularly spaced sub-points classified inside).

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "cover/covering/bvh.h"
#include "cover/covering/gwn.h"
#include "cover/covering/prepared.h"
#include "cover/solid/memory_limit.h"
#include "cover/solid/solid.h"
#include "cover/solid/voxel_bounds.h"

namespace cover {

enum class CellState : uint8_t { kEmpty = 0, kFull = 1, kPartial = 2 };

struct OctreeOptions {
  int depth = 6;    ///< maximum depth (root = 0), 0..16; cells at depth D have side size/2^D
  int samples = 4;  ///< occupancy of partial cells: samples³ sub-points per cell, 1..32
  /// Refuse builds expected to need more memory (the command's --max-memory), in bytes.
  uint64_t max_bytes = kDefaultMaxMemoryBytes;
  /// Called on the calling thread after each block of cells with the estimated share of the work
  /// done, 0..1 (levels weighted by 4^d, the growth of crossed cells); default: none.
  std::function<void(double)> progress;
};

/// Nodes in breadth-first order; children of an inner node are 8 consecutive nodes starting at
/// `first_child`, in Morton order: child c has offset (c&1, (c>>1)&1, (c>>2)&1) along (x, y, z).
/// Within a depth, nodes keep their parents' order — the breadth-first vertex order of a VTK
/// HyperTree. Cell faces are the grid planes bounds.min + m·cell_size(depth) (m whole) computed
/// in doubles, the same values at every depth, so children tile their parent exactly.
struct Octree {
  struct Node {
    uint32_t first_child = 0;  ///< 0 for a leaf cell (the root is node 0, never a child)
    uint8_t depth = 0;
    CellState state = CellState::kEmpty;  ///< inner nodes: kPartial
    /// 1 full, 0 empty; partial leaves: the share of their samples³ sub-points (the centres of a
    /// regular sub-grid) inside, points on the surface counting ½; inner nodes: the mean of their
    /// children.
    float occupancy = 0;
    /// Integer corner (i, j, k) at its depth: the cell spans grid planes i·2^(D−depth) ..
    /// (i+1)·2^(D−depth) along x, and so on (Octree::min / box give the doubles). 16 bytes a
    /// node: the array of a depth-10 tree is written once, and fresh pages are dear.
    std::array<uint16_t, 3> cell{0, 0, 0};
  };
  VoxelBounds bounds;
  int depth = 0;
  std::vector<Node> nodes;

  /// Side of the cells at depth d: bounds.size / 2^d.
  double cell_size(int d) const;
  /// Grid plane m (0 ≤ m ≤ 2^depth) of `axis`: bounds.min[axis] + m·cell_size(depth).
  double plane(int axis, uint64_t m) const;
  /// The node's lower corner (grid planes) and its closed box [min, next grid planes].
  Vec3 min(const Node& node) const;
  Bbox box(const Node& node) const;
  /// Leaf cells by state: {empty, full, partial}.
  std::array<uint64_t, 3> leaf_counts() const;
};

/// Builds the octree of `solid` over `bounds`: level by level, the cells no leaf surface meets
/// become full / empty leaves, the others split (or, at `options.depth`, become partial leaves).
/// Memory and time grow with the number of crossed cells, not with 8^depth. TBB-parallel; the
/// result does not depend on the thread count. Preconditions: closed leaves. Throws InputError
/// for options out of range or bounds that are not a finite cube of positive size, and the
/// check_memory() message "--depth D: the octree needs N MiB, ..." (solid/memory_limit.h) when
/// the expected memory exceeds options.max_bytes: before building, from the surface area (a
/// surface of area A meets about 1.5·A/h² cells of side h), and again before each level from its
/// exact node count; NotComputable beyond 2^32 nodes.
/// Field leaves: cells full / empty only where covering/box_states.h certifies them (interval
/// bounds of each field over the closed cell), undecided cells split and, at the depth, sampled
/// (octree/detail/field_octree.h); NotComputable with open leaves beside them.
/// Open leaves (through the Prepared's trees, covering/gwn.h): cells the surface does not cross
/// take the class of their own centre (the winding-number membership is not constant there: an
/// approximation, docs/design.md).
Octree build_octree(const Prepared& prepared, const VoxelBounds& bounds,
                    const OctreeOptions& options);

/// One-shot: prepares the solid, then builds. \throws as above.
Octree build_octree(const Solid& solid, const VoxelBounds& bounds, const OctreeOptions& options);

}  // namespace cover
