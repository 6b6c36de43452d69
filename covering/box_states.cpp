// The three-valued states of closed boxes (box_states.h).

#include "cover/covering/box_states.h"

#include <algorithm>

#include "cover/covering/bvh_walk.h"
#include "cover/covering/classify.h"
#include "cover/covering/detail/implicit.h"
#include "cover/covering/detail/windings.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"

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

/// True when triangle abc may meet the closed box: their boxes overlap and the triangle's plane
/// does not leave all 8 corners strictly on one side (exact orient3d): 4 of the 13 separating
/// axes of the exact test (octree/detail/box_overlap.h), enough to clear the small boxes of
/// rays and points near a surface.
bool may_meet(const Vec3& a, const Vec3& b, const Vec3& c, const Bbox& box) {
  Bbox tb;
  tb.add(a);
  tb.add(b);
  tb.add(c);
  if (!(tb.min.x <= box.max.x && tb.max.x >= box.min.x && tb.min.y <= box.max.y &&
        tb.max.y >= box.min.y && tb.min.z <= box.max.z && tb.max.z >= box.min.z))
    return false;
  int above = 0, below = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 p{k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y,
                 k & 4 ? box.max.z : box.min.z};
    const int o = orient3d(a, b, c, p);
    above += o > 0;
    below += o < 0;
    if (above < k + 1 && below < k + 1) return true;
  }
  return false;
}

/// Marks in `crossed` the mesh leaves with a covering triangle that may meet the closed box.
void crossed_leaves(const Bvh& bvh, const Bbox& box, std::vector<uint8_t>& crossed) {
  walk(
      bvh,
      [&](const Bvh::Node& n) {
        return n.lo[0] <= box.max.x && n.hi[0] >= box.min.x && n.lo[1] <= box.max.y &&
               n.hi[1] >= box.min.y && n.lo[2] <= box.max.z && n.hi[2] >= box.min.z;
      },
      [&](const Bvh::Tri& t, uint32_t) {
        if (!crossed[t.leaf] && may_meet(t.a, t.b, t.c, box)) crossed[t.leaf] = 1;
      });
}

/// An open leaf's state on a box none of its triangles meets (gwn.h GwnClosure): inside is
/// |W − w_C| > 1/2 with W the closure's exact winding number, constant on a box that neither
/// the leaf's nor the cones' triangles meet; where the cones provably subtend |w_C| < 0.4 over
/// the box (winding_below, which also rules out cone triangles meeting it) that is W ≠ 0, read
/// at the centre. Else undecided.
uint8_t open_state(const GwnForest& forest, size_t leaf, const Bbox& box, const Vec3& centre) {
  const int32_t k = forest.tree_of_leaf[leaf];
  if (k < 0) return kUnknown;
  const GwnClosure& c = forest.closures[static_cast<size_t>(k)];
  if (!winding_below(c.cone, box, 0.4)) return kUnknown;
  const LeafWindings w = detail::crossing_windings(c.solid, *c.bvh, {&centre, 1}, 1);
  return w.winding[0] != 0 ? kIn : kOut;
}

/// The state of one box; leaf_state and crossed are scratch of one entry per leaf.
uint8_t state_of(const Prepared& prepared, const Bbox& box, std::vector<uint8_t>& leaf_state,
                 std::vector<uint8_t>& crossed) {
  const Solid& s = prepared.solid();
  if (s.tree.nodes.empty()) return kOut;
  const size_t leaves = s.leaves.size();
  leaf_state.assign(leaves, kOut);
  crossed.assign(leaves, 0);
  if (!prepared.bvh().nodes().empty()) crossed_leaves(prepared.bvh(), box, crossed);
  const Vec3 centre[1] = {0.5 * (box.min + box.max)};
  LeafWindings w;
  for (size_t l = 0; l < leaves; ++l) {
    const Leaf& leaf = s.leaves[l];
    if (leaf.is_implicit()) {
      leaf_state[l] = detail::implicit_box_state(prepared, static_cast<uint32_t>(l), box);
    } else if (crossed[l]) {
      leaf_state[l] = kUnknown;
    } else if (leaf.open()) {
      leaf_state[l] = open_state(*prepared.gwn(), l, box, centre[0]);
    } else {
      if (w.leaves == 0) w = detail::crossing_windings(s, prepared.bvh(), centre, 1);
      leaf_state[l] = w.winding[l] != 0 ? kIn : kOut;
    }
  }
  return evaluate3(s.tree, s.tree.root, leaf_state);
}

}  // namespace

uint8_t box_state(const Prepared& prepared, const Bbox& box) {
  std::vector<uint8_t> leaf_state, crossed;
  return state_of(prepared, box, leaf_state, crossed);
}

std::vector<uint8_t> box_states(const Prepared& prepared, std::span<const Bbox> boxes) {
  prepared.bvh();  // built once, before the threads
  std::vector<uint8_t> state(boxes.size());
  parallel_for(boxes.size(), 64, [&](size_t begin, size_t end) {
    std::vector<uint8_t> leaf_state, crossed;
    for (size_t c = begin; c < end; ++c)
      state[c] = state_of(prepared, boxes[c], leaf_state, crossed);
  });
  return state;
}

}  // namespace cover
