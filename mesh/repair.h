#pragma once
// Defect repair of an OPEN leaf on load (io/scene.h prepare_leaf; docs/cli.md#semantics).
// Only meshes with boundary edges are repaired (a closed leaf is kept exactly as read, so its
// results do not change):
//   welding            vertices with exactly equal coordinates (−0 == +0) become one index, the
//                      first in vertex order (OFF / PLY / OBJ seams; STL already welds on read).
//                      The vertex array is kept; faces are re-indexed.
//   zero-area faces    faces whose vertices all lie on one line (exact, all_collinear) are
//                      dropped: they bound no solid angle.

#include <cstddef>

#include "cover/mesh/validate.h"
#include "cover/solid/polygon_mesh.h"

namespace cover {

/// Re-indexes faces so that exactly equal vertices share the lowest index; returns the number
/// of vertex indices that were merged into another (0: nothing changed).
size_t weld_duplicate_vertices(PolygonMesh& mesh);

/// Drops faces whose vertices are all collinear (exact); returns how many were dropped.
size_t drop_zero_area_faces(PolygonMesh& mesh);

/// What loading would repair in `mesh` (validated as `report`) and what is left: `cover info`'s
/// "repair", "rule" and "boundary_edge_fraction".
struct RepairReport {
  int64_t welded_vertices = 0;
  int64_t zero_area_faces = 0;
  int64_t boundary_edges = 0;  ///< after repair
  int64_t edges = 0;           ///< after repair
  bool open() const { return boundary_edges > 0; }
  const char* rule() const { return open() ? "generalized winding number" : "exact"; }
  double boundary_edge_fraction() const {
    return edges > 0 ? static_cast<double>(boundary_edges) / static_cast<double>(edges) : 0.0;
  }
};
RepairReport repair_report(const PolygonMesh& mesh, const MeshReport& report);

}  // namespace cover
