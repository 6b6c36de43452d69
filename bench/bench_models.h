#pragma once
// The scaling benchmarks' model and queries (bench_queries, scaling_vs_cgal): a closed bumpy
// sphere at a target triangle count, uniform points in its box, rays from a sphere around it.
// Every random input is seeded, so both programs query the same mesh with the same points and rays.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "cover/covering/ray.h"
#include "cover/solid/primitives.h"
#include "cover/solid/solid.h"

namespace bench {

/// Longitudes of make_sphere whose triangulation has about `target` triangles: s longitudes and
/// s/2 bands give 2s pole triangles + s(s/2 − 2) quads of 2 triangles = s² − 2s (s even).
inline int segments_for(int64_t target) {
  const int s = static_cast<int>(std::lround(1 + std::sqrt(1.0 + static_cast<double>(target))));
  return s + (s % 2);
}

/// Closed, outward, star-shaped bumpy sphere of radius ≈ 1 (0.85 to 1.15) at the origin, triangles
/// only. The displacement depends on the direction alone, so it is well defined at the poles.
inline cover::PolygonMesh bumpy_sphere(int segments) {
  const cover::PolygonMesh sphere = cover::make_sphere({0, 0, 0}, 1.0, segments);
  cover::PolygonMesh mesh;
  mesh.vertices.reserve(sphere.vertices.size());
  for (const cover::Vec3& u : sphere.vertices)
    mesh.vertices.push_back((1 + 0.15 * std::sin(6 * u.x) * std::sin(6 * u.y) * std::sin(6 * u.z)) *
                            u);
  for (size_t f = 0; f < sphere.face_count(); ++f) {
    const auto loop = sphere.face(f);
    for (size_t i = 1; i + 1 < loop.size(); ++i) mesh.add_face({loop[0], loop[i], loop[i + 1]});
  }
  return mesh;
}

/// `n` uniform random points in the solid's bounding box.
inline std::vector<cover::Vec3> random_points(const cover::Solid& solid, size_t n, uint64_t seed) {
  const cover::Bbox box = solid.bbox();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(box.min.x, box.max.x), uy(box.min.y, box.max.y),
      uz(box.min.z, box.max.z);
  std::vector<cover::Vec3> points(n);
  for (auto& p : points) p = {ux(rng), uy(rng), uz(rng)};
  return points;
}

/// `n` rays from uniform points on the sphere (center of the box, radius = box diagonal), which
/// encloses the solid, aimed at uniform points in the box (as bench/compare_cgal does).
inline std::vector<cover::Ray> random_rays(const cover::Solid& solid, size_t n, uint64_t seed) {
  const cover::Bbox box = solid.bbox();
  const cover::Vec3 center = 0.5 * (box.min + box.max);
  const double radius = std::sqrt(cover::dot(box.max - box.min, box.max - box.min));
  const std::vector<cover::Vec3> targets = random_points(solid, n, seed);
  std::mt19937_64 rng(seed + 1);
  std::normal_distribution<double> nd;
  std::vector<cover::Ray> rays(n);
  for (size_t i = 0; i < n; ++i) {
    cover::Vec3 u{nd(rng), nd(rng), nd(rng)};
    u = (radius / std::sqrt(cover::dot(u, u))) * u;
    rays[i].origin = center + u;
    rays[i].dir = targets[i] - rays[i].origin;
  }
  return rays;
}

}  // namespace bench
