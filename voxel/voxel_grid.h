#pragma once
// Bit-packed voxel grids over a lattice's index box (docs/cli.md, `cover voxelize`;
// docs/scale-out.md#bricks). The lattice and its index boxes: solid/voxel_bounds.h.
//
// A VoxelGrid holds the voxels of one index box of a lattice (the whole lattice, or a brick),
// 1 bit per voxel. Storage is column-major: the nz voxels of column (i, j) (local indices,
// k = 0..nz−1, z upwards) are consecutive bits in words_per_column() 64-bit words; columns
// ordered i slowest: word index (i·ny + j)·words_per_column() + k/64, bit k%64. That is
// [x][y][z] order, the order of .npy, .raw and Zarr exports; .binvox (x, z, y) transposes.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "cover/solid/voxel_bounds.h"

namespace cover {

struct VoxelGrid {
  VoxelLattice lattice;  ///< the global grid this one is (a region of)
  IndexBox box;          ///< the region held: local voxel (i, j, k) is global box.lo + (i, j, k)
  std::vector<uint64_t> bits;

  /// Local dims (box.hi − box.lo).
  int nx() const { return box.hi[0] - box.lo[0]; }
  int ny() const { return box.hi[1] - box.lo[1]; }
  int nz() const { return box.hi[2] - box.lo[2]; }
  /// True when the grid holds the whole lattice.
  bool whole() const { return box == whole_box(lattice); }
  size_t words_per_column() const { return (static_cast<size_t>(std::max(nz(), 0)) + 63) / 64; }
  /// Words the bits of an nx × ny × nz grid take.
  size_t word_count() const {
    return static_cast<size_t>(std::max(nx(), 0)) * static_cast<size_t>(std::max(ny(), 0)) *
           words_per_column();
  }
  size_t column_word(int i, int j) const {
    return (static_cast<size_t>(i) * static_cast<size_t>(ny()) + static_cast<size_t>(j)) *
           words_per_column();
  }
  /// Voxel (i, j, k), local indices.
  bool get(int i, int j, int k) const {
    return (bits[column_word(i, j) + static_cast<size_t>(k) / 64] >> (k % 64)) & 1;
  }
  void set(int i, int j, int k) {
    bits[column_word(i, j) + static_cast<size_t>(k) / 64] |= uint64_t{1} << (k % 64);
  }
  double voxel_size() const { return lattice.spacing; }
  /// Centre of local voxel (i, j, k): the lattice's centre of global box.lo + (i, j, k).
  Vec3 voxel_centre(int i, int j, int k) const {
    return lattice.centre(box.lo[0] + i, box.lo[1] + j, box.lo[2] + k);
  }
  /// Number of set voxels (padding bits above k = nz − 1 are ignored).
  uint64_t count() const;
};

/// An all-empty grid holding `box` of `lattice` (bits zeroed).
VoxelGrid empty_voxel_grid(const VoxelLattice& lattice, const IndexBox& box);

}  // namespace cover
