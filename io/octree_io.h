#pragma once
// Octree export (docs/cli.md, `cover octree`), by extension, written atomically (temporary file,
// then rename):
//   .htg   VTK XML HyperTreeGrid, file version 1.0 (opens in ParaView; read back by VTK 9.1's
//          vtkXMLHyperTreeGridReader): one tree over the cube, cell arrays "state" (UInt8:
//          0 empty, 1 full, 2 partial) and "occupancy" (Float32), inline base64
//   .bt    OctoMap binary tree (octovis and liboctomap open it; the bytes liboctomap's
//          OcTree::writeBinary writes for the same leaves, fully pruned): an OcTree whose
//          resolution res is the finest cell size size/2^depth, every cell at its world place.
//          occupied = full, or partial with occupancy >= threshold; free = empty, or partial
//          below it; outside the cube: unknown (no node). OctoMap's voxels are the cells
//          [k·res, (k+1)·res) per axis, k = −32768 .. 32767, so the cube must lie on that grid:
//          min a whole multiple of res (min/res a whole number in double arithmetic) and inside
//          ±32768·res (octomap_bounds gives such a cube); depth 1..16
//   .json  summary: bounds {min, size}, depth, nodes, leaves {empty, full, partial}, threshold,
//          and every leaf cell in node order {min, size, state ("empty" / "full" / "partial"),
//          occupancy}

#include <filesystem>

#include "cover/octree/octree.h"

namespace cover {

/// The default cube of a .bt octree of `depth` (1..16) around `box` (an empty box: the unit
/// cube centred on the origin): 2^depth cells of side res from a whole multiple m·res, holding
/// the box with one cell of margin per side (none at depth 1) within OctoMap's keys (−32768 ≤ m
/// ≤ 32768 − 2^depth), m the largest such, at most floor(box.min/res) − 1. res = q·2^j with q a
/// whole number ≤ 16 (so the cells' corners and OctoMap's voxel centres are exact doubles): the
/// smallest such number for which some m exists, tried upwards from extent/(2^depth − 2)
/// (extent/2 at depth 1); near the origin at most 9/8 of extent/(2^depth − 3). \throws
/// PreconditionError for a depth outside 1..16.
VoxelBounds octomap_bounds(const Bbox& box, int depth);

/// Throws the InputError write_octree throws for a .bt `path` of the cube `bounds` at `depth`
/// (1..16) that is not on OctoMap's grid; nothing otherwise.
void check_octomap_cube(const std::filesystem::path& path, const VoxelBounds& bounds, int depth);

/// True for .htg, .bt and .json (any letter case).
bool is_octree_extension(const std::filesystem::path& path);

/// Writes `tree` in the format of `path`'s extension. Throws InputError naming the file on an
/// unsupported extension, an empty tree, a .bt of depth 0, a .bt whose cube is not on OctoMap's
/// grid (see above; the message says why), or I/O failure, and InputError for a threshold
/// outside [0, 1].
void write_octree(const std::filesystem::path& path, const Octree& tree, double threshold);

}  // namespace cover
