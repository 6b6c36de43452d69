#pragma once
// The C interface between io/vdb_io.cpp and the OpenVDB plugin cover_vdb.so
// (io/vdb_plugin.cpp), loaded with dlopen on the first .vdb write.
//
// Why a plugin: linking libopenvdb into a program costs every start of it ~35 ms of dynamic symbol
// lookups (62k relocations), a third of a small `cover evaluate`. Only .vdb output needs OpenVDB,
// so only it pays. Plain C types, so the plugin and its loader need no common C++ ABI beyond the C
// one.

#include <stddef.h>
#include <stdint.h>

extern "C" {

/// Bumped whenever CoverVdbGrid or the function's meaning changes; the loader refuses another.
#define COVER_VDB_PLUGIN_VERSION 1

/// A whole voxel grid (voxel/voxel_grid.h): voxel (i, j, k) is bit k % 64 of
/// bits[(i·dims[1] + j)·words_per_column + k / 64].
struct CoverVdbGrid {
  double origin[3];
  double spacing;
  int dims[3];
  size_t words_per_column;
  const uint64_t* bits;
};

/// int cover_vdb_plugin_version(void): COVER_VDB_PLUGIN_VERSION of the plugin.
typedef int (*CoverVdbVersionFn)(void);
/// int cover_vdb_write(grid, path, message, capacity): writes the grid as one BoolGrid
/// "occupancy" to `path` (io/vdb_io.h says what the file holds); 0 on success, else nonzero
/// with a one-line reason in `message` (NUL-terminated, at most `capacity` bytes).
typedef int (*CoverVdbWriteFn)(const CoverVdbGrid* grid, const char* path, char* message,
                               size_t capacity);

}  // extern "C"
