#pragma once
// The exact per-triangle steps of ray casting (covering/ray.cpp), shared with raster/'s
// object-order render of parallel rays (render/render.cpp), so that both find the same hits, with
// the same t, in the same order, and sweep them into the same spans.

#include <cstddef>

#include "cover/covering/bvh.h"
#include "cover/covering/ray.h"
#include "cover/solid/solid.h"

namespace cover::detail {

/// The perturbation axes (u, w, k) for a ray direction: k is the axis of its largest component
/// (ray.h).
struct Axes {
  int u, w, k;
};
Axes axes_for(const Vec3& d);

/// Whether the perturbed ray crosses t ahead of its origin; `sign` gets the hit's sign (ray.h).
bool crosses(const Bvh::Tri& t, const Ray& ray, Axes ax, int& sign);

/// The last step of crosses() for a ray whose line is known to cross t's interior with the
/// given sign (sign(n·d)): whether the crossing lies ahead of the (perturbed) origin.
bool ahead(const Bvh::Tri& t, const Ray& ray, Axes ax, int sign);

/// The hit parameter of a ray that crosses t: from the face's shared plane `plane` (nullptr for a
/// triangular face: t's own plane), clamped into the slab interval of t's exact box. The same
/// value as every traversal of covering/ray.cpp computes.
double hit_t(const Bvh::FacePlane* plane, const Bvh::Tri& t, const Ray& r);

/// Hit order: t, then leaf, then face, then triangle index.
bool hit_before(const RayHit& a, const RayHit& b);

/// Sorts result.hits (hit_before) and sweeps them into the CSG inside spans: the winding at the
/// origin is the sum of the signs (closed leaves), then per-leaf counters with the expression
/// evaluated after the last hit at each t.
void sweep_spans(RayResult& out, const CsgTree& tree, size_t leaves);

}  // namespace cover::detail
