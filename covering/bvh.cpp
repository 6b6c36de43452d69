#include "cover/covering/bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "cover/covering/detail/float_bounds.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"

namespace cover {
namespace {

/// What the build moves around (40 bytes instead of a 104-byte triangle): the triangle's box as
/// outward-rounded floats (already widened by the margin, see Bvh::Node), its centroid, and its
/// input position (the tie-breaker that keeps splits deterministic).
struct Ref {
  float lo[3], hi[3], c[3];
  uint32_t index;
};

constexpr int kBins = 16;           // SAH bins over the centroid extent of the widest axis
constexpr uint32_t kSahDepth = 64;  // deeper nodes use median splits: depth ≤ 64 + log2(n) + 1

/// Half the surface area of a box (the SAH weight of a node).
double half_area(const float lo[3], const float hi[3]) {
  const double dx = double{hi[0]} - lo[0], dy = double{hi[1]} - lo[1], dz = double{hi[2]} - lo[2];
  return dx * dy + dy * dz + dz * dx;
}

/// A subtree built by one task: above the parallel threshold an inner node with two child
/// pieces, below it a serially built run of nodes whose inner `first` are local indices.
struct Piece {
  Bvh::Node node;
  std::vector<Bvh::Node> nodes;
  std::unique_ptr<Piece> left, right;
  uint32_t size = 0;  ///< nodes of the subtree
};

/// A node's box and the box of its triangles' centroids.
struct Extent {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  float clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
  void add(const Ref& r) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], r.lo[a]);
      hi[a] = std::max(hi[a], r.hi[a]);
      clo[a] = std::min(clo[a], r.c[a]);
      chi[a] = std::max(chi[a], r.c[a]);
    }
  }
  void add(const Extent& e) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], e.lo[a]);
      hi[a] = std::max(hi[a], e.hi[a]);
      clo[a] = std::min(clo[a], e.clo[a]);
      chi[a] = std::max(chi[a], e.chi[a]);
    }
  }
};

struct Builder {
  LargeBuffer<Ref>& refs;
  const BvhOptions& options;

  Extent extent(uint32_t begin, uint32_t end) const {
    Extent e;
    for (uint32_t i = begin; i < end; ++i) e.add(refs[i]);
    return e;
  }

