#pragma once
// Exact plane clip and patch of a closed mesh ([Erleben2006 §3–§6]).
// Both halves are kept and closed by cap faces on the plane.
//   above = solid ∩ {x : n·x ≥ d}   (cap faces have outward normal −n)
//   below = solid ∩ {x : n·x ≤ d}   (cap faces have outward normal +n)
// Vertex sides are exact (no tolerance); points constructed on crossing edges are computed once,
// shared by both halves and rounded to the nearest double; every 2D decision of the cap is exact
// on the unrounded points (see cap.cpp).

#include <array>
#include <cstdint>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover::brep {

/// The clip plane n·x = d (solid/types.h; n need not be unit length; n ≠ 0).
using cover::Plane;

struct ClipOptions {
  bool triangulate_caps = false;  ///< caps as triangles; default: convex polygons [Erleben2006 §4]
};

/// One half of the clip.
struct ClipHalf {
  PolygonMesh mesh;       ///< closed, outward-oriented 2-manifold (empty when nothing is there)
  int64_t rings = 0;      ///< boundary rings walked on the plane (touching rings walk as one)
  int64_t cap_faces = 0;  ///< faces added on the plane
  /// #F: per face of `mesh`, the input face it is part of, or kNoFace for a cap face.
  std::vector<uint32_t> face_source;
};

/// ClipHalf::face_source of a cap face.
inline constexpr uint32_t kNoFace = 0xffffffffu;

struct ClipResult {
  ClipHalf above, below;
  int64_t constructed_vertices = 0;  ///< edge ∩ plane points (each shared by both halves)
  int64_t split_vertices = 0;        ///< vertex copies made by split_nonmanifold_vertices: one per
                                     ///< plane vertex shared by the halves, one per extra fan
  int64_t forced_ears = 0;           ///< ear-clipping fallbacks (0 unless rings are degenerate)
  double cap_seconds = 0;            ///< time in the cap (exact points, rings, decomposition)
};

/// Clips a closed, consistently oriented 2-manifold polygon mesh (any simple polygons; faces with
/// holes joined by false edges too) that does not intersect itself, by `plane`.
/// Faces lying in the plane go to the half they bound from outside (normal·n < 0: above).
/// Throws InputError for a zero or non-finite plane, an open or non-manifold mesh; NotComputable
/// when the cap's rings are inconsistent (which only a self-intersecting input can cause).
ClipResult clip(const PolygonMesh& mesh, const Plane& plane, const ClipOptions& options = {});

/// The same clip by the exact plane through three points (not collinear; throws InputError
/// otherwise): its positive side (`above`) is where the normal (p1 − p0) × (p2 − p0) points
/// (orient3d > 0). The plane then contains p0, p1, p2 exactly, which a rounded (n, d) cannot:
/// decompose.h cuts through a mesh edge this way.
ClipResult clip(const PolygonMesh& mesh, const std::array<Vec3, 3>& through,
                const ClipOptions& options = {});

}  // namespace cover::brep
