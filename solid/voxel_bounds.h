#pragma once
// The cube a voxel grid (voxel/voxel_grid.h) or an octree (octree/octree.h) subdivides.

#include "cover/solid/types.h"

namespace cover {

/// The cube [min, min + size]³ (size > 0).
struct VoxelBounds {
  Vec3 min;
  double size = 1;
};

/// Default bounds: the box made cubic around its centre, with a margin of one voxel per side:
/// size = max extent · N/(N − 2). An empty box is taken as centred at the origin and a box of
/// zero extent as having extent 1. \throws PreconditionError if N < 3.
VoxelBounds default_voxel_bounds(const Bbox& box, int n);

}  // namespace cover
