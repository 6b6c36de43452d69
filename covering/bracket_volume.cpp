// The bracket volume of solids with field leaves (covering/volume.h volume(), method "bracket").
//
// Cells of an octree over the result's box are settled three-valued per leaf: a field leaf by the
// interval enclosure of f − T over the closed cell (field/field.h bound: inside when lo > 0,
// outside when hi < 0, else unknown); a mesh leaf unknown when some covering triangle's box meets
// the closed cell, else by its exact winding number at the cell's centre (constant on a cell no
// surface of the leaf meets). The tree in Kleene's three-valued logic then says full, empty or
// unknown; full cells add to both ends of the bracket, unknown ones to its upper end only, and
// unknown cells are split in eight until (V_out − V_in)/2 ≤ target·V or the next level would hold
// more cells than the budget (so all levels together settle at most about 8/7 of it).
// Sums are outward-rounded intervals (CGAL::Interval_nt), so the bracket holds in doubles.

#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <cmath>

#include "cover/covering/bounds.h"
#include "cover/covering/bvh_walk.h"
#include "cover/covering/classify.h"
#include "cover/covering/detail/windings.h"
#include "cover/covering/volume.h"
#include "cover/field/field.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover::detail {
namespace {

enum Tri : uint8_t { kOut = 0, kIn = 1, kUnknown = 2 };

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

VolumeResult bracket_volume(const Prepared& prepared, const VolumeOptions& options) {
  using I = CGAL::Interval_nt<false>;
  const Solid& s = prepared.solid();
  const std::optional<Bbox> bounds = result_bounds(s);
  if (!bounds) throw NotComputable("the result is unbounded: it has no volume");
  VolumeResult r;
  r.method = "bracket";
  if (bounds->empty()) return r;
  const Bvh& bvh = prepared.bvh();
  const size_t leaves = s.leaves.size();
  std::vector<Bbox> level{*bounds}, next;
  I inside_sum(0), unknown_sum(0);
  const size_t budget = std::max<size_t>(options.max_rays, 4096);  // cells of a level, at most
  size_t settled = 0;
  for (int depth = 0; !level.empty(); ++depth) {
    std::vector<uint8_t> state(level.size());
    parallel_for(level.size(), 64, [&](size_t begin, size_t end) {
      std::vector<uint8_t> leaf_state(leaves), crossed(leaves);
      std::vector<Vec3> centre(1);
      for (size_t c = begin; c < end; ++c) {
        const Bbox& box = level[c];
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
            if (w.leaves == 0) w = crossing_windings(s, bvh, centre, 1);
            leaf_state[l] = w.winding[l] != 0 ? kIn : kOut;
          }
        }
        state[c] = evaluate3(s.tree, s.tree.root, leaf_state);
      }
    });
    settled += level.size();
    // In cell order: the sums (hence the bracket) do not depend on the threads.
    I unknown_here(0);
    for (size_t c = 0; c < level.size(); ++c) {
      if (state[c] == kOut) continue;
      const Bbox& b = level[c];
      const I v = (I(b.max.x) - b.min.x) * (I(b.max.y) - b.min.y) * (I(b.max.z) - b.min.z);
      if (state[c] == kIn)
        inside_sum += v;
      else
        unknown_here += v;
    }
    const double lo = inside_sum.inf(), hi = (inside_sum + unknown_here).sup();
    const double half = (hi - lo) / 2, mid = lo + half;
    if (options.progress)
      options.progress(std::min(1.0, static_cast<double>(settled) / (budget + budget / 7)));
    const size_t unknown_cells =
        static_cast<size_t>(std::count(state.begin(), state.end(), uint8_t{kUnknown}));
    if (half <= options.bracket_relative_error * std::abs(mid) || unknown_cells == 0 ||
        8 * unknown_cells > budget) {
      r.volume = mid;
      r.error_bound = std::nextafter(hi - mid > mid - lo ? hi - mid : mid - lo, INFINITY);
      r.target_met = half <= options.bracket_relative_error * std::abs(mid);
      r.rays = settled;
      return r;
    }
    next.clear();
    for (size_t c = 0; c < level.size(); ++c) {
      if (state[c] != kUnknown) continue;
      const Bbox& b = level[c];
      const Vec3 m = 0.5 * (b.min + b.max);
      for (int o = 0; o < 8; ++o) {
        Bbox child;
        child.min = {o & 1 ? m.x : b.min.x, o & 2 ? m.y : b.min.y, o & 4 ? m.z : b.min.z};
        child.max = {o & 1 ? b.max.x : m.x, o & 2 ? b.max.y : m.y, o & 4 ? b.max.z : m.z};
        next.push_back(child);
      }
    }
    level.swap(next);
  }
  return r;
}

}  // namespace cover::detail
