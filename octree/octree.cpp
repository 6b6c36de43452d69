#include "cover/octree/octree.h"

#include <cmath>
#include <string>

#include "cover/octree/detail/builder.h"
#include "cover/octree/detail/field_octree.h"
#include "cover/solid/errors.h"
#include "cover/solid/large_vector.h"
#include "cover/solid/parallel.h"

// (C)–(D) of the builder (detail/builder.h: the notation) and the level loop; the public entry
// points.

namespace cover {
namespace octree_build {
namespace {

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

}  // namespace

std::string octree_subject(int depth) {
  return parameter("depth") + " " + std::to_string(depth) + ": the octree";
}

Builder::Builder(const Prepared& prepared, const VoxelBounds& bounds, const OctreeOptions& options)
    : prepared_(prepared),
      solid_(prepared.solid()),
      bvh_(prepared.bvh()),
      bounds_(bounds),
      depth_(options.depth),
      samples_(options.samples),
      h_(std::ldexp(bounds.size, -options.depth)),
      max_bytes_(options.max_bytes),
      progress_(options.progress),
      open_(solid_.has_open_leaf()) {
  if (solid_.leaves.size() <= kTableLeaves) table_ = solid_.tree.truth_table(solid_.leaves.size());
  const int n = samples_;
  for (int p = 0; p < std::min(n * n * n, 64); ++p)
    sub_index_[p] = {static_cast<uint8_t>(p % n), static_cast<uint8_t>(p / n % n),
                     static_cast<uint8_t>(p / n / n)};
}

Octree Builder::run() {
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

/// Twice the class (halves()) of a derived side class: its reference's windings plus its
/// deltas, the expression evaluated on them; classified directly should the reference lie on
/// a surface (it cannot: it is on no plane of T_P, in the parent's interior). `refs_begin`:
/// the chunk's first reference in `windings`.
uint32_t Builder::derived_class(const Derived& x, const LeafWindings& windings, size_t refs_begin,
                                const std::vector<Delta>& deltas, std::vector<int>& winding) const {
  const size_t leaves = windings.leaves;
  const size_t at = (refs_begin + x.ref) * leaves;
  bool on_surface = false;
  winding.assign(windings.winding.begin() + at, windings.winding.begin() + at + leaves);
  for (size_t l = 0; l < leaves; ++l) on_surface |= windings.on_surface[at + l] != 0;
  if (on_surface) {
    return halves(classify(prepared_, std::span<const Vec3>(&x.point, 1))[0]);
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

/// Cells [b0, b1) of level d; `nodes` is the level's first node, `next_start` the next level's.
/// Appends the crossed cells (d < D) and their triangles to `next` / `next_lists`.
void Builder::block(int d, size_t b0, size_t b1, Octree::Node* nodes, size_t next_start,
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
  const std::vector<PointClass> classes = classify(prepared_, points, options);
  const LeafWindings windings = leaf_windings(prepared_, refs, options);
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

}  // namespace octree_build

namespace {

using octree_build::Builder;
using octree_build::covering_area;
using octree_build::expected_nodes;
using octree_build::kBytesPerNode;
using octree_build::kMaxDepth;
using octree_build::kMaxSamples;
using octree_build::octree_subject;

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

Octree build_octree(const Prepared& prepared, const VoxelBounds& bounds,
                    const OctreeOptions& options) {
  check_octree_request(prepared.solid(), bounds, options);
  if (prepared.solid().leaves.empty()) return empty_octree(bounds, options);
  // Field and warp leaves (open leaves beside them too: box_states settles an open leaf by its
  // closure) take the three-valued route.
  if (prepared.solid().has_implicit_leaf())
    return octree_build::build_field_octree(prepared, bounds, options);
  return Builder(prepared, bounds, options).run();
}

Octree build_octree(const Solid& solid, const VoxelBounds& bounds, const OctreeOptions& options) {
  const Prepared prepared(solid);
  return build_octree(prepared, bounds, options);
}

}  // namespace cover