  /// Sets node's bounds to `e` (the extent of refs[begin, end)); false for a leaf, else
  /// partitions the range into [begin, mid) and [mid, end), both non-empty, and sets the
  /// halves' extents: binned SAH on the widest centroid axis (the halves' extents are unions of
  /// the bins': min and max are exact, so they equal a pass over the halves, which is saved), or
  /// the centroid median when SAH finds no split (all centroids in one bin) or the node is deep.
  bool split(const Extent& e, Bvh::Node& node, uint32_t begin, uint32_t end, uint32_t depth,
             uint32_t& mid, Extent& left, Extent& right) {
    const uint32_t n = end - begin;
    for (int a = 0; a < 3; ++a) node.lo[a] = e.lo[a], node.hi[a] = e.hi[a];
    node.count = 0;
    if (n <= options.leaf_size) return false;
    const float ex = e.chi[0] - e.clo[0], ey = e.chi[1] - e.clo[1], ez = e.chi[2] - e.clo[2];
    const int axis = ex >= ey && ex >= ez ? 0 : (ey >= ez ? 1 : 2);
    const float width = e.chi[axis] - e.clo[axis];
    if (depth < kSahDepth && width > 0) {
      // In double: kBins / width stays finite even for a denormal float width, and
      // (c - clo) * scale lies in [0, kBins] up to rounding, so the int conversion is defined.
      const double scale = kBins / double{width};
      const float clo = e.clo[axis];
      auto bin = [&](const Ref& r) {
        return std::clamp(static_cast<int>((double{r.c[axis]} - clo) * scale), 0, kBins - 1);
      };
      uint32_t count[kBins] = {};
      Extent bins[kBins];
      for (uint32_t i = begin; i < end; ++i) {
        const Ref& r = refs[i];
        const int b = bin(r);
        ++count[b];
        bins[b].add(r);
      }
      // cost[b]: SAH cost of splitting after bin b (area × count on each side); least b on ties.
      double right_cost[kBins];
      Extent suffix;
      uint32_t rn = 0;
      for (int b = kBins - 1; b > 0; --b) {
        rn += count[b];
        suffix.add(bins[b]);
        right_cost[b] = rn > 0 ? half_area(suffix.lo, suffix.hi) * rn : 0;
      }
      Extent prefix;
      uint32_t ln = 0;
      int best = -1;
      double best_cost = INFINITY;
      for (int b = 0; b + 1 < kBins; ++b) {
        ln += count[b];
        prefix.add(bins[b]);
        if (ln == 0 || ln == n) continue;
        const double cost = half_area(prefix.lo, prefix.hi) * ln + right_cost[b + 1];
        if (cost < best_cost) best_cost = cost, best = b;
      }
      if (best >= 0) {
        mid = static_cast<uint32_t>(std::partition(refs.begin() + begin, refs.begin() + end,
                                                   [&](const Ref& r) { return bin(r) <= best; }) -
                                    refs.begin());
        left = right = Extent{};
        for (int b = 0; b < kBins; ++b) (b <= best ? left : right).add(bins[b]);
        return true;
      }
    }
    mid = begin + n / 2;
    std::nth_element(refs.begin() + begin, refs.begin() + mid, refs.begin() + end,
                     [axis](const Ref& l, const Ref& r) {
                       return l.c[axis] < r.c[axis] ||
                              (l.c[axis] == r.c[axis] && l.index < r.index);
                     });
    left = extent(begin, mid);
    right = extent(mid, end);
    return true;
  }

  /// Builds the subtree of refs[begin, end) (extent e) with its root written to out[slot] and
  /// its other nodes appended to `out`, children pairs in depth-first order.
  void build_serial(std::vector<Bvh::Node>& out, uint32_t slot, uint32_t begin, uint32_t end,
                    uint32_t depth, const Extent& e) {
    Bvh::Node node;
    uint32_t mid = 0;
    Extent left, right;
    if (!split(e, node, begin, end, depth, mid, left, right)) {
      node.first = begin;
      node.count = end - begin;
      out[slot] = node;
      return;
    }
    node.first = static_cast<uint32_t>(out.size());
    out[slot] = node;
    out.resize(out.size() + 2);
    build_serial(out, node.first, begin, mid, depth + 1, left);
    build_serial(out, node.first + 1, mid, end, depth + 1, right);
  }

  /// Builds the subtree of refs[begin, end) (extent e) into `piece`, both halves in parallel
  /// above the threshold (the tree does not depend on which thread builds what).
  void build(Piece& piece, uint32_t begin, uint32_t end, uint32_t depth, const Extent& e) {
    uint32_t mid = 0;
    Extent left, right;
    if (end - begin < options.parallel_threshold ||
        !split(e, piece.node, begin, end, depth, mid, left, right)) {
      piece.nodes.reserve(2 * (end - begin) / options.leaf_size + 1);
      piece.nodes.resize(1);
      build_serial(piece.nodes, 0, begin, end, depth, e);
      piece.size = static_cast<uint32_t>(piece.nodes.size());
      return;
    }
    piece.left = std::make_unique<Piece>();
    piece.right = std::make_unique<Piece>();
    parallel_invoke([&] { build(*piece.left, begin, mid, depth + 1, left); },
                    [&] { build(*piece.right, mid, end, depth + 1, right); });
    piece.size = 1 + piece.left->size + piece.right->size;
  }

