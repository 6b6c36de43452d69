#pragma once
// Defect repair of an OPEN leaf on load (solid/scene.h prepare_leaf; CONTRACT.md "Semantics").
// Only meshes with boundary edges are repaired (a closed leaf is kept exactly as read, so its
// results do not change):
//   welding            vertices with exactly equal coordinates (−0 == +0) become one index, the
//                      first in vertex order (OFF / PLY / OBJ seams; STL already welds on read).
//                      The vertex array is kept; faces are re-indexed.
//   zero-area faces    faces whose vertices all lie on one line (exact, all_collinear) are
//                      dropped: they bound no solid angle.

#include <cstddef>

#include "solid/polygon_mesh.h"

namespace cover {

/// Re-indexes faces so that exactly equal vertices share the lowest index; returns the number
/// of vertex indices that were merged into another (0: nothing changed).
size_t weld_duplicate_vertices(PolygonMesh& mesh);

/// Drops faces whose vertices are all collinear (exact); returns how many were dropped.
size_t drop_zero_area_faces(PolygonMesh& mesh);

}  // namespace cover
