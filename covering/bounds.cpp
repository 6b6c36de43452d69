#include "covering/bounds.h"

#include <algorithm>

namespace cover {
namespace {

/// A box that contains the result (leaf boxes; ∪ → hull, ∩ → overlap, − → the first operand's);
/// empty optional for an unbounded node.
std::optional<Bbox> node_bounds(const Solid& s, uint32_t node) {
  const CsgNode& n = s.tree.nodes[node];
  switch (n.op) {
    case CsgOp::kLeaf:
      return s.leaves[n.leaf].bbox;
    case CsgOp::kComplement:
      return std::nullopt;
    case CsgOp::kDifference:
      return node_bounds(s, n.children[0]);
    case CsgOp::kUnion: {
      Bbox box;
      for (uint32_t c : n.children) {
        const auto b = node_bounds(s, c);
        if (!b) return std::nullopt;
        box.add(*b);
      }
      return box;
    }
    case CsgOp::kIntersection: {
      std::optional<Bbox> box;
      for (uint32_t c : n.children) {
        const auto b = node_bounds(s, c);
        if (!b) continue;
        if (!box) {
          box = b;
          continue;
        }
        box->min = {std::max(box->min.x, b->min.x), std::max(box->min.y, b->min.y),
                    std::max(box->min.z, b->min.z)};
        box->max = {std::min(box->max.x, b->max.x), std::min(box->max.y, b->max.y),
                    std::min(box->max.z, b->max.z)};
      }
      return box;
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<Bbox> result_bounds(const Solid& solid) { return node_bounds(solid, solid.tree.root); }

}  // namespace cover
