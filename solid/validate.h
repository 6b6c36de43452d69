#pragma once
// Topological and geometric validation of one leaf mesh (what `cover info` reports per leaf).
// Edges are undirected vertex-index pairs of the faces' loops; false edges (a pair used once in
// each direction inside the SAME face, paper §3 Fig. 1) are not edges of the surface and are
// skipped. Conventions:
//   boundary edge      used by exactly one face side
//   non-manifold edge  used by more than two face sides
//   oriented           every manifold edge is traversed once in each direction
//   outward            oriented and the signed covering volume is > 0
//   components         connected components of faces through shared edges
//   genus              (2·components − χ)/2 with χ = V − E + F over referenced vertices;
//                      only for closed, manifold, oriented meshes (else -1)
//   degenerate face    fewer than 3 distinct vertices, or zero area (all vertices collinear, exact)

#include <cstdint>
#include <optional>

#include "solid/polygon_mesh.h"

namespace cover {

struct ValidateOptions {
  bool check_self_intersection = true;  ///< run the (exact, CGAL) self-intersection test
};

struct MeshReport {
  bool closed = false;
  bool manifold = false;
  bool oriented = false;
  bool outward = false;
  int64_t boundary_edges = 0;
  int64_t nonmanifold_edges = 0;
  int64_t components = 0;
  int64_t genus = -1;  ///< -1 when not closed/manifold/oriented
  int64_t degenerate_faces = 0;
  double volume = 0;  ///< signed covering volume (Σ signed tetra volumes from the origin)
  std::optional<bool> self_intersecting;  ///< empty when not checked
};

/// Validates one mesh. Precondition: all indices < vertices.size().
MeshReport validate_mesh(const PolygonMesh& mesh, const ValidateOptions& options = {});

/// Exact self-intersection test of the faces (fan-triangulated); false edges and degenerate
/// triangles ignored; triangles that share vertices intersect only if they meet elsewhere.
bool self_intersects(const PolygonMesh& mesh);

}  // namespace cover
