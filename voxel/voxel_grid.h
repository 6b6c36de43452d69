#pragma once
// Voxel lattices, index boxes (bricks) and bit-packed voxel grids (docs/cli.md,
// `cover voxelize`; docs/scale-out.md#bricks).
//
// A lattice is the global grid: origin o (the min corner), one spacing h for all three axes, and
// dims (NX, NY, NZ). Voxel (i, j, k) has centre o + (i+½, j+½, k+½)·h, computed in doubles exactly
// as VoxelLattice::centre() does, always with the GLOBAL indices: a brick (an index box of the
// lattice) never re-bases its centres, so every brick is bit-identical to the same region of the
// whole grid. The cubic grid of `--res N --bounds min,size` is the lattice (min, size/N, N,N,N).
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

/// The global grid of a voxelization: origin, spacing, dims.
struct VoxelLattice {
  Vec3 origin;                ///< min corner of voxel (0, 0, 0)
  double spacing = 1;         ///< h > 0, the same on every axis
  std::array<int, 3> dims{};  ///< voxels per axis (NX, NY, NZ), each ≥ 1
  /// The cube of a cubic grid made from VoxelBounds (cubic_lattice): its exact size, which
  /// .binvox and the .raw sidecar record (spacing = cube_size / N); nullopt for grids made
  /// from a voxel size or dims.
  std::optional<double> cube_size;

  /// Centre of voxel (i, j, k) (global indices) — the point whose membership the voxel records.
  Vec3 centre(int i, int j, int k) const {
    return {origin.x + (i + 0.5) * spacing, origin.y + (j + 0.5) * spacing,
            origin.z + (k + 0.5) * spacing};
  }
  /// True when the three dims are equal.
  bool cubic() const { return dims[0] == dims[1] && dims[1] == dims[2]; }
  /// Number of voxels, NX·NY·NZ.
  uint64_t voxel_count() const {
    return static_cast<uint64_t>(dims[0]) * static_cast<uint64_t>(dims[1]) *
           static_cast<uint64_t>(dims[2]);
  }
};

/// The N×N×N lattice over the cube `bounds`: origin bounds.min, spacing bounds.size / N (the
/// double voxelize has always used), cube_size bounds.size.
inline VoxelLattice cubic_lattice(const VoxelBounds& bounds, int n) {
  return {bounds.min, bounds.size / n, {n, n, n}, bounds.size};
}

/// A half-open index box [lo, hi) of a lattice: voxels lo[a] ≤ index[a] < hi[a] on each axis a.
struct IndexBox {
  std::array<int, 3> lo{};
  std::array<int, 3> hi{};

  std::array<int, 3> dims() const { return {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}; }
  bool empty() const { return hi[0] <= lo[0] || hi[1] <= lo[1] || hi[2] <= lo[2]; }
  friend bool operator==(const IndexBox&, const IndexBox&) = default;
};

/// The index box of the whole lattice, [0, dims).
inline IndexBox whole_box(const VoxelLattice& lattice) { return {{0, 0, 0}, lattice.dims}; }

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
