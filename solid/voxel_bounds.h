#pragma once
// The grids of voxels and octrees: the cube a voxel grid (voxel/voxel_grid.h) or an octree
// (octree/octree.h) subdivides, the global lattice of a voxelization and its index boxes.
//
// A lattice is the global grid: origin o (the min corner), one spacing h for all three axes, and
// dims (NX, NY, NZ). Voxel (i, j, k) has centre o + (i+½, j+½, k+½)·h, computed in doubles exactly
// as VoxelLattice::centre() does, always with the GLOBAL indices: a brick (an index box of the
// lattice) never re-bases its centres, so every brick is bit-identical to the same region of the
// whole grid. The cubic grid of `--res N --bounds min,size` is the lattice (min, size/N, N,N,N).

#include <array>
#include <cstdint>
#include <optional>

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

}  // namespace cover
