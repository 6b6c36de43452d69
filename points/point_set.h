#pragma once
// Point-set leaves (docs/design.md "Point sets"): an oriented point cloud stands for the set where
// its winding number exceeds 1/2 (Barill et al. 2018, "Fast winding numbers for soups and
// clouds"): each point is a dipole of area a_i and normal n_i. Cover carries each dipole as one
// small triangle (dipole_triangles): far from it, a flat triangle of area a and unit normal n at
// p subtends a·(p − q)·n/|p − q|³ + O(size/distance) of the solid angle, the dipole's; near it,
// the triangle's exact solid angle is the regularized value. The cloud then is an open-mesh leaf
// of those triangles, answered by the generalized winding number with its bounds
// (covering/gwn.h), by every query command.
//
// Conventions
//   neighbours  the k nearest other points of a point (nanoflann kd-tree, squared Euclidean
//               distances; ties in the library's order, which depends only on the input)
//   normals     when not given: the eigenvector of the smallest eigenvalue of the covariance of
//               the point and its k neighbours (PCA; Hoppe et al. 1992), oriented by
//               propagation along a minimum spanning tree of the symmetric kNN graph with
//               weights 1 − |n_i·n_j| (Hoppe §3.3), each connected component from its point of
//               largest x, whose normal is set to point to +x (outward for a closed scan)
//   areas       the area of the point's Voronoi cell among its neighbours, projected to its
//               tangent plane (Barill §4.3), the cell bounded by the square of half-side the
//               distance to the k-th neighbour

#include <span>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover {

struct PointSetOptions {
  int neighbours = 16;  ///< k, from 3 to 64
};

/// Normals by PCA and MST orientation (conventions above). \pre ≥ k + 1 finite points.
std::vector<Vec3> estimate_normals(std::span<const Vec3> points, const PointSetOptions& options);

/// Tangent-plane Voronoi areas (conventions above). \pre normals unit, as many as points.
std::vector<double> voronoi_areas(std::span<const Vec3> points, std::span<const Vec3> normals,
                                  const PointSetOptions& options);

/// One equilateral triangle per point, centred on it in its tangent plane, of its area,
/// counter-clockwise about its normal (3 vertices per point, in point order).
PolygonMesh dipole_triangles(std::span<const Vec3> points, std::span<const Vec3> normals,
                             std::span<const double> areas);

/// The leaf mesh of a cloud: normals given (one per point, normalized here; a zero normal is an
/// error) or estimated when `normals` is empty, areas by voronoi_areas, then dipole_triangles.
/// \throws InputError for fewer than k + 1 points, a bad k, a non-finite point, normals of the
/// wrong count or a zero normal ("normal 12 is zero").
PolygonMesh point_set_mesh(std::span<const Vec3> points, std::span<const Vec3> normals,
                           const PointSetOptions& options = {});

}  // namespace cover
