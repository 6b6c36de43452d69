#pragma once
// Presence-buffer voxelization of a non-evaluated CSG solid ([Segura2004 §7]).
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

#include <array>
#include <functional>
#include <optional>
#include <vector>

#include "cover/covering/prepared.h"
#include "cover/solid/solid.h"
#include "cover/voxel/voxel_grid.h"

namespace cover {

/// Largest number of voxels per axis of any grid (a brick's lattice included): a column's
/// `below` counts and row indices are packed in 16 bits.
inline constexpr int kMaxVoxelDims = 16384;
/// Largest N of a whole cubic grid voxelized in memory (--res).
inline constexpr int kMaxVoxelResolution = 4096;

/// The grid, in one of three ways (docs/cli.md, `cover voxelize`):
///   cubic     (default) N = resolution voxels per axis over the cube `bounds` (default:
///             default_voxel_bounds(result box, N)); spacing = size / N.
///   voxel_size > 0: spacing h over the box B (the cube `bounds` when given, else the result's
///             box): origin = B.min, dims[a] = the smallest d ≥ 1 with d·h ≥ extent[a] (in
///             doubles, starting from ⌈extent[a] / h⌉).
///   dims all > 0: those voxel counts over B, origin = B.min, spacing = the smallest double h
///             with dims[a]·h ≥ extent[a] on every axis (starting from max extent[a] / dims[a]),
///             so the grid covers B and reaches it exactly on the tightest axis.
/// An axis of zero extent gets one voxel (voxel_size) or keeps its count (dims); a box of zero
/// extent everywhere (or empty) is taken as the unit cube around its centre (the origin when
/// empty).
struct VoxelizeOptions {
  int resolution = 128;               ///< N: voxels per axis of a cubic grid (1 to 4096)
  std::optional<VoxelBounds> bounds;  ///< cube of a cubic grid, or the box B of the others
  double voxel_size = 0;              ///< > 0: a grid of this spacing over B (not with dims)
  std::array<int, 3> dims{};          ///< all > 0: a grid with these voxel counts over B
  /// Called on the calling thread, after each band of rows it finishes and once at the end, with
  /// the share of bands done, 0..1 (non-decreasing); default: none. The grid does not depend on
  /// it.
  std::function<void(double)> progress;
};

/// The lattice `options` describe; `result_box` is the box B (or the box the default cube is
/// built around) when options.bounds is absent. \throws InputError for a non-finite or
/// non-positive voxel_size, a dim out of 1..kMaxVoxelDims, voxel_size and dims both given, or a
/// voxel size that needs more than kMaxVoxelDims voxels on an axis. A cubic grid with default
/// bounds and N < 3 gets the margin of N = 3.
VoxelLattice voxel_lattice(const Bbox& result_box, const VoxelizeOptions& options);

/// Voxelizes the result of the prepared CSG expression over the whole lattice of `options`.
/// Open leaves: each voxel records classify() of its centre (covering/classify.h
/// classify_lattice), the winding-number membership, instead of the sweep.
/// \pre 1 ≤ resolution ≤ 4096; bounds given or the result bounded; bounds finite with a
/// positive size (Model::voxelize checks all of these). \throws PreconditionError when the
/// default bounds need a resolution below 3 (default_voxel_bounds).
VoxelGrid voxelize(const Prepared& prepared, const VoxelizeOptions& options);

/// The same into `grid`, reusing its memory (repeated voxelizations, benchmarks).
void voxelize(const Prepared& prepared, const VoxelizeOptions& options, VoxelGrid& grid);

/// One-shot: prepares the solid, then voxelizes.
VoxelGrid voxelize(const Solid& solid, const VoxelizeOptions& options);

/// Voxelizes the brick `box` of `lattice` into `grid` (grid.lattice = lattice, grid.box = box, its
/// memory reused): bit-identical to the same region of the whole lattice's grid (the same centre
/// doubles, the same exact predicates, the same tie rule; docs/scale-out.md#bricks), at a cost ∝
/// the covering triangles whose x/y range reaches the brick's columns (found through the
/// prepared BVH) plus its voxels; the whole lattice scans every face without the BVH. Open
/// leaves as voxelize(). `progress` as VoxelizeOptions::progress (may be empty). Thread-safe.
/// \pre box inside [0, lattice.dims) and not empty; lattice dims ≤ kMaxVoxelDims; spacing
/// finite and > 0 (Model::voxelize_brick checks).
void voxelize_brick(const Prepared& prepared, const VoxelLattice& lattice, const IndexBox& box,
                    VoxelGrid& grid, const std::function<void(double)>& progress = {});

/// The sweep of voxelize_brick() over the faces `faces` lists (any superset of those whose fan
/// triangles' x/y boxes contain a column centre of the brick, in any order), or every face for
/// nullptr. \pre closed leaves, and as above.
void voxelize_brick(const Solid& solid, const VoxelLattice& lattice, const IndexBox& box,
                    const std::vector<uint32_t>* faces, VoxelGrid& grid,
                    const std::function<void(double)>& progress = {});

}  // namespace cover
