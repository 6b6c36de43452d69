#include "cover/octree/detail/field_octree.h"

#include <algorithm>
#include <cmath>

#include "cover/covering/box_states.h"
#include "cover/covering/classify.h"
#include "cover/octree/detail/builder.h"
#include "cover/solid/errors.h"
#include "cover/solid/memory_limit.h"
#include "cover/solid/parallel.h"

namespace cover::octree_build {

Octree build_field_octree(const Prepared& prepared, const VoxelBounds& bounds,
                          const OctreeOptions& options) {
  Octree tree;
  tree.bounds = bounds;
  tree.depth = options.depth;
  tree.nodes.push_back(Octree::Node{});
  std::vector<uint32_t> level{0}, next;
  std::vector<Bbox> boxes;
  const int samples = options.samples;
  const size_t per_cell = static_cast<size_t>(samples) * samples * samples;
  const double weight_total = (std::ldexp(1.0, 2 * tree.depth + 2) - 1) / 3;
  double weight_done = 0;
  for (int d = 0; d <= tree.depth && !level.empty(); ++d) {
    boxes.resize(level.size());
    for (size_t i = 0; i < level.size(); ++i) boxes[i] = tree.box(tree.nodes[level[i]]);
    const std::vector<uint8_t> state = box_states(prepared, boxes);
    next.clear();
    std::vector<uint32_t> partial;  // at the last level: the cells to sample
    size_t undecided = 0;
    for (uint8_t s : state) undecided += s == kBoxUndecided;
    if (d < tree.depth) {
      const double nodes = static_cast<double>(tree.nodes.size()) + 8.0 * undecided;
      if (nodes > UINT32_MAX)
        throw NotComputable("octree: more than 2^32 nodes; use a smaller depth");
      check_memory(kBytesPerNode * nodes, options.max_bytes, octree_subject(tree.depth));
    }
    for (size_t i = 0; i < level.size(); ++i) {
      Octree::Node& node = tree.nodes[level[i]];
      if (state[i] != kBoxUndecided) {
        node.state = state[i] == kBoxInside ? CellState::kFull : CellState::kEmpty;
        node.occupancy = state[i] == kBoxInside ? 1.0f : 0.0f;
        continue;
      }
      node.state = CellState::kPartial;
      if (d == tree.depth) {
        partial.push_back(level[i]);
        continue;
      }
      const auto first = static_cast<uint32_t>(tree.nodes.size());
      tree.nodes[level[i]].first_child = first;
      const Octree::Node parent = tree.nodes[level[i]];
      for (int c = 0; c < 8; ++c) {  // Morton order: (c&1, (c>>1)&1, (c>>2)&1) along (x, y, z)
        Octree::Node child;
        child.depth = static_cast<uint8_t>(d + 1);
        child.cell = {static_cast<uint16_t>(2 * parent.cell[0] + (c & 1)),
                      static_cast<uint16_t>(2 * parent.cell[1] + ((c >> 1) & 1)),
                      static_cast<uint16_t>(2 * parent.cell[2] + ((c >> 2) & 1))};
        tree.nodes.push_back(child);
        next.push_back(first + static_cast<uint32_t>(c));
      }
    }
    // Partial leaves: samples³ sub-point centres each, classified in batches of about 2^20.
    const size_t batch = std::max<size_t>(1, (size_t{1} << 20) / per_cell);
    std::vector<Vec3> points;
    for (size_t b = 0; b < partial.size(); b += batch) {
      const size_t e = std::min(partial.size(), b + batch);
      points.clear();
      for (size_t i = b; i < e; ++i) {
        const Bbox box = tree.box(tree.nodes[partial[i]]);
        const Vec3 size = box.max - box.min;
        for (int x = 0; x < samples; ++x)
          for (int y = 0; y < samples; ++y)
            for (int z = 0; z < samples; ++z)
              points.push_back({box.min.x + (x + 0.5) / samples * size.x,
                                box.min.y + (y + 0.5) / samples * size.y,
                                box.min.z + (z + 0.5) / samples * size.z});
      }
      const std::vector<PointClass> c = classify(prepared, points);
      for (size_t i = b; i < e; ++i) {
        double inside = 0;
        for (size_t k = 0; k < per_cell; ++k) {
          const PointClass pc = c[(i - b) * per_cell + k];
          inside += pc == PointClass::kInside ? 1.0 : (pc == PointClass::kOutside ? 0.0 : 0.5);
        }
        tree.nodes[partial[i]].occupancy = static_cast<float>(inside / per_cell);
      }
    }
    weight_done += std::ldexp(1.0, 2 * d);
    if (options.progress) options.progress(std::min(1.0, weight_done / weight_total));
    level.swap(next);
  }
  // Inner nodes: the mean of their children (children come after their parents).
  for (size_t i = tree.nodes.size(); i-- > 0;) {
    Octree::Node& node = tree.nodes[i];
    if (node.first_child == 0) continue;
    float sum = 0;
    for (int c = 0; c < 8; ++c) sum += tree.nodes[node.first_child + c].occupancy;
    node.occupancy = sum / 8;
  }
  return tree;
}

}  // namespace cover::octree_build
