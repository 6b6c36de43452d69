#include "raster/voxel_grid.h"
#include "solid/errors.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

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

uint64_t VoxelGrid::count() const {
  // Padding bits above k = N−1 in a column's last word are masked out, so a grid filled by
  // anything other than set() still counts only real voxels.
  const size_t words = words_per_column();
  if (words == 0) return 0;
  const unsigned tail = static_cast<unsigned>(n % 64);
  const uint64_t last_mask = tail == 0 ? ~uint64_t{0} : (uint64_t{1} << tail) - 1;
  uint64_t total = 0;
  for (size_t c = 0; c + words <= bits.size(); c += words) {
    for (size_t w = 0; w + 1 < words; ++w) total += std::popcount(bits[c + w]);
    total += std::popcount(bits[c + words - 1] & last_mask);
  }
  return total;
}

}  // namespace cover
