#include "cover/covering/bounds.h"

#include <algorithm>

namespace cover {
namespace {

/// What is known of a node's set N without evaluating it. `cobounded` is N's membership at
/// infinity (every leaf outside there; exact, from the expression alone): false → N ⊆ box,
/// true → the complement of N ⊆ box. An empty box is the empty set.
struct NodeBounds {
  bool cobounded = false;
  Bbox box;
};

Bbox overlap(Bbox a, const Bbox& b) {
  a.min = {std::max(a.min.x, b.min.x), std::max(a.min.y, b.min.y), std::max(a.min.z, b.min.z)};
  a.max = {std::min(a.max.x, b.max.x), std::min(a.max.y, b.max.y), std::min(a.max.z, b.max.z)};
  if (a.min.x > a.max.x || a.min.y > a.max.y || a.min.z > a.max.z) return Bbox{};
  return a;
}

/// Intersection of sets given as bounds, each possibly complemented (`negate`): the bounded
/// ones' boxes overlap; if none is bounded, the complement is the union of the complements.
NodeBounds intersect_bounds(const std::vector<NodeBounds>& parts, const std::vector<bool>& negate) {
  NodeBounds out;
  bool any_bounded = false;
  Bbox meet, hull;
  for (size_t i = 0; i < parts.size(); ++i) {
    const bool co = parts[i].cobounded != negate[i];
    if (!co) {
      meet = any_bounded ? overlap(meet, parts[i].box) : parts[i].box;
      any_bounded = true;
    } else {
      hull.add(parts[i].box);
    }
  }
  if (any_bounded) {
    out.box = meet;
  } else {
    out.cobounded = true;
    out.box = hull;
  }
  return out;
}

NodeBounds node_bounds(const Solid& s, uint32_t node) {
  const CsgNode& n = s.tree.nodes[node];
  if (n.op == CsgOp::kLeaf) return {false, s.leaves[n.leaf].bbox};
  std::vector<NodeBounds> parts;
  for (uint32_t c : n.children) parts.push_back(node_bounds(s, c));
  switch (n.op) {
    case CsgOp::kComplement:
      return {!parts[0].cobounded, parts[0].box};
    case CsgOp::kIntersection:
      return intersect_bounds(parts, std::vector<bool>(parts.size(), false));
    case CsgOp::kDifference: {
      std::vector<bool> negate(parts.size(), true);
      negate[0] = false;
      return intersect_bounds(parts, negate);
    }
    case CsgOp::kUnion: {  // ∪ X = ∁ ∩ ∁X
      NodeBounds inner = intersect_bounds(parts, std::vector<bool>(parts.size(), true));
      inner.cobounded = !inner.cobounded;
      return inner;
    }
    case CsgOp::kLeaf:
      break;
  }
  return {};
}

}  // namespace

bool is_bounded(const Solid& solid) {
  std::vector<uint8_t> outside(solid.leaves.size(), 0);
  return solid.leaves.empty() || !solid.tree.evaluate(outside);
}

std::optional<Bbox> result_bounds(const Solid& solid) {
  if (solid.leaves.empty()) return Bbox{};
  const NodeBounds b = node_bounds(solid, solid.tree.root);
  if (b.cobounded) return std::nullopt;
  return b.box;
}

std::string unbounded_message(const std::string& input) {
  return input +
         ": the result is unbounded (it contains every point far from all leaves, e.g. "
         "a complement at the root); this command needs a bounded solid";
}

}  // namespace cover
