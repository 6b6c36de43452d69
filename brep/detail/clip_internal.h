#pragma once
// Internals shared by clip.cpp (kernel steps), exact.cpp (exact predicates on input doubles) and
// cap.cpp (rings and caps on exact constructed points). Not installed API.

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "brep/clip.h"
#include "brep/halfedge.h"

namespace cover::brep::detail {

inline constexpr double kFilterMin = 1e-200;  // below: the relative bounds could fail (underflow)
inline constexpr double kFilterMax = 1e200;   // above: overflow

/// Exact sign of n·v − d (rational arithmetic).
int plane_side_exact(const Vec3& n, double d, const Vec3& v);

/// Exact sign of n·v − d. Filter: the double evaluation ((n.x·v.x + n.y·v.y) + n.z·v.z) − d has
/// error ≤ 5u·M (1 + 5u), u = 2^−53, M = |n.x·v.x| + |n.y·v.y| + |n.z·v.z| + |d| (four roundings
/// of a sum of four terms, Higham's γ_4, plus the product roundings); 1e-15·M (> 9u·M) covers it
/// and the rounding of M itself. Outside [kFilterMin, kFilterMax] the exact path decides.
inline int plane_side(const Vec3& n, double d, const Vec3& v) {
  const double px = n.x * v.x, py = n.y * v.y, pz = n.z * v.z;
  const double value = ((px + py) + pz) - d;
  const double mag = std::abs(px) + std::abs(py) + std::abs(pz) + std::abs(d);
  if (mag > kFilterMin && mag < kFilterMax) {
    const double bound = 1e-15 * mag;
    if (value > bound) return 1;
    if (value < -bound) return -1;
  }
  return plane_side_exact(n, d, v);
}

/// Exact sign of the orientation of (a, b, c) projected on the coordinate plane that drops
/// `axis` (0: (y, z), 1: (z, x), 2: (x, y)): the `axis` component of (b−a)×(c−a).
int orient2d_exact(const Vec3& a, const Vec3& b, const Vec3& c, int axis);

/// orient2d with Shewchuk's stage-A filter ((3 + 16u)u bound), exact fallback.
inline int orient2d(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
  const int u = axis == 2 ? 0 : axis + 1, w = axis == 0 ? 2 : (axis == 1 ? 0 : 1);
  const double left = (a[u] - c[u]) * (b[w] - c[w]);
  const double right = (a[w] - c[w]) * (b[u] - c[u]);
  const double det = left - right;
  const double sum = std::abs(left) + std::abs(right);
  if (sum > kFilterMin && sum < kFilterMax) {
    const double bound = 3.3306690738754716e-16 * sum;
    if (det > bound) return 1;
    if (det < -bound) return -1;
  }
  return orient2d_exact(a, b, c, axis);
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
