#pragma once
// Bounding volume hierarchy over the covering triangles of every leaf (docs/design.md#exactness).
//
// Why hand-written: queries need exact culling on double boxes for an axis-aligned half-line
// (classification) and for general rays, plus the triangle's leaf and face; CGAL's AABB_tree
// (the peer) stores a primitive per node with slower traversal (bench/compare_cgal measures both).
// Layout: 32-byte nodes; the root is node 0 (node 1 is unused), and the two children of an inner
// node are nodes `first` and `first + 1`, a pair at an even index (one 64-byte cache line for
// both boxes a traversal step tests), pairs in treelets of kTreeletLevels levels (breadth first
// inside a treelet, treelets depth first; bvh.cpp treelet_order). A leaf node's triangles are
// stored in one leaf block (see LeafBlock: its distinct vertices once, then 12 bytes per
// triangle), blocks in node order. Boxes contain the exact min/max of the double coordinates, so
// "box misses ⇒ triangle misses" holds exactly. Build: binned SAH (16 bins over the centroid extent
// of the widest axis), the centroid median where SAH finds no split or below depth 64; subtrees
// above a size threshold are built in parallel into separate pieces and then placed in depth-first
// order, so the tree does not depend on the thread count.

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "cover/solid/large_vector.h"
#include "cover/solid/solid.h"

namespace cover {

struct BvhOptions {
  uint32_t leaf_size = 4;  ///< max triangles per leaf node (clamped to [1, Bvh::kMaxLeafSize])
  size_t parallel_threshold = 8192;  ///< subtrees at least this large are built in parallel
};

class Bvh {
 public:
  /// Traversals (walk, walk_batch, for_each_triangle) are internal: covering/bvh_walk.h.
  /// Bound on a traversal stack (of node ids, or node ids with intervals): a depth-first stack
  /// holds at most depth + 1 entries, and the depth is ≤ 64 (SAH) + 32 (median splits of at most
  /// 2^32 triangles) + 1 (bvh.cpp).
  static constexpr int kMaxStack = 128;
  /// Largest leaf (BvhOptions::leaf_size is clamped to it): a block's vertex slots fit a byte.
  static constexpr uint32_t kMaxLeafSize = 64;
  /// Levels of children pairs stored together as one treelet (bvh.cpp treelet_order), and the
  /// most pairs a treelet holds (contiguous from its root pair).
  static constexpr int kTreeletLevels = 3;
  static constexpr uint32_t kTreeletPairs = (1u << kTreeletLevels) - 1;
  /// A covering triangle (v0, vi, vi+1) of a face, in its LEAF's own orientation (outward).
  struct Tri {
    Vec3 a, b, c;
    uint32_t leaf = 0;
    uint32_t face = 0;  ///< face index in the Solid
  };
  /// 32 bytes. Bounds are floats rounded outwards from the exact double box widened by 1e-9 of
  /// the scene's largest coordinate, so they contain it with room for a ray slab test's rounding: a
  /// half-line or ray that misses them misses every triangle below (culling only; every decision on
  /// a triangle uses its double coordinates).
  struct Node {
    float lo[3];
    float hi[3];
    uint32_t first = 0;  ///< leaf: its block's offset in 8-byte words; inner: the left child
    uint32_t count = 0;  ///< leaf: number of triangles; inner: 0
  };

