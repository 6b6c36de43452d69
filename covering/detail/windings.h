#pragma once
// The exact crossing counts behind leaf_windings() (classify.cpp), for a solid and a BVH of it:
// what the open leaves' closures (gwn.cpp) count on, with no open-leaf rounding. Internal to
// covering/.

#include <cstddef>
#include <span>

#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/solid/solid.h"

namespace cover::detail {

/// Every leaf's crossing count (its winding number where the leaf is closed) at every point,
/// through `bvh` (built over `solid`); `grain` points per parallel chunk.
LeafWindings crossing_windings(const Solid& solid, const Bvh& bvh, std::span<const Vec3> points,
                               size_t grain = 256);

}  // namespace cover::detail
