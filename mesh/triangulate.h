#pragma once
// Triangulation of one polygon face of a mesh, shared by the self-intersection test (validate.h)
// and boundary evaluation (boolean/evaluate.h). Exact: every decision is a CGAL Epick predicate
// on the input doubles; no point is constructed. Notation:
//   loop        the face's vertex indices in order (cyclic); a face with holes holds several
//               loops joined by false edges (each run once in each direction)
//   projection  the coordinate plane that drops the dominant axis of the loop's Newell normal
//               (computed in doubles: it only picks the plane and the orientation; when it is
//               zero, the normal of the first corner that is not)
//   fan         the triangles (loop[0], loop[i], loop[i+1]): the covering triangles of the face
//               (covering/triangles.cpp), used when the projected loop turns the same way
//               (never straight) at every vertex and repeats no index
//   otherwise   a constrained Delaunay triangulation of the projected loop edges, keeping the
//               regions crossed an odd number of times from outside: a false edge (run twice)
//               separates nothing, so holes stay holes
// Every loop vertex is a corner of a triangle (no vertex in the middle of a fanned side).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "cover/solid/types.h"

namespace cover {

/// Index of the largest |n_k| (ties to the lower axis): the coordinate a projection of a plane
/// with normal n drops.
inline int dominant_axis(const Vec3& n) {
  const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
  return ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
}

/// (b − a) × (c − a) times a positive power of two, in doubles: the differences are first
/// scaled (exactly) to magnitude at most 1, so that the normal of a tiny triangle (side 1e-200)
/// does not underflow to 0. For choosing a projection; signs that matter are taken exactly.
inline Vec3 normal_direction(const Vec3& a, const Vec3& b, const Vec3& c) {
  Vec3 u = b - a, v = c - a;
  const double m = std::max(
      {std::abs(u.x), std::abs(u.y), std::abs(u.z), std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (m > 0 && std::isfinite(m)) {
    const int e = -std::ilogb(m);
    u = {std::ldexp(u.x, e), std::ldexp(u.y, e), std::ldexp(u.z, e)};
    v = {std::ldexp(v.x, e), std::ldexp(v.y, e), std::ldexp(v.z, e)};
  }
  return cross(u, v);
}

/// What triangulate_face found out about a face's boundary.
enum class FaceTiling : uint8_t {
  kSimple,    ///< no crossing: the triangles tile the face once
  kWinding,   ///< turns one way at every vertex but winds k > 1 times (a star): the fan, which
              ///< covers each point as often as the loop winds around it
  kCrossing,  ///< loop edges cross in the projection: no triangles
};

/// Appends the triangles of the face `loop` over `points`: vertex indices, in the loop's
/// orientation (counter-clockwise seen from where the Newell normal points); collinear
/// triangles are dropped. Precondition: every loop[i] < points.size().
FaceTiling triangulate_face(std::span<const Vec3> points, std::span<const uint32_t> loop,
                            std::vector<std::array<uint32_t, 3>>& out);

}  // namespace cover
