#include "cover/solid/voxel_bounds.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cover/solid/errors.h"

namespace cover {

VoxelBounds default_voxel_bounds(const Bbox& box, int n) {
  if (n < 3)
    throw PreconditionError("default_voxel_bounds: resolution " + std::to_string(n) +
                            " < 3 leaves no room for the margin");
  // An empty box (nothing to enclose) is centred at the origin; a box with no extent (a point)
  // gets unit extent so that the cube keeps a positive size.
  const Vec3 centre = box.empty() ? Vec3{} : 0.5 * (box.min + box.max);
  double extent = 0;
  if (!box.empty())
    extent = std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z});
  if (!(extent > 0) || !std::isfinite(extent)) extent = 1;
  // One voxel of margin per side: N voxels of size h span the extent plus 2h.
  VoxelBounds bounds;
  bounds.size = extent * n / (n - 2);
  const double half = 0.5 * bounds.size;
  bounds.min = {centre.x - half, centre.y - half, centre.z - half};
  return bounds;
}

}  // namespace cover
