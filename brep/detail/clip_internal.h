#pragma once
// Internals shared by clip.cpp (kernel steps) and cap.cpp (rings and caps on exact constructed
// points). Not installed API.

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "cover/brep/clip.h"
#include "cover/brep/halfedge.h"
#include "cover/solid/predicates.h"  // plane_side, polygon_orientation, orient2d, orient3d

namespace cover::brep::detail {

/// What the cap needs to know about the clipped mesh.
struct CapContext {
  Plane plane;  ///< with `through`: a rounded plane whose normal[axis] has the exact sign
  /// The plane through three points (clip.h), exact; then `plane` only orients the cap frame.
  std::optional<std::array<Vec3, 3>> through;
  int axis = 2;                    ///< dominant axis of the normal (largest |n_k|)
  uint32_t original_vertices = 0;  ///< vertex ids below this are input vertices
  /// For vertex id original_vertices + i: the input vertices of the edge it splits.
  std::vector<std::array<uint32_t, 2>> constructed_from;
  std::vector<Vec3> input_points;  ///< input vertex positions (exact)
  std::vector<uint8_t> face_side;  ///< per face: 0 above, 1 below (grown by add_caps)
  bool triangulate = false;        ///< ClipOptions::triangulate_caps
};

struct CapStats {
  std::array<int64_t, 2> rings{0, 0};      ///< per side (0 above, 1 below)
  std::array<int64_t, 2> cap_faces{0, 0};  ///< per side
  int64_t forced_ears = 0;                 ///< ear_clip fallbacks (0 on valid input)
};

/// Walks the border half-edges of each side into rings, nests them, bridges holes, decomposes and
/// inserts the cap faces ([Erleben2006 §3, §4, §6]); sets every constructed vertex's position to
/// its exact point rounded to the nearest double. Throws NotComputable on inconsistent rings.
CapStats add_caps(HalfedgeMesh& mesh, CapContext& context);

}  // namespace cover::brep::detail
