#pragma once
// The octree of a solid with field leaves (field_octree.cpp; internal to octree/).

#include "cover/covering/prepared.h"
#include "cover/octree/octree.h"

namespace cover::octree_build {

/// Level by level, each cell's state from covering/box_states.h (fields by interval bounds over
/// the closed cell, mesh leaves by triangle boxes and exact windings, the tree in Kleene's
/// logic): full and empty only where certified; undecided cells split, and at `options.depth`
/// become partial leaves whose occupancy is the share of their samples³ sub-points classify()
/// finds inside (on the surface: ½). The same node layout as the mesh builder.
/// \pre options and bounds checked (check_octree_request); closed mesh leaves.
Octree build_field_octree(const Prepared& prepared, const VoxelBounds& bounds,
                          const OctreeOptions& options);

}  // namespace cover::octree_build