  /// Copies `piece` into the tree: its root to nodes[slot], its other nodes (piece.size − 1,
  /// an even number: children pairs) to nodes[at, ...), making child indices global. A serial
  /// piece's local pairs start at index 1, so local i > 0 goes to at + i − 1.
  static void place(const Piece& piece, LargeVector<Bvh::Node>& nodes, uint32_t slot, uint32_t at) {
    if (!piece.left) {
      for (size_t i = 0; i < piece.nodes.size(); ++i) {
        Bvh::Node node = piece.nodes[i];
        if (node.count == 0) node.first += at - 1;
        nodes[i == 0 ? slot : at + i - 1] = node;
      }
      return;
    }
    Bvh::Node& node = nodes[slot];
    node = piece.node;
    node.first = at;
    const uint32_t left_at = at + 2, right_at = left_at + piece.left->size - 1;
    parallel_invoke([&] { place(*piece.left, nodes, at, left_at); },
                    [&] { place(*piece.right, nodes, at + 1, right_at); });
  }
};

/// Reorders the children pairs (depth-first from Builder::place) into treelets: the pairs of
/// Bvh::kTreeletLevels consecutive levels below a treelet's root pair are stored contiguously,
/// breadth first, and the treelets in depth-first order; a treelet's root pairs lie at pair
/// depths 0, kTreeletLevels, 2·kTreeletLevels, ... (pair depth 0: the root's children). Why:
/// a walk that reaches a treelet's root pair can fetch the whole treelet at once (walk_batch
/// does for small batches), so one ray waits for memory once per kTreeletLevels levels instead
/// of once per level. Child links are remapped; nodes 0 and 1 stay.
void treelet_order(LargeVector<Bvh::Node>& nodes) {
  if (nodes.size() < 4 || nodes[0].count > 0) return;
  const size_t pairs = (nodes.size() - 2) / 2;
  auto pair_of = [](uint32_t node) { return (node - 2) / 2; };  // node index → pair number
  LargeVector<uint32_t> order;                                  // pair numbers in the new order
  order.reserve(pairs);
  std::vector<uint32_t> roots{pair_of(nodes[0].first)}, level, below;
  while (!roots.empty()) {
    level.assign(1, roots.back());
    roots.pop_back();
    for (int d = 0; d < Bvh::kTreeletLevels && !level.empty(); ++d) {
      below.clear();
      for (const uint32_t p : level) {
        order.push_back(p);
        for (const uint32_t c : {2 + 2 * p, 3 + 2 * p})
          if (nodes[c].count == 0) below.push_back(pair_of(nodes[c].first));
      }
      level.swap(below);
    }
    roots.insert(roots.end(), level.rbegin(), level.rend());  // leftmost treelet next
  }
  if (order.size() != pairs) throw InternalError("BVH: children pairs do not form one tree");
  LargeVector<uint32_t> to(pairs);  // pair number → its new pair number
  for (uint32_t k = 0; k < pairs; ++k) to[order[k]] = k;
  // Child links first, then the pairs moved in place along the permutation's cycles (no second
  // node array: at 10k triangles its fresh pages cost more than the whole reordering).
  for (Bvh::Node& node : nodes)
    if (node.count == 0 && node.first >= 2) node.first = 2 + 2 * to[pair_of(node.first)];
  for (uint32_t start = 0; start < pairs; ++start) {
    if (to[start] == start) continue;
    Bvh::Node carry[2] = {nodes[2 + 2 * start], nodes[3 + 2 * start]};
    uint32_t at = start;
    while (to[at] != start) {  // put carry at its place, pick up what was there
      const uint32_t dest = to[at];
      std::swap(carry[0], nodes[2 + 2 * dest]);
      std::swap(carry[1], nodes[3 + 2 * dest]);
      to[at] = at;  // done
      at = dest;
    }
    nodes[2 + 2 * start] = carry[0];
    nodes[3 + 2 * start] = carry[1];
    to[at] = at;
  }
}

}  // namespace

