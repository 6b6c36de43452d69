#pragma once
// The result's state on closed boxes, three-valued (shared by the bracket volume and the octree
// of solids with field leaves; not installed). Per leaf: a field leaf by the interval enclosure
// of f − T over the box (field/field.h bound: inside when it is > 0, outside when < 0, else
// undecided); a mesh leaf undecided when some covering triangle's box meets the closed box,
// else by its exact winding number at the box's centre (constant on a box no surface of the
// leaf meets). The tree is evaluated in Kleene's three-valued logic: a box is inside (outside)
// only when every point of it is.

#include <cstdint>
#include <span>
#include <vector>

#include "cover/covering/prepared.h"

namespace cover {

enum : uint8_t { kBoxOutside = 0, kBoxInside = 1, kBoxUndecided = 2 };

/// The state of each box, in parallel (thread-count independent). \pre closed mesh leaves.
std::vector<uint8_t> box_states(const Prepared& prepared, std::span<const Bbox> boxes);

}  // namespace cover
