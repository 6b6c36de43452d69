#pragma once
// Object-order casting of a camera's pixel rays (render/render.h): instead of walking a BVH per
// pixel, each covering triangle is projected onto the image and tested, exactly, against the rays
// of the pixels its projection may cover.
//
// Why: most triangles cover a pixel or less, so the work is about one exact crossing test per
// (triangle, nearby pixel) instead of a BVH walk per ray — and no BVH is built for the first frame
// (on the 606k-triangle preview scene a BVH build would be over a third of a ray-cast first
// frame; bench/render_vs_embree). Orthographic rays are parallel, which also allows
// a 2D prefilter and a shortcut for pixels certainly inside a triangle's projection; perspective
// rays get the exact test on every candidate.
//
// Exactness: the projection only picks candidate pixels, with a margin many orders of magnitude
// above its rounding (object_order.cpp); every hit is decided by the same exact perturbed
// crossing test, with the same t (hit_t) and the same sort and sweep, as covering/ray.cpp
// (covering/ray_steps.h). So each pixel gets the same VisibleHit as first_visible() of
// its ray; RayHit::tri indexes this module's triangles, not a BVH's.

#include <algorithm>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <utility>

#include "cover/covering/bvh.h"
#include "cover/covering/ray.h"
#include "cover/render/camera.h"
#include "cover/solid/solid.h"

namespace cover {

/// The allowed parameter interval [lo, hi] of a ray outside the removed half-space
/// {x : n·x > d} of a section (none: [0, ∞)); lo > hi: nothing visible.
inline std::pair<double, double> section_window(const Ray& ray,
                                                const std::optional<Plane>& section) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (!section) return {0.0, kInf};
  const double s = dot(section->normal, ray.dir);
  const double v0 = dot(section->normal, ray.origin) - section->offset;
  if (s == 0) return v0 <= 0 ? std::pair{0.0, kInf} : std::pair{1.0, 0.0};
  const double ts = -v0 / s;
  return s > 0 ? std::pair{0.0, ts} : std::pair{std::max(0.0, ts), kInf};
}

/// Called once per pixel (in parallel across tiles): pixel index (row-major), its ray, what it
/// sees first within its window, and the triangle of v.enter when v.hit && !v.cap.
using VisibleSink =
    std::function<void(size_t pixel, const Ray& ray, const VisibleHit& v, const Bvh::Tri* tri)>;

/// Runs `sink` for every pixel of `camera` (closed leaves) with the rays' windows
/// from `section` (section_window), tile by tile (tile ×
/// tile pixels); `tile_done(n)` after each tile with the tiles finished there (its calls may be
/// concurrent). Results do not depend on the thread count or the tile size.
void object_order_visible(const Solid& solid, const Camera& camera,
                          const std::optional<Plane>& section, int tile, const VisibleSink& sink,
                          const std::function<void(size_t)>& tile_done);

}  // namespace cover