namespace {

/// The covering triangles of `solid` as the build sees them: triangle g (numbered face by face,
/// fan order, degenerate ones included) is (v0, v_k, v_k+1) of face face_of[g], k = g − start + 1.
struct FanTriangles {
  LargeVector<uint32_t> start;    ///< first triangle of each face (#faces + 1)
  LargeVector<uint32_t> face_of;  ///< face of each triangle
  explicit FanTriangles(const Solid& solid) : start(solid.face_count() + 1, 0) {
    const size_t faces = solid.face_count();
    for (size_t f = 0; f < faces; ++f) {
      const size_t k = solid.face(f).size();
      start[f + 1] = start[f] + static_cast<uint32_t>(k >= 3 ? k - 2 : 0);
    }
    face_of.resize(start[faces]);
    parallel_for(faces, 4096, [&](size_t begin, size_t end) {
      for (size_t f = begin; f < end; ++f)
        for (uint32_t g = start[f]; g < start[f + 1]; ++g) face_of[g] = static_cast<uint32_t>(f);
    });
  }
  size_t size() const { return face_of.size(); }
  /// The vertex indices of triangle g in its leaf's own orientation (outward).
  std::array<uint32_t, 3> corners(const Solid& solid, uint32_t g) const {
    const uint32_t f = face_of[g];
    const auto face = solid.face(f);
    const bool rev = solid.face_sign[f] < 0;  // back to the leaf's own orientation
    auto at = [&](size_t i) { return face[rev ? face.size() - 1 - i : i]; };
    const size_t k = g - start[f] + 1;
    return {at(0), at(k), at(k + 1)};
  }
  /// Triangle g in its leaf's own orientation (outward).
  Bvh::Tri get(const Solid& solid, uint32_t g) const {
    const uint32_t f = face_of[g];
    const auto c = corners(solid, g);
    return {solid.vertices[c[0]], solid.vertices[c[1]], solid.vertices[c[2]], solid.face_leaf[f],
            f};
  }
};

/// Whether t bounds volume (not collinear: some projected orientation is nonzero).
bool non_degenerate(const Bvh::Tri& t) {
  return orient2d(t.a, t.b, t.c, 0) != 0 || orient2d(t.a, t.b, t.c, 1) != 0 ||
         orient2d(t.a, t.b, t.c, 2) != 0;
}

}  // namespace

