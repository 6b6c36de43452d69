#pragma once
// Out-of-core voxel export to a Zarr v2 directory store (docs/scale-out.md),
// written by Cover itself:
//   OUT.zarr/.zarray   {"zarr_format": 2, "shape": [NX, NY, NZ], "chunks": [C, C, C],
//                      "dtype": "|u1", "compressor": {"id": "zlib", "level": L},
//                      "fill_value": 0, "order": "C", "filters": null,
//                      "dimension_separator": "."}
//   OUT.zarr/.zattrs   {"origin", "spacing", "dims", "bounds" ({"min", "size"} of a cubic
//                      grid's cube, else {"min", "max"}), "index": "[x, y, z]",
//                      "centre": "origin + (i + 1/2, j + 1/2, k + 1/2) * spacing",
//                      "tie_rule": ...}
//   OUT.zarr/I.J.K     chunk (I, J, K): the C³ bytes 0/1 of voxels [I·C, (I+1)·C) × ... in C order
//                      (edge chunks padded with 0), zlib-compressed (zlib format, as numcodecs'
//                      Zlib); a chunk whose voxels are all 0 is not written (fill_value 0).
// Bricks: one brick is one column of chunks, [I·C, (I+1)·C) × [J·C, (J+1)·C) × [0, NZ) (each
// covering triangle is then processed once per brick it reaches, not once per chunk), computed
// by `brick` and turned into chunk files at once; at most `bricks_in_flight` bricks exist at a
// time, so memory is bounded by them, not by NX·NY·NZ.
// Atomic (io/atomic_file.h OutputFolder): the store is built in OUT.zarr.tmp-PID-K beside the
// target (links followed: writing through a link fills the folder it names) and swapped in
// whole; the old store is then removed. An existing target is replaced only when it is an empty
// folder or a store Cover wrote (.zarray, and only .zarray, .zattrs and chunk files I.J.K).
// Any failure, or SIGINT / SIGTERM / SIGHUP, removes the temporary folder and leaves the target
// as it was.

#include <cstdint>
#include <filesystem>
#include <functional>

#include "cover/voxel/voxel_grid.h"

namespace cover {

struct ZarrOptions {
  int chunk = 128;  ///< C: chunk edge in voxels (≥ 1)
  int level = 1;    ///< zlib level, 1 (fastest) to 9
  /// Bricks computed at once (0: twice the worker threads, reduced to fit max_bytes).
  int bricks_in_flight = 0;
  /// Memory budget for the bricks in flight, in bytes (--max-memory).
  uint64_t max_bytes = uint64_t{4096} << 20;
  /// Called on the calling thread after bricks it finishes, with the share done (0..1).
  std::function<void(double)> progress;
};

/// What write_zarr wrote.
struct ZarrResult {
  uint64_t occupied = 0;        ///< set voxels
  uint64_t chunks = 0;          ///< chunks of the array
  uint64_t chunks_written = 0;  ///< chunk files (those not all 0)
  int bricks_in_flight = 0;     ///< bricks computed at once
  double brick_bytes = 0;       ///< memory estimate of one brick in flight
};

/// Fills `grid` with the brick `box` of the lattice (VoxelGrid::box = box); called concurrently
/// from several threads, each with its own grid.
using BrickFunction = std::function<void(const IndexBox& box, VoxelGrid& grid)>;

/// True for a path ending in .zarr (case-insensitive).
bool is_zarr_extension(const std::filesystem::path& path);

/// Memory estimate of one brick in flight (its bits, a chunk's bytes and its compressed copy,
/// the voxelizer's scratch), in bytes.
double zarr_brick_bytes(const VoxelLattice& lattice, int chunk);

/// Writes the store (see above). \throws InputError "PATH: ..." for chunk < 1 or level out of
/// 1..9, a target that exists and is not a Zarr store Cover wrote (a regular file, a folder
/// holding other files), an unwritable folder, or a write failure; the check_memory
/// message when one brick does not fit max_bytes. Exceptions from `brick` are rethrown after
/// the temporary directory is removed.
ZarrResult write_zarr(const std::filesystem::path& path, const VoxelLattice& lattice,
                      const ZarrOptions& options, const BrickFunction& brick);

/// Writes a whole grid held in memory (grid.whole()) as the same store: each brick copied from
/// `grid`. \throws PreconditionError when the grid is a region; otherwise as above.
ZarrResult write_zarr(const std::filesystem::path& path, const VoxelGrid& grid,
                      const ZarrOptions& options = {});

}  // namespace cover
