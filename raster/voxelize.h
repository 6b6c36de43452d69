#pragma once
// Presence-buffer voxelization of a non-evaluated CSG solid (paper §7, DESIGN.md §4).
//
// With the covering origin at −∞ along z, each covering tetrahedron becomes the column below its
// triangle: a voxel centre c is covered by triangle T iff the upward half-line from c crosses T.
// So for every voxel column (i, j) whose centre line crosses T, the voxels below the crossing get
// T's sign (n_z: +1 where the leaf is left upwards). Per column and leaf, a sweep over the sorted
// crossings turns these flips into the leaf's winding number (small counters, so windings > 1 and
// nested shells follow the nonzero rule); the CSG tree is evaluated once per run of constant
// memberships and the run is written with word operations.
// Exact: "the centre line crosses T" is the perturbed projected test of covering/classify.cpp,
// and "the centre is below T" is orient3d — no epsilon. Centres exactly on a leaf surface follow
// one deterministic rule: voxel (i, j, k) records the membership of the centre displaced
// infinitesimally to c + (ε, ε², ε³) (slightly towards +x, then +y, then +z).
// Parallel over triangles, then over bands of rows (each band's crossings found, grouped by
// column and swept by one task, its columns written once); the grid does not depend on the
// thread count. Per-thread scratch (a band's crossings) is kept between calls.

#include <functional>
#include <optional>

#include "raster/voxel_grid.h"
#include "solid/solid.h"

namespace cover {

struct VoxelizeOptions {
  int resolution = 128;                ///< N: voxels per axis (1 to 4096)
  std::optional<VoxelBounds> bounds;   ///< default: default_voxel_bounds(result box, N)
  /// Called on the calling thread, after each band of rows it finishes and once at the end, with
  /// the share of bands done, 0..1 (non-decreasing); default: none. The grid does not depend on
  /// it.
  std::function<void(double)> progress;
};

/// Voxelizes the result of the CSG expression over an N×N×N grid.
/// \pre closed leaves; 1 ≤ resolution ≤ 4096; bounds given or the result bounded; bounds finite
/// with a positive size (Model::voxelize checks all of these). \throws PreconditionError when the
/// default bounds need a resolution below 3 (default_voxel_bounds).
VoxelGrid voxelize(const Solid& solid, const VoxelizeOptions& options);

/// The same into `grid`, reusing its memory (repeated voxelizations, benchmarks).
void voxelize(const Solid& solid, const VoxelizeOptions& options, VoxelGrid& grid);

}  // namespace cover