Bvh::Bvh(const Solid& solid, const BvhOptions& options) {
  // The triangles are read from the faces several times (plane/keep/bounds, refs, leaf blocks)
  // instead of being copied into an intermediate array, which at 606k triangles would be 48 MB
  // of fresh memory to fault in (solid/large_vector.h).
  const size_t faces = solid.face_count();
  const size_t leaves = solid.leaves.size();
  const FanTriangles fan(solid);
  leaf_bounds_.resize(leaves);
  size_t polygons = 0;  // faces with more than one fan triangle: they get a stored plane
  for (size_t f = 0; f < faces; ++f) polygons += fan.start[f + 1] - fan.start[f] > 1;
  if (polygons > 0) {
    plane_of_.assign(faces, UINT32_MAX);
    uint32_t next = 0;
    for (size_t f = 0; f < faces; ++f)
      if (fan.start[f + 1] - fan.start[f] > 1) plane_of_[f] = next++;
    planes_.resize(polygons);
  }
  // 1. Face planes, the non-degenerate triangles, and each leaf's exact box (per chunk, then
  //    merged in chunk order).
  constexpr size_t kChunk = 4096;  // faces
  const size_t chunks = (faces + kChunk - 1) / kChunk;
  std::vector<uint8_t> keep(fan.size(), 0);
  std::vector<Bbox> chunk_bounds(chunks * leaves);
  parallel_for(faces, kChunk, [&](size_t begin, size_t end) {
    Bbox* boxes = chunk_bounds.data() + begin / kChunk * leaves;
    for (size_t f = begin; f < end; ++f) {
      Vec3 n{};
      for (uint32_t g = fan.start[f]; g < fan.start[f + 1]; ++g) {
        const Tri t = fan.get(solid, g);
        n = n + cross(t.b - t.a, t.c - t.a);
        if (!non_degenerate(t)) continue;
        keep[g] = 1;
        Bbox& box = boxes[t.leaf];
        box.add(t.a);
        box.add(t.b);
        box.add(t.c);
      }
      if (!plane_of_.empty() && plane_of_[f] != UINT32_MAX)
        planes_[plane_of_[f]] = {fan.get(solid, fan.start[f]).a, n};
    }
  });
  for (size_t c = 0; c < chunks; ++c)
    for (size_t l = 0; l < leaves; ++l)
      if (const Bbox& b = chunk_bounds[c * leaves + l]; !b.empty()) {
        leaf_bounds_[l].add(b.min);
        leaf_bounds_[l].add(b.max);
      }
  // Kept triangles numbered in order: kept[g] = number of kept triangles before g.
  LargeVector<uint32_t> kept(fan.size() + 1, 0);
  for (size_t g = 0; g < fan.size(); ++g) kept[g + 1] = kept[g] + keep[g];
  const uint32_t n = kept[fan.size()];
  if (n == 0) return;
  for (const Bbox& b : leaf_bounds_)
    if (!b.empty()) {
      bounds_.add(b.min);
      bounds_.add(b.max);
    }
  // Widen node bounds by 1e-9 of the scene's scale: a ray slab test in doubles then errs far less
  // than the widening, so it can drop no box the exact ray meets (ray.cpp needs no padding).
  double scale = 0;
  for (int a = 0; a < 3; ++a)
    scale = std::max({scale, std::abs(bounds_.min[a]), std::abs(bounds_.max[a])});
  const double margin = 1e-9 * scale;
  // 2. One Ref per kept triangle, in triangle order; index = the triangle number g (increasing
  //    with the position, the tie-breaker of median splits).
  LargeBuffer<Ref> refs(n);  // written in full by the parallel loop below (first touch too)
  parallel_for(faces, kChunk, [&](size_t begin, size_t end) {
    for (uint32_t g = fan.start[begin]; g < fan.start[end]; ++g) {
      if (!keep[g]) continue;
      const Tri t = fan.get(solid, g);
      Ref& r = refs[kept[g]];
      for (int a = 0; a < 3; ++a) {
        r.lo[a] = detail::float_down(std::min({t.a[a], t.b[a], t.c[a]}) - margin);
        r.hi[a] = detail::float_up(std::max({t.a[a], t.b[a], t.c[a]}) + margin);
        r.c[a] = static_cast<float>((t.a[a] + t.b[a] + t.c[a]) / 3);
      }
      r.index = g;
    }
  });
  // 3. The tree, then the triangles in leaf-node order.
  BvhOptions o = options;
  o.leaf_size = std::clamp<uint32_t>(o.leaf_size, 1, kMaxLeafSize);
  Builder builder{refs, o};
  Piece root;
  builder.build(root, 0, n, 0, builder.extent(0, n));
  // The root, an unused node (so that every children pair starts at an even index: one 64-byte
  // cache line when the array is 64-byte aligned, as LargeVector's mapped blocks are), the pairs.
  nodes_.resize(root.size + 1);
  Builder::place(root, nodes_, 0, 2);
  nodes_[1] = Node{};
  for (int a = 0; a < 3; ++a) nodes_[1].lo[a] = INFINITY, nodes_[1].hi[a] = -INFINITY;
  treelet_order(nodes_);
  // 4. The leaf blocks (Bvh::LeafBlock), in node order: sizes (distinct vertex indices per
  //    leaf), offsets, then the blocks, each leaf's triangles read from the faces again.
  std::vector<uint32_t> leaf_nodes;
  for (uint32_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].count > 0) leaf_nodes.push_back(i);
  leaves_ = leaf_nodes.size();
  // A leaf node's distinct vertices (by index: a vertex is stored once per block) and each
  // triangle's slots among them; returns their number. Indices only: the first pass (sizes)
  // reads no coordinates.
  auto gather = [&](const Node& node, uint32_t* verts, uint8_t* slots) {
    uint32_t nv = 0;
    for (uint32_t k = 0; k < node.count; ++k) {
      const auto c = fan.corners(solid, refs[node.first + k].index);
      for (int i = 0; i < 3; ++i) {
        uint32_t s = 0;
        while (s < nv && verts[s] != c[i]) ++s;
        if (s == nv) verts[nv++] = c[i];
        slots[3 * k + i] = static_cast<uint8_t>(s);
      }
    }
    return nv;
  };
  auto words = [](uint32_t count, uint32_t verts) {
    return (LeafBlock::vertices_offset(count) + sizeof(Vec3) * verts) / 8;
  };
  LargeVector<uint64_t> offset(leaf_nodes.size() + 1, 0);
  parallel_for(leaf_nodes.size(), 1024, [&](size_t begin, size_t end) {
    uint32_t verts[3 * kMaxLeafSize];
    uint8_t slots[3 * kMaxLeafSize];
    for (size_t l = begin; l < end; ++l) {
      const Node& node = nodes_[leaf_nodes[l]];
      offset[l + 1] = words(node.count, gather(node, verts, slots));
    }
  });
  for (size_t l = 0; l < leaf_nodes.size(); ++l) offset[l + 1] += offset[l];
  if (offset[leaf_nodes.size()] > UINT32_MAX)
    throw NotComputable("BVH leaf blocks exceed 32 GB (too many triangles for one BVH)");
  // Not zero-filled (LargeBuffer): the loop below writes every word of every block (its memset
  // included) and every triangle's block_of_ entry, from both threads.
  blocks_.resize(offset[leaf_nodes.size()]);
  block_of_.resize(n);
  parallel_for(leaf_nodes.size(), 1024, [&](size_t begin, size_t end) {
    uint32_t verts[3 * kMaxLeafSize];
    uint8_t slots[3 * kMaxLeafSize];
    for (size_t l = begin; l < end; ++l) {
      Node& node = nodes_[leaf_nodes[l]];
      const uint32_t nv = gather(node, verts, slots);
      auto* p = reinterpret_cast<unsigned char*>(&blocks_[offset[l]]);
      std::memset(p, 0, 8 * words(node.count, nv));
      const uint32_t first = node.first;  // the leaf's first triangle (refs order)
      std::memcpy(p, &first, 4);
      p[4] = static_cast<uint8_t>(node.count);
      for (uint32_t k = 0; k < node.count; ++k) {
        const uint32_t face = fan.face_of[refs[first + k].index];
        const uint32_t leaf = solid.face_leaf[face];
        unsigned char* r = p + LeafBlock::record_offset(k);
        std::memcpy(r, &leaf, 4);
        std::memcpy(r + 4, &face, 4);
        std::memcpy(r + 8, &slots[3 * k], 3);
        block_of_[first + k] = static_cast<uint32_t>(offset[l]);
      }
      unsigned char* v = p + LeafBlock::vertices_offset(node.count);
      for (uint32_t i = 0; i < nv; ++i)
        std::memcpy(v + sizeof(Vec3) * i, &solid.vertices[verts[i]], sizeof(Vec3));
      node.first = static_cast<uint32_t>(offset[l]);
    }
  });
}

size_t Bvh::memory_bytes() const {
  return blocks_.capacity() * sizeof(uint64_t) + block_of_.capacity() * sizeof(uint32_t) +
         nodes_.capacity() * sizeof(Node) + planes_.capacity() * sizeof(FacePlane) +
         plane_of_.capacity() * sizeof(uint32_t);
}

}  // namespace cover
