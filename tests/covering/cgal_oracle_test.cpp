// Covering kernels against CGAL on real meshes (libcgal-demo): volume vs PMP::volume and
// classification vs Side_of_triangle_mesh. CGAL reads the files itself (independent path).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <random>

#include "cover/covering/classify.h"
#include "cover/covering/volume.h"
#include "cover/io/scene.h"
#include "helpers.h"

namespace cover {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;

class RealMesh : public ::testing::TestWithParam<const char*> {};

Mesh cgal_read(const std::string& name) {
  Mesh m;
  EXPECT_TRUE(CGAL::IO::read_polygon_mesh(test::cgal_mesh(name).string(), m)) << name;
  return m;
}

TEST_P(RealMesh, VolumeEqualsCgalVolume) {
  const Mesh m = cgal_read(GetParam());
  const double expected = CGAL::to_double(CGAL::Polygon_mesh_processing::volume(m));
  const LoadedInput in = load_input(test::cgal_mesh(GetParam()));
  const VolumeResult r = volume(in.solid);
  EXPECT_EQ(r.method, "covering");
  EXPECT_NEAR(r.volume, expected, 1e-12 * std::abs(expected)) << GetParam();
  const double area = CGAL::to_double(CGAL::Polygon_mesh_processing::area(m));
  EXPECT_NEAR(*r.area, area, 1e-12 * area);
}

TEST_P(RealMesh, ClassificationAgreesWithSideOfTriangleMesh) {
  const Mesh m = cgal_read(GetParam());
  CGAL::Side_of_triangle_mesh<Mesh, K> side(m);
  const LoadedInput in = load_input(test::cgal_mesh(GetParam()));
  const Bbox box = in.solid.bbox();
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> ux(box.min.x, box.max.x), uy(box.min.y, box.max.y),
      uz(box.min.z, box.max.z);
  std::vector<Vec3> pts(4000);
  for (Vec3& p : pts) p = {ux(rng), uy(rng), uz(rng)};
  // Mesh vertices are exactly on the surface.
  for (size_t i = 0; i < 12; ++i)
    pts.push_back(in.solid.vertices[i * 7 % in.solid.vertices.size()]);
  const auto classes = classify(in.solid, pts);
  int disagreements = 0, inside = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    const CGAL::Bounded_side s = side(K::Point_3(pts[i].x, pts[i].y, pts[i].z));
    const PointClass c = classes[i];
    if (s == CGAL::ON_BOUNDARY) {
      disagreements += c != PointClass::kFace && c != PointClass::kEdge && c != PointClass::kVertex;
    } else {
      const bool in_cgal = s == CGAL::ON_BOUNDED_SIDE;
      inside += in_cgal;
      disagreements += (c == PointClass::kInside) != in_cgal ||
                       (c != PointClass::kInside && c != PointClass::kOutside);
    }
  }
  EXPECT_EQ(disagreements, 0) << GetParam();
  EXPECT_GT(inside, 0);
}

INSTANTIATE_TEST_SUITE_P(Cgal, RealMesh,
                         ::testing::Values("elephant.off", "knot1.off", "armadillo.off",
                                           "bunny00.off", "fandisk.off"),
                         [](const auto& info) {
                           std::string n = info.param;
                           return n.substr(0, n.find('.'));
                         });

}  // namespace
}  // namespace cover
