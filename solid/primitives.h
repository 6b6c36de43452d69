#pragma once
// Primitive leaves as closed, outward-oriented polygon meshes (docs/cli.md#scenes).

#include "cover/solid/polygon_mesh.h"

namespace cover {

/// Largest `segments` of a sphere (~8M faces) and of a cylinder (scenes and cover::sphere /
/// cover::cylinder refuse more).
inline constexpr int kMaxSphereSegments = 4096;
inline constexpr int kMaxCylinderSegments = 1 << 20;

/// Axis-aligned box [min, max] as 6 quads. \pre min < max componentwise, finite (cover::box
/// checks; so do cover::sphere and cover::cylinder for the two below).
PolygonMesh make_box(Vec3 min, Vec3 max);

/// UV sphere with `segments` longitudes (>= 3) and max(2, segments/2) latitude bands; the
/// vertices lie exactly on the sphere (up to rounding), so the polyhedron is inscribed.
PolygonMesh make_sphere(Vec3 center, double radius, int segments);

/// Cylinder from `base` to `top` with a regular `segments`-gon (>= 3) cross-section inscribed in
/// the circle of `radius`; two polygonal caps and quad sides. Precondition: base != top.
PolygonMesh make_cylinder(Vec3 base, Vec3 top, double radius, int segments);

}  // namespace cover
