#pragma once
// Unsigned distances from points to the covering triangles of a BVH (covering/bvh.h): the
// nearest triangle by a depth-first walk pruned by the distance to each node's box (the float
// boxes enclose the exact ones, so the pruning never drops the nearest), each triangle's closest
// point by its Voronoi regions (field/closest.h, Ericson §5.1.5), in doubles. Model::distance
// signs them by the exact classification.

#include <span>
#include <vector>

#include "cover/covering/bvh.h"

namespace cover {

/// The distance from each point to the nearest triangle of `bvh` (+∞ when it has none). Parallel;
/// thread-count independent.
std::vector<double> nearest_distances(const Bvh& bvh, std::span<const Vec3> points);

}  // namespace cover
