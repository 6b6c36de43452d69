#include "cover/voxel/voxel_grid.h"

#include <bit>

#include "cover/solid/large_vector.h"

namespace cover {

uint64_t VoxelGrid::count() const {
  // Padding bits above k = nz−1 in a column's last word are masked out, so a grid filled by
  // anything other than set() still counts only real voxels.
  const size_t words = words_per_column();
  if (words == 0) return 0;
  const unsigned tail = static_cast<unsigned>(nz() % 64);
  const uint64_t last_mask = tail == 0 ? ~uint64_t{0} : (uint64_t{1} << tail) - 1;
  uint64_t total = 0;
  for (size_t c = 0; c + words <= bits.size(); c += words) {
    for (size_t w = 0; w + 1 < words; ++w) total += std::popcount(bits[c + w]);
    total += std::popcount(bits[c + words - 1] & last_mask);
  }
  return total;
}

VoxelGrid empty_voxel_grid(const VoxelLattice& lattice, const IndexBox& box) {
  VoxelGrid grid;
  grid.lattice = lattice;
  grid.box = box;
  resize_huge(grid.bits, grid.word_count());
  return grid;
}

}  // namespace cover
