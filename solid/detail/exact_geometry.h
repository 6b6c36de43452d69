#pragma once
// Exact geometric predicates used by solid/ without exposing CGAL (implemented with CGAL's Epick
// filtered predicates in self_intersect.cpp, the one translation unit of solid/ that includes
// CGAL).

#include <cstdint>
#include <span>
#include <vector>

#include "solid/types.h"

namespace cover::detail {

/// True when the points vertices[loop[i]] lie on one line, decided exactly on the input doubles.
/// Fewer than three distinct points (coincident coordinates count once) are collinear.
/// Precondition: every loop[i] < vertices.size().
bool all_collinear(std::span<const Vec3> vertices, std::span<const uint32_t> loop);

}  // namespace cover::detail
