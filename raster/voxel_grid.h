#pragma once
// A bit-packed voxel grid (1 bit per voxel) over a cube (CONTRACT.md `cover voxelize`).
// Voxel (i, j, k) has centre min + (i+½, j+½, k+½)·size/N (computed in doubles exactly as
// voxel_centre() does). Storage is column-major: the N voxels of column (i, j) (k = 0..N−1, z
// upwards) are consecutive bits in words_per_column() 64-bit words; columns ordered i slowest:
// word index (i·N + j)·words_per_column() + k/64, bit k%64. That is [x][y][z] order, the order of
// .npy and .raw exports; .binvox (x, z, y) transposes on output.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "solid/large_vector.h"
#include "solid/voxel_bounds.h"

namespace cover {

struct VoxelGrid {
  int n = 0;
  VoxelBounds bounds;
  LargeVector<uint64_t> bits;

  size_t words_per_column() const { return (static_cast<size_t>(n) + 63) / 64; }
  size_t column_word(int i, int j) const {
    return (static_cast<size_t>(i) * n + static_cast<size_t>(j)) * words_per_column();
  }
  bool get(int i, int j, int k) const {
    return (bits[column_word(i, j) + static_cast<size_t>(k) / 64] >> (k % 64)) & 1;
  }
  void set(int i, int j, int k) {
    bits[column_word(i, j) + static_cast<size_t>(k) / 64] |= uint64_t{1} << (k % 64);
  }
  double voxel_size() const { return bounds.size / n; }
  /// Centre of voxel (i, j, k) — the point whose membership the voxel records.
  Vec3 voxel_centre(int i, int j, int k) const {
    const double h = voxel_size();
    return {bounds.min.x + (i + 0.5) * h, bounds.min.y + (j + 0.5) * h, bounds.min.z + (k + 0.5) * h};
  }
  /// Number of set voxels (padding bits above k = N − 1 are ignored).
  uint64_t count() const;
};

}  // namespace cover
