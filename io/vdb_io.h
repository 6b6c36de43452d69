#pragma once
// OpenVDB export (docs/cli.md, `cover voxelize`): OUT.vdb holds one openvdb::BoolGrid
// named "occupancy". Index space = voxel (i, j, k) of the grid (global indices, 0 ≤ i < NX, ...);
// a set voxel is an active voxel of value true, every other voxel is the background (false,
// inactive); 8³ leaves that are all set become tiles (tree().prune()). World transform: a linear
// transform of voxel size h translated by origin + h/2, so indexToWorld(i, j, k) = origin +
// (i + ½, j + ½, k + ½)·h, the voxel's centre (OpenVDB's cell-centred index convention).
// Grid metadata: "cover_origin" (Vec3d), "cover_spacing" (double), "cover_dims" (Vec3i),
// "cover_tie_rule" (string). Written atomically (io/atomic_file.h) through
// openvdb::io::File. OpenVDB's headers stay in vdb_io.cpp (slow to compile; linked PRIVATE).

#include <filesystem>

#include "cover/voxel/voxel_grid.h"

namespace cover {

/// True for .vdb (case-insensitive).
bool is_vdb_extension(const std::filesystem::path& path);

/// Writes the whole grid as OUT.vdb. \throws InputError naming the file on an I/O failure (no
/// partial file left), or when Cover was built without OpenVDB; PreconditionError for a brick.
void write_vdb(const std::filesystem::path& path, const VoxelGrid& grid);

}  // namespace cover
