// Distances to the nearest covering triangle (distance.h).

#include "cover/covering/distance.h"

#include <algorithm>
#include <cmath>

#include "cover/covering/bvh_walk.h"
#include "cover/field/closest.h"
#include "cover/solid/parallel.h"

namespace cover {
namespace {

using V = field::detail::V3<double>;

double distance_to(const Vec3& p, const Bvh::Tri& t) {
  const V q{p.x, p.y, p.z};
  const V c = field::detail::closest_on_triangle(q, V{t.a.x, t.a.y, t.a.z}, V{t.b.x, t.b.y, t.b.z},
                                                 V{t.c.x, t.c.y, t.c.z});
  const V d = q - c;
  const double r = std::sqrt(field::detail::dot(d, d));
  if (std::isfinite(r)) return r;
  // A collinear triangle (zero area): its nearest point is on one of its edges.
  double best = INFINITY;
  const V v[3] = {{t.a.x, t.a.y, t.a.z}, {t.b.x, t.b.y, t.b.z}, {t.c.x, t.c.y, t.c.z}};
  for (int e = 0; e < 3; ++e) {
    const V s = q - field::detail::closest_on_segment(q, v[e], v[(e + 1) % 3]);
    best = std::min(best, std::sqrt(field::detail::dot(s, s)));
  }
  return best;
}

/// The squared distance from p to the node's (float) box: a lower bound of the exact one.
double box_distance2(const Vec3& p, const Bvh::Node& n) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double g =
        std::max({static_cast<double>(n.lo[k]) - p[k], p[k] - static_cast<double>(n.hi[k]), 0.0});
    d2 += g * g;
  }
  return d2;
}

}  // namespace

std::vector<double> nearest_distances(const Bvh& bvh, std::span<const Vec3> points) {
  std::vector<double> out(points.size(), INFINITY);
  parallel_for(points.size(), 256, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const Vec3& p = points[i];
      double best = INFINITY;
      walk(
          bvh, [&](const Bvh::Node& n) { return box_distance2(p, n) <= best * best; },
          [&](const Bvh::Tri& t, uint32_t) { best = std::min(best, distance_to(p, t)); });
      out[i] = best;
    }
  });
  return out;
}

}  // namespace cover
