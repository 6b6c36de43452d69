#pragma once
// Smooth shading normals for the renderer: per face corner, the area-weighted mean of the unit
// normals of the faces around the corner's vertex that lie within the crease angle of the
// corner's own face (auto-smooth by angle: a sphere's or a cylinder's facets shade as one
// surface, a box's edges and a CAD part's creases stay sharp, a scan's facet noise below the
// angle disappears). A hit interpolates its fan triangle's three corners barycentrically.
// Deterministic: each corner's sum runs over its vertex's faces in face order.

#include <array>
#include <cstdint>

#include "cover/covering/bvh.h"
#include "cover/solid/large_vector.h"
#include "cover/solid/solid.h"

namespace cover {

struct ShadingNormals {
  /// Per entry of Solid::face_vertices (face f's corners at face_start[f]..): the corner's
  /// smooth unit normal in the face's stored orientation. Empty: flat shading.
  LargeBuffer<std::array<float, 3>> corner;
  bool empty() const { return corner.empty(); }
};

/// The corner normals of `solid`'s mesh leaves for a crease angle in degrees; empty (flat
/// shading) for crease_degrees <= 0 or a solid without faces. O(Σ corners · vertex degree).
ShadingNormals shading_normals(const Solid& solid, double crease_degrees);

/// The smooth normal at `point` on fan triangle `tri` (Bvh::Tri: (v0, v_k, v_k+1) of face
/// tri.face in its leaf's own orientation), turned to the side of the triangle's own normal
/// cross(b − a, c − a); the triangle's unit normal where `normals` is empty or the corners are
/// not found.
Vec3 smooth_normal(const Solid& solid, const ShadingNormals& normals, const Bvh::Tri& tri,
                   Vec3 point);

}  // namespace cover
