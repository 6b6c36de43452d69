#pragma once
// Internals shared by clip.cpp (kernel steps), exact.cpp (exact predicates on input doubles) and
// cap.cpp (rings and caps on exact constructed points). Not installed API.

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "brep/clip.h"
#include "brep/halfedge.h"
#include "covering/predicates.h"  // orient2d, orient3d and the filter range

namespace cover::brep::detail {

/// Exact sign of n·v − d (rational arithmetic).
int plane_side_exact(const Vec3& n, double d, const Vec3& v);

/// Exact sign of n·v − d. Filter: the double evaluation ((n.x·v.x + n.y·v.y) + n.z·v.z) − d has
/// error ≤ 5u·M (1 + 5u), u = 2^−53, M = |n.x·v.x| + |n.y·v.y| + |n.z·v.z| + |d| (four roundings
/// of a sum of four terms, Higham's γ_4, plus the product roundings); 1e-15·M (> 9u·M) covers it
/// and the rounding of M itself. Outside the filter range of covering/predicates.h the exact
/// path decides.
inline int plane_side(const Vec3& n, double d, const Vec3& v) {
  const double px = n.x * v.x, py = n.y * v.y, pz = n.z * v.z;
  const double value = ((px + py) + pz) - d;
  const double mag = std::abs(px) + std::abs(py) + std::abs(pz) + std::abs(d);
  if (mag > cover::detail::kFilterMin && mag < cover::detail::kFilterMax) {
    const double bound = 1e-15 * mag;
    if (value > bound) return 1;
    if (value < -bound) return -1;
  }
  return plane_side_exact(n, d, v);
}

/// Exact sign of the signed area of the closed polygon `points` projected dropping `axis`.
int polygon_orientation(const std::vector<Vec3>& points, int axis);

/// What the cap needs to know about the clipped mesh.
struct CapContext {
  Plane plane;
  int axis = 2;                          ///< dominant axis of the normal (largest |n_k|)
  uint32_t original_vertices = 0;        ///< vertex ids below this are input vertices
  /// For vertex id original_vertices + i: the input vertices of the edge it splits.
  std::vector<std::array<uint32_t, 2>> constructed_from;
  std::vector<Vec3> input_points;        ///< input vertex positions (exact)
  std::vector<uint8_t> face_side;        ///< per face: 0 above, 1 below (grown by add_caps)
  bool triangulate = false;              ///< ClipOptions::triangulate_caps
};

struct CapStats {
  std::array<int64_t, 2> rings{0, 0};      ///< per side (0 above, 1 below)
  std::array<int64_t, 2> cap_faces{0, 0};  ///< per side
  int64_t forced_ears = 0;                 ///< ear_clip fallbacks (0 on valid input)
};

/// Walks the border half-edges of each side into rings, nests them, bridges holes, decomposes
/// and inserts the cap faces (paper §3, §4, §6); sets every constructed vertex's position to its
/// exact point rounded to the nearest double. Throws NotComputable on inconsistent rings.
CapStats add_caps(HalfedgeMesh& mesh, CapContext& context);

}  // namespace cover::brep::detail
