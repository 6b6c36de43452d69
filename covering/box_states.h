#pragma once
// The result's state on closed boxes, three-valued (shared by the bracket volume, the octree
// of solids with field and warp leaves, and the warp leaves' own decisions; not installed). Per
// leaf: a field or warp leaf by covering/detail/implicit.h (a field by the interval enclosure of
// f − T over the box: inside when it is > 0, outside when < 0, else undecided; a warp by its
// child's state over the enclosure of the box's preimage); a mesh leaf undecided when some
// covering triangle may meet the closed box (their boxes overlap and the triangle's plane does
// not leave every corner strictly on one side, exactly), else by its exact winding number at
// the box's centre (constant on a box no surface of the leaf meets); an open mesh leaf always
// undecided (its set |w| > 1/2 may end away from its triangles, covering/gwn.h). The tree is
// evaluated in Kleene's three-valued logic: a box is inside (outside) only when every point of it
// is.

#include <cstdint>
#include <span>
#include <vector>

#include "cover/covering/prepared.h"

namespace cover {

enum : uint8_t { kBoxOutside = 0, kBoxInside = 1, kBoxUndecided = 2 };

/// The state of each box, in parallel (thread-count independent).
std::vector<uint8_t> box_states(const Prepared& prepared, std::span<const Bbox> boxes);
/// The state of one box, on the calling thread.
uint8_t box_state(const Prepared& prepared, const Bbox& box);

}  // namespace cover
