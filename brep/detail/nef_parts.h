#pragma once
// The exact fallback of decompose.h for a piece no plane cut could split (CGAL's Nef polyhedra;
// CGAL is included by nef_parts.cpp only). Not installed API.

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover::brep::detail {

/// The convex parts of the closed, outward triangle mesh `piece` (CGAL convex_decomposition_3 on
/// a Nef polyhedron with exact rational points): per part, its vertices rounded to the nearest
/// doubles. Empty when the Nef polyhedron cannot be built (a piece that is not a closed
/// 2-manifold). Slow (seconds for a few hundred faces): meant for small pieces.
std::vector<std::vector<Vec3>> nef_convex_parts(const PolygonMesh& piece);

/// One cut of decompose's cut tree: the exact plane through three points (clip.h) and the half
/// kept (above: the side the normal (p1 − p0) × (p2 − p0) points to).
struct HalfSpace {
  std::array<Vec3, 3> plane;
  bool above;
};

/// The exact regions of one shell (its Nef polyhedron, built once: a few tenths of a second for
/// thousands of faces).
class ShellRegions {
 public:
  /// `shell`: closed, outward triangles (exact points).
  explicit ShellRegions(const PolygonMesh& shell);
  ~ShellRegions();
  ShellRegions(const ShellRegions&) = delete;
  ShellRegions& operator=(const ShellRegions&) = delete;

  /// The convex parts, as nef_convex_parts, of the exact region shell ∩ box `near` ∩ every
  /// half-space of `cuts` (Nef intersections: no point is rounded until the parts are). The
  /// region may hold more than the piece sought (parts of its cut-tree siblings within the box):
  /// the caller picks the parts. nullopt when the Nef polyhedron fails; empty for an empty region.
  std::optional<std::vector<std::vector<Vec3>>> convex_parts(std::span<const HalfSpace> cuts,
                                                             const Bbox& near) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cover::brep::detail
