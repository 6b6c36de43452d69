#pragma once
// Octree export (CONTRACT.md `cover octree`), by extension, written atomically (temporary file,
// then rename):
//   .htg   VTK XML HyperTreeGrid, file version 1.0 (opens in ParaView; read back by VTK 9.1's
//          vtkXMLHyperTreeGridReader): one tree over the cube, cell arrays "state" (UInt8:
//          0 empty, 1 full, 2 partial) and "occupancy" (Float32), inline base64
//   .bt    OctoMap binary tree (octovis and liboctomap open it; the bytes liboctomap's
//          OcTree::writeBinary writes for the same leaves): an OcTree whose resolution is the
//          finest cell size; occupied = full, or partial with occupancy >= threshold;
//          free = empty, or partial below it. OctoMap keys have no origin: the cube is stored
//          centred on the origin (x_octomap = x − (bounds.min + size/2)); depth 1..16
//   .json  summary: bounds {min, size}, depth, nodes, leaves {empty, full, partial}, threshold,
//          and every leaf cell in node order {min, size, state ("empty" / "full" / "partial"),
//          occupancy}

#include <filesystem>

#include "octree/octree.h"

namespace cover {

/// True for .htg, .bt and .json (any letter case).
bool is_octree_extension(const std::filesystem::path& path);

/// Writes `tree` in the format of `path`'s extension. Throws InputError naming the file on an
/// unsupported extension, an empty tree, a .bt of depth 0, or I/O failure, and InputError for a
/// threshold outside [0, 1].
void write_octree(const std::filesystem::path& path, const Octree& tree, double threshold);

}  // namespace cover