  /// A leaf node's triangles as stored, a view of its block of 8-byte words: a header {uint32
  /// index of its first triangle, uint8 triangles}, one 12-byte record per triangle {uint32
  /// leaf, uint32 face, uint8 slots of its vertices a, b, c}, padded to 8 bytes, then the
  /// block's distinct vertices (by vertex index; 24 bytes each, the exact doubles). Why: a leaf
  /// of a mesh shares most vertices between its triangles (3.2 triangles and about 5.5 vertices
  /// per leaf on the benchmark sphere), so the BVH takes 80 bytes per triangle instead of 100,
  /// and a leaf read touches about 4 cache lines instead of 5–6 (docs/benchmarks.md). Fields are
  /// read with memcpy (the words hold bytes of several types).
  class LeafBlock {
   public:
    explicit LeafBlock(const uint64_t* words) : p_(reinterpret_cast<const unsigned char*>(words)) {}
    /// Index of the block's first triangle; its triangles are first() .. first() + size() − 1.
    uint32_t first() const {
      uint32_t f;
      std::memcpy(&f, p_, 4);
      return f;
    }
    uint32_t size() const { return p_[4]; }
    /// Triangle k < size() of the block.
    Tri operator[](uint32_t k) const {
      const unsigned char* r = p_ + record_offset(k);
      const unsigned char* v = p_ + vertices_offset(size());
      Tri t;
      std::memcpy(&t.a, v + 24 * r[8], sizeof(Vec3));
      std::memcpy(&t.b, v + 24 * r[9], sizeof(Vec3));
      std::memcpy(&t.c, v + 24 * r[10], sizeof(Vec3));
      std::memcpy(&t.leaf, r, 4);
      std::memcpy(&t.face, r + 4, 4);
      return t;
    }
    /// Byte offset of triangle k's record (after the 8-byte header; 12 bytes each).
    static constexpr size_t record_offset(size_t k) { return 8 + 12 * k; }
    /// Byte offset of the vertices in a block of `triangles` triangles.
    static constexpr size_t vertices_offset(size_t triangles) {
      return (record_offset(triangles) + 7) & ~size_t{7};
    }

   private:
    const unsigned char* p_;
  };

  /// Builds over every non-degenerate covering triangle of `solid` (collinear ones are dropped:
  /// they bound no volume and no perturbed ray crosses them).
  explicit Bvh(const Solid& solid, const BvhOptions& options = {});

  /// The plane used for hit distances on a face of more than three vertices: its first vertex
  /// and Newell normal (the sum of its fan triangles' normals). All covering triangles of the
  /// face share it, so coincident fan triangles (non-convex faces, false edges) give
  /// bit-identical t. A triangular face's plane is its triangle's own (a, cross(b − a, c − a)),
  /// so none is stored for it (48 bytes per face: 29 MB for the 606k-face render benchmark).
  struct FacePlane {
    Vec3 point;
    Vec3 normal;
  };

  /// Number of triangles (the non-degenerate covering triangles, numbered leaf block by block).
  size_t triangle_count() const { return block_of_.size(); }
  /// Triangle i < triangle_count() (through its block: for random access off the hot paths).
  Tri triangle(uint32_t i) const {
    const LeafBlock b(&blocks_[block_of_[i]]);
    return b[i - b.first()];
  }
  /// The block of a leaf node (node.count > 0).
  LeafBlock block(const Node& leaf) const { return LeafBlock(&blocks_[leaf.first]); }
  const uint64_t* block_words() const { return blocks_.data(); }
  /// The stored plane of face f, or nullptr for a triangular face (use the triangle's plane).
  const FacePlane* face_plane(uint32_t face) const {
    if (plane_of_.empty() || plane_of_[face] == UINT32_MAX) return nullptr;
    return &planes_[plane_of_[face]];
  }
  const LargeVector<Node>& nodes() const { return nodes_; }
  /// Exact bounding box of all triangles (empty when there are none).
  const Bbox& bounds() const { return bounds_; }
  /// Exact bounding box of each leaf's triangles, by leaf id (#leaves; empty for a leaf without
  /// triangles).
  const std::vector<Bbox>& leaf_bounds() const { return leaf_bounds_; }
  size_t leaf_count() const { return leaves_; }
  /// Bytes held by the structure (leaf blocks, nodes, face planes, triangle index).
  size_t memory_bytes() const;

 private:
  LargeBuffer<uint64_t> blocks_;    ///< the leaf blocks, in node order
  LargeBuffer<uint32_t> block_of_;  ///< per triangle: its block's offset (for triangle(i))
  LargeVector<Node> nodes_;
  LargeVector<FacePlane> planes_;   ///< of the faces with more than three vertices, in order
  LargeVector<uint32_t> plane_of_;  ///< per face: index into planes_ or UINT32_MAX; empty if none
  Bbox bounds_;
  std::vector<Bbox> leaf_bounds_;
  size_t leaves_ = 0;
};

}  // namespace cover
