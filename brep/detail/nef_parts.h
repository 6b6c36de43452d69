#pragma once
// The exact fallback of decompose.h for a piece no plane cut could split (CGAL's Nef polyhedra;
// CGAL is included by nef_parts.cpp only). Not installed API.

#include <vector>

#include "solid/polygon_mesh.h"

namespace cover::brep::detail {

/// The convex parts of the closed, outward triangle mesh `piece` (CGAL convex_decomposition_3 on
/// a Nef polyhedron with exact rational points): per part, its vertices rounded to the nearest
/// doubles. Empty when the Nef polyhedron cannot be built (a piece that is not a closed
/// 2-manifold). Slow (seconds for a few hundred faces): meant for small pieces.
std::vector<std::vector<Vec3>> nef_convex_parts(const PolygonMesh& piece);

}  // namespace cover::brep::detail
