#pragma once
// The exact convex hull behind decompose.h (CGAL convex_hull_3 with exact predicates; CGAL is
// included by convex_hull.cpp only). Not installed API.

#include <span>

#include "cover/solid/polygon_mesh.h"

namespace cover::brep::detail {

/// The convex hull of `points` as a closed, outward triangle mesh over the hull's vertices.
/// Every point is on the inner side of, or on, every triangle's plane (exact orient3d).
/// Precondition: the points are not all coplanar.
PolygonMesh convex_hull(std::span<const Vec3> points);

}  // namespace cover::brep::detail
