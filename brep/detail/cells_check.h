#pragma once
// The exact check of a mesh as written, shared by the cell pieces and their glued mesh
// (cells.cpp). Not installed API.

#include <string>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover::brep::detail {

/// Replaces every face of more than 3 vertices whose vertices do not all share one coordinate
/// value (a face on a wall does) by the triangles mesh/triangulate.h tiles it with: a rounded
/// constructed point leaves a split face generally not planar, and its triangles are then what
/// the file means (and what the exact self-intersection test checks). `kinds` (one entry per
/// face, or empty) follows the faces. A face whose tiling drops a collinear triangle or crosses
/// itself is kept as it is (the check below then fails on it).
template <class Kind>
void triangulate_nonplanar(PolygonMesh& mesh, std::vector<Kind>& kinds);

/// Why `mesh` is not valid as written, or "" when it is: a closed, consistently oriented
/// 2-manifold without degenerate faces or self-intersections (CGAL's exact test on the doubles;
/// distinct vertices at one point are a contact) whose exact signed volume is > 0. With
/// `contacts_allowed` (the cut mesh itself has distinct vertices at one point: a result that
/// touches itself, whose pieces touch there too) the self-intersection test is left out.
std::string invalid_reason(const PolygonMesh& mesh, bool contacts_allowed = false);

}  // namespace cover::brep::detail
