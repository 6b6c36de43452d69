#pragma once
// Repair of the contacts that rounding makes in an exactly computed mesh.
//
// The evaluator (boolean/) and the plane patcher (brep/) decide everything on exact points and
// write each constructed point rounded to the nearest double, independently. Two exact points
// that are distinct but closer than rounding distance (a fan of edges meeting a plane near a
// vertex that lies just off it; two intersection curves crossing at a shallow angle) can then
// round to one double point, or to points one ulp apart across each other: the written mesh
// touches or crosses itself in a sliver, although the exact one does not.
//
// repair_rounding finds the faces that meet (exact predicates on the written doubles,
// intersecting_face_pairs of validate.h, tested only for faces with a rounded vertex) and
// collapses the shortest edge of such faces: one end vertex is dropped and its faces use the
// other, at the other's position (no new coordinates are made). A collapse is taken only when it
// keeps the mesh a closed, consistently oriented 2-manifold around the kept vertex (each edge
// at the vertex used once in each direction, the faces around it one fan, no face repeated, no
// face left with a repeated vertex); faces left with fewer than 3 distinct corners are dropped.
// It repeats until no pair is left or no collapse is allowed (then `remaining_pairs` > 0).
//
// The edges collapsed are rounding-scale: at most kMaxCollapseRelative of the largest absolute
// coordinate long (a collapse moves the mesh by at most that, so volumes change by at most about
// that length times the area of the faces around it).

#include <cstdint>
#include <span>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover {

/// Longest edge a collapse may remove, relative to the largest absolute vertex coordinate:
/// 2^-36 ≈ 1.5e-11, i.e. about 32,000 ulps of that coordinate. Rounding moves a point by at most
/// half an ulp per coordinate and a chain of clips by a few; slivers come from points some ulps
/// apart. The margin leaves room for that while staying far below what a model means (a feature
/// of 1e-11 of the model's size is below the 1e-9 relative agreement the evaluator is held to).
inline constexpr double kMaxCollapseRelative = 0x1p-36;

struct RoundingRepair {
  int64_t collapsed_edges = 0;
  int64_t dropped_faces = 0;
  int64_t rounds = 0;           ///< detection passes that found pairs
  int64_t remaining_pairs = 0;  ///< face pairs still meeting at the end (0: repaired)
  /// Old face index of each face of the repaired mesh; empty when nothing changed (no copy).
  std::vector<uint32_t> face_origin;
  bool changed() const { return collapsed_edges > 0; }
};

/// Repairs `mesh` (closed, oriented 2-manifold) in place as described above. `rounded` has one
/// flag per vertex: set for the vertices whose coordinates were rounded (only faces with such a
/// vertex are tested against the others; faces without one are taken to be valid among
/// themselves). Collapsed vertices are removed from the vertex array (the others keep their
/// order). Cheap when nothing meets: one box-intersection pass over the suspect faces.
/// `group` (optional, one id per face) is passed to intersecting_face_pairs: faces with one
/// nonzero id are known not to overlap each other; a collapse keeps a face's id.
RoundingRepair repair_rounding(PolygonMesh& mesh, std::span<const uint8_t> rounded,
                               std::span<const uint32_t> group = {});

}  // namespace cover
