#pragma once
// Voxel grid export (docs/cli.md, `cover voxelize`), chosen by extension; written atomically
// (io/atomic_file.h: temporary file, then rename, or with an open OutputBatch) and streamed
// from the bit grid (no N³-byte buffer):
//   .binvox  binvox 1: "#binvox 1", "dim N N N", "translate x y z", "scale s", "data", then RLE
//            pairs (value, count ≤ 255) over index x·N·N + z·N + y
//   .vti     VTK XML ImageData, cell data "occupancy" (UInt8, 0/1), origin = min,
//            spacing = size/N, extent 0 N 0 N 0 N (N³ cells), raw appended binary data
//   .npy     NumPy 1.0 format, uint8 array of shape (N, N, N) indexed [x, y, z], C order
//   .raw     uint8 bytes in [x][y][z] order, plus a sidecar named by appending ".json"
//            (out.raw → out.raw.json): {"dims", "order": "xyz (z fastest)", "dtype": "uint8",
//            "bounds": {"min", "size"}, "voxel_size"}; both committed together or neither
// Numbers in text headers are the shortest decimals that read back exactly. Extensions are
// matched case-insensitively.

#include <filesystem>

#include "cover/voxel/voxel_grid.h"

namespace cover {

/// True for .binvox, .vti, .npy, .raw.
bool is_voxel_extension(const std::filesystem::path& path);

/// Writes the grid; throws InputError naming the file on unsupported extension or I/O failure
/// (leaving no partial or temporary file); \throws PreconditionError if grid.bits does not hold
/// N·N·words_per_column() words or the bounds are not finite with size > 0.
void write_voxels(const std::filesystem::path& path, const VoxelGrid& grid);

}  // namespace cover
