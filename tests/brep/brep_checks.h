#pragma once
// Invariant checks shared by the brep tests: a clipped half must be a closed, consistently
// oriented 2-manifold (kernel validity), outward (positive volume) and free of self-intersections
// near the cut. Pinched vertices (distinct vertices at equal coordinates, one per fan) are
// counted separately and welded for the self-intersection test.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "cover/brep/clip.h"
#include "cover/brep/halfedge.h"
#include "cover/mesh/validate.h"
#include "cover/solid/measure.h"

namespace cover::test {

struct HalfCheck {
  brep::BrepReport report;
  double volume = 0;
  int64_t pinched = 0;  ///< extra vertices sharing coordinates with another vertex
  bool self_intersecting = false;
};

/// Validity, volume and (restricted to faces within `slab` of the plane; all faces when slab < 0)
/// self-intersection of one half.
inline HalfCheck check_half(const PolygonMesh& half, const brep::Plane& plane, double slab) {
  HalfCheck c;
  c.report = brep::validate(brep::HalfedgeMesh::from_polygon_mesh(half));
  c.volume = signed_volume(half);
  std::vector<uint32_t> order(half.vertices.size()), weld(half.vertices.size());
  for (uint32_t v = 0; v < order.size(); ++v) order[v] = v;
  auto key = [&](uint32_t v) {
    const Vec3& p = half.vertices[v];
    return std::array<double, 3>{p.x, p.y, p.z};
  };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
  for (size_t i = 0; i < order.size(); ++i) {
    const bool same = i > 0 && key(order[i]) == key(order[i - 1]);
    weld[order[i]] = same ? weld[order[i - 1]] : order[i];
    c.pinched += same;
  }
  PolygonMesh near;
  near.vertices = half.vertices;
  std::vector<uint32_t> loop;
  for (size_t f = 0; f < half.face_count(); ++f) {
    bool keep = slab < 0;
    loop.clear();
    for (uint32_t v : half.face(f)) {
      loop.push_back(weld[v]);
      const Vec3& p = half.vertices[v];
      keep = keep || std::abs(dot(plane.normal, p) - plane.offset) <= slab;
    }
    if (keep) near.add_face(loop);
  }
  c.self_intersecting = near.face_count() > 0 && self_intersects(near);
  return c;
}

/// Expects both halves valid and the volumes to add up to `volume` (relative `tolerance`).
inline void expect_valid_clip(const brep::ClipResult& r, const brep::Plane& plane, double volume,
                              double slab, const std::string& what, double tolerance = 1e-9) {
  for (const brep::ClipHalf* h : {&r.above, &r.below}) {
    const char* name = h == &r.above ? "above" : "below";
    const HalfCheck c = check_half(h->mesh, plane, slab);
    EXPECT_TRUE(c.report.consistent) << what << " " << name;
    EXPECT_TRUE(c.report.closed) << what << " " << name;
    EXPECT_TRUE(c.report.manifold) << what << " " << name;
    EXPECT_FALSE(c.self_intersecting) << what << " " << name;
    if (h->mesh.face_count() > 0) {
      EXPECT_GT(c.volume, 0) << what << " " << name;
    }
  }
  EXPECT_EQ(r.forced_ears, 0) << what;
  const double sum = signed_volume(r.above.mesh) + signed_volume(r.below.mesh);
  EXPECT_NEAR(sum, volume, tolerance * std::abs(volume)) << what;
}

}  // namespace cover::test
