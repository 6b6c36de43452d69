// Plane clip on real meshes (libcgal-demo) against CGAL::Polygon_mesh_processing::clip with
// clip_volume = true: 20 seeded random planes through the bounding box and 3 axis planes through
// vertices per model, CGAL's clip on every one of them (in the ASan+UBSan build on 4 of them, for
// runtime). Both halves: closed, 2-manifold, outward, no self-intersection near the cut,
// volumes adding up to the input's and each equal to CGAL's half (CGAL keeps the negative side
// of its plane: below = Plane_3(n, −d), above = Plane_3(−n, d)).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <random>

#include "brep_checks.h"
#include "cover/brep/clip.h"
#include "cover/io/mesh_io.h"
#include "helpers.h"

namespace cover::brep {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

double cgal_half_volume(const Mesh& input, const Vec3& n, double d) {
  Mesh copy = input;
  PMP::clip(copy, K::Plane_3(n.x, n.y, n.z, -d), CGAL::parameters::clip_volume(true));
  return CGAL::to_double(PMP::volume(copy));
}

std::vector<Plane> planes_for(const PolygonMesh& m, uint64_t seed) {
  std::vector<Plane> planes;
  const Bbox b = face_bbox(m);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1, 1), t(0, 1);
  for (int i = 0; i < 20; ++i) {
    const Vec3 n{unit(rng), unit(rng), unit(rng)};
    const Vec3 p{b.min.x + t(rng) * (b.max.x - b.min.x), b.min.y + t(rng) * (b.max.y - b.min.y),
                 b.min.z + t(rng) * (b.max.z - b.min.z)};
    planes.push_back({n, dot(n, p)});
  }
  const Vec3& v = m.vertices[m.vertices.size() / 3];
  planes.push_back({{1, 0, 0}, v.x});
  planes.push_back({{0, 1, 0}, v.y});
  planes.push_back({{0, 0, 1}, v.z});
  return planes;
}

class ClipRealMesh : public ::testing::TestWithParam<const char*> {};

TEST_P(ClipRealMesh, HalvesAreValidAndMatchCgal) {
  const std::string name = GetParam();
  const PolygonMesh m = read_mesh(test::cgal_mesh(name));
  Mesh cgal;
  ASSERT_TRUE(CGAL::IO::read_polygon_mesh(test::cgal_mesh(name).string(), cgal));
  const double volume = signed_volume(m);
  const Bbox b = face_bbox(m);
  const double size = std::max({b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z});
  const std::vector<Plane> planes = planes_for(m, std::hash<std::string>{}(name));
  for (size_t i = 0; i < planes.size(); ++i) {
    const Plane& p = planes[i];
    ClipOptions o;
    o.triangulate_caps = i % 2 == 1;
    const std::string what = name + " plane " + std::to_string(i);
    const ClipResult r = clip(m, p, o);
    const double scale = std::sqrt(dot(p.normal, p.normal)) *
                         (size + std::abs(b.max.x) + std::abs(b.max.y) + std::abs(b.max.z));
    test::expect_valid_clip(r, p, volume, 1e-9 * scale, what);
#ifdef COVER_SANITIZED
    if (i % 8 != 0 && i != 20)
      continue;  // checked build: every eighth random plane, one axis plane
#endif
    const double below = cgal_half_volume(cgal, p.normal, p.offset);
    const double above = cgal_half_volume(cgal, -1.0 * p.normal, -p.offset);
    EXPECT_NEAR(signed_volume(r.below.mesh), below, 1e-9 * volume) << what;
    EXPECT_NEAR(signed_volume(r.above.mesh), above, 1e-9 * volume) << what;
  }
}

INSTANTIATE_TEST_SUITE_P(Libcgal, ClipRealMesh,
                         ::testing::Values("elephant.off", "knot1.off", "armadillo.off",
                                           "bunny00.off", "fandisk.off", "cheese.off"),
                         [](const auto& info) {
                           std::string s = info.param;
                           return s.substr(0, s.find('.'));
                         });

}  // namespace
}  // namespace cover::brep
