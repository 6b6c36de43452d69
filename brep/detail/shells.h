#pragma once
// The shells of a closed triangle mesh, for decompose.h (not installed API).

#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover::brep::detail {

/// Splits a closed, outward triangle mesh into its shells: the classes of triangles connected
/// through edges, where at an edge held by k > 1 triangles in each direction each triangle
/// holding a → b is joined to the triangle holding b → a that comes next around the edge on its
/// inner side (exact orient3d / orient2d on the doubles). Solids that touch along an edge or at
/// a vertex, or lie apart, are different shells. Each shell comes with its own vertices (in
/// first-use order), in the order of its first triangle.
/// \throws InputError when an edge is held by different numbers of triangles in the two
///   directions (an open or inconsistently oriented mesh).
std::vector<PolygonMesh> split_shells(const PolygonMesh& triangles);

}  // namespace cover::brep::detail
