// The three-valued states of closed boxes (box_states.h).

#include "cover/covering/box_states.h"

#include <algorithm>

#include "cover/covering/bvh_walk.h"
#include "cover/covering/classify.h"
#include "cover/covering/detail/windings.h"
#include "cover/field/field.h"
#include "cover/solid/parallel.h"

namespace cover {
namespace {

constexpr uint8_t kOut = kBoxOutside, kIn = kBoxInside, kUnknown = kBoxUndecided;

/// Kleene's three-valued evaluation of the tree on per-leaf states.
uint8_t evaluate3(const CsgTree& tree, uint32_t node, std::span<const uint8_t> state) {
  const CsgNode& n = tree.nodes[node];
  switch (n.op) {
    case CsgOp::kLeaf:
      return state[n.leaf];
    case CsgOp::kComplement: {
      const uint8_t v = evaluate3(tree, n.children[0], state);
      return v == kUnknown ? uint8_t{kUnknown} : static_cast<uint8_t>(1 - v);
    }
    case CsgOp::kUnion: {
      uint8_t out = kOut;
      for (uint32_t c : n.children) {
        const uint8_t v = evaluate3(tree, c, state);
        if (v == kIn) return kIn;
        if (v == kUnknown) out = kUnknown;
      }
      return out;
    }
    case CsgOp::kIntersection: {
      uint8_t out = kIn;
      for (uint32_t c : n.children) {
        const uint8_t v = evaluate3(tree, c, state);
        if (v == kOut) return kOut;
        if (v == kUnknown) out = kUnknown;
      }
      return out;
    }
    case CsgOp::kDifference: {
      uint8_t out = evaluate3(tree, n.children[0], state);
      for (size_t i = 1; i < n.children.size() && out != kOut; ++i) {
        const uint8_t v = evaluate3(tree, n.children[i], state);
        if (v == kIn) return kOut;
        if (v == kUnknown) out = kUnknown;
      }
      return out;
    }
  }
  return kUnknown;
}

/// Marks in `crossed` the mesh leaves with a covering triangle whose box meets the closed box.
void crossed_leaves(const Bvh& bvh, const Bbox& box, std::vector<uint8_t>& crossed) {
  walk(
      bvh,
      [&](const Bvh::Node& n) {
        return n.lo[0] <= box.max.x && n.hi[0] >= box.min.x && n.lo[1] <= box.max.y &&
               n.hi[1] >= box.min.y && n.lo[2] <= box.max.z && n.hi[2] >= box.min.z;
      },
      [&](const Bvh::Tri& t, uint32_t) {
        if (crossed[t.leaf]) return;
        Bbox tb;
        tb.add(t.a);
        tb.add(t.b);
        tb.add(t.c);
        if (tb.min.x <= box.max.x && tb.max.x >= box.min.x && tb.min.y <= box.max.y &&
            tb.max.y >= box.min.y && tb.min.z <= box.max.z && tb.max.z >= box.min.z)
          crossed[t.leaf] = 1;
      });
}

}  // namespace

std::vector<uint8_t> box_states(const Prepared& prepared, std::span<const Bbox> boxes) {
  const Solid& s = prepared.solid();
  const Bvh& bvh = prepared.bvh();
  const size_t leaves = s.leaves.size();
  std::vector<uint8_t> state(boxes.size());
  parallel_for(boxes.size(), 64, [&](size_t begin, size_t end) {
    std::vector<uint8_t> leaf_state(leaves), crossed(leaves);
    std::vector<Vec3> centre(1);
    for (size_t c = begin; c < end; ++c) {
      const Bbox& box = boxes[c];
      std::fill(crossed.begin(), crossed.end(), 0);
      crossed_leaves(bvh, box, crossed);
      centre[0] = 0.5 * (box.min + box.max);
      LeafWindings w;
      for (size_t l = 0; l < leaves; ++l) {
        const Leaf& leaf = s.leaves[l];
        if (leaf.is_field()) {
          const field::Range b = field::bound(s.fields[leaf.field], box);
          leaf_state[l] = b.lo > 0 ? kIn : (b.hi < 0 ? kOut : kUnknown);
        } else if (crossed[l]) {
          leaf_state[l] = kUnknown;
        } else {
          if (w.leaves == 0) w = detail::crossing_windings(s, bvh, centre, 1);
          leaf_state[l] = w.winding[l] != 0 ? kIn : kOut;
        }
      }
      state[c] = s.tree.nodes.empty() ? kOut : evaluate3(s.tree, s.tree.root, leaf_state);
    }
  });
  return state;
}

}  // namespace cover
