// Presence-buffer voxelization (voxel/voxelize.h) against the independent point classifier on
// every voxel centre, the documented tie rule, and convergence to the exact volume.
#include "cover/voxel/voxelize.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cover/covering/classify.h"
#include "cover/covering/volume.h"
#include "cover/io/scene.h"
#include "cover/solid/parallel.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "helpers.h"

namespace cover {
namespace {

struct Comparison {
  long mismatches = 0, boundary = 0, occupied = 0;
};

/// Classifies every voxel centre with classify() and compares; centres on a surface (face,
/// edge, vertex) are counted separately (they follow the tie rule, checked elsewhere).
Comparison compare(const Solid& s, const VoxelGrid& g) {
  std::vector<Vec3> centres;
  centres.reserve(static_cast<size_t>(g.nx()) * g.nx() * g.nx());
  for (int i = 0; i < g.nx(); ++i)
    for (int j = 0; j < g.nx(); ++j)
      for (int k = 0; k < g.nx(); ++k) centres.push_back(g.voxel_centre(i, j, k));
  const std::vector<PointClass> cls = classify(s, centres);
  Comparison c;
  size_t idx = 0;
  for (int i = 0; i < g.nx(); ++i)
    for (int j = 0; j < g.nx(); ++j)
      for (int k = 0; k < g.nx(); ++k, ++idx) {
        const bool v = g.get(i, j, k);
        c.occupied += v;
        if (cls[idx] != PointClass::kInside && cls[idx] != PointClass::kOutside) {
          ++c.boundary;
          continue;
        }
        c.mismatches += v != (cls[idx] == PointClass::kInside);
      }
  return c;
}

Solid mesh(const std::string& name) { return load_input(test::cgal_mesh(name)).solid; }

TEST(Voxelize, RealMeshesMatchPointClassification) {
  for (const char* name : {"elephant.off", "knot1.off", "armadillo.off", "bunny00.off"})
    for (int n : {64, 128}) {
      const Solid s = mesh(name);
      VoxelizeOptions o;
      o.resolution = n;
      const VoxelGrid g = voxelize(s, o);
      const Comparison c = compare(s, g);
      EXPECT_EQ(c.mismatches, 0) << name << " " << n;
      EXPECT_GT(c.occupied, n * n) << name;
      EXPECT_EQ(g.count(), static_cast<uint64_t>(c.occupied));
    }
}

TEST(Voxelize, NestedCsgScenesMatchPointClassification) {
  const std::string bunny = test::cgal_mesh("bunny00.off").string();
  const std::vector<std::string> scenes = {
      R"({"union": [{"difference": [{"mesh": ")" + bunny + R"("},
          {"sphere": {"center": [0.1, 0.1, 0.1], "radius": 0.3}}]},
          {"box": {"min": [0.2, -0.6, -0.2], "max": [0.7, 0.0, 0.3]}}]})",
      R"({"intersection": [{"mesh": ")" + bunny +
          R"(", "transform": {"rotate": {"axis": [0,0,1], "degrees": 30}}},
          {"complement": {"cylinder": {"base": [0, 0, -1], "top": [0, 0, 1], "radius": 0.2}}},
          {"mesh": ")" +
          bunny + R"(", "transform": {"scale": 0.9, "translate": [0.15, 0, 0]}}]})"};
  for (const std::string& text : scenes)
    for (int n : {64, 128}) {
      const Solid s = parse_scene(text, "scene.json").solid;
      VoxelizeOptions o;
      o.resolution = n;
      const VoxelGrid g = voxelize(s, o);
      const Comparison c = compare(s, g);
      EXPECT_EQ(c.mismatches, 0) << n;
      EXPECT_GT(c.occupied, n * n);
    }
}

TEST(Voxelize, CentresOnTheBoundaryFollowTheTieRule) {
  // Bounds [0, 8]³ with N = 8: centres at 0.5, 1.5, ...; the box's faces pass through centres.
  // Rule: a centre c on the surface takes the membership of c + (ε, ε², ε³), so for a box
  // [lo, hi] a centre is set iff lo <= c < hi on every axis.
  const Vec3 lo{1.5, 2.5, 0.5}, hi{5.5, 6.5, 3.5};
  const Solid s = make_leaf(make_box(lo, hi), "box");
  VoxelizeOptions o;
  o.resolution = 8;
  o.bounds = VoxelBounds{{0, 0, 0}, 8};
  const VoxelGrid g = voxelize(s, o);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k) {
        const Vec3 c = g.voxel_centre(i, j, k);
        const bool expected =
            lo.x <= c.x && c.x < hi.x && lo.y <= c.y && c.y < hi.y && lo.z <= c.z && c.z < hi.z;
        EXPECT_EQ(g.get(i, j, k), expected) << i << " " << j << " " << k;
      }
  // Union of two boxes sharing the face x = 3.5 (through centres): no seam.
  const Solid u = unite({make_leaf(make_box({0.5, 0.5, 0.5}, {3.5, 7.5, 7.5}), "a"),
                         make_leaf(make_box({3.5, 0.5, 0.5}, {6.5, 7.5, 7.5}), "b")});
  const VoxelGrid gu = voxelize(u, o);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(gu.get(i, 3, 3), i < 6) << i;
}

TEST(Voxelize, VoxelVolumeConvergesToTheExactVolume) {
  // Only voxels cut by the surface can be wrong, so |count·h³ − V| <= (cut voxels)·h³, and the
  // cut voxels number at most about 3·area/h² (a surface piece of area A meets ≲ 3A/h² cubes):
  // the error is O(h) and must shrink with the resolution.
  const Solid s = mesh("knot1.off");
  const VolumeResult exact = volume(s);
  const double area = *exact.area;
  std::vector<double> errors;
  for (int n : {16, 32, 64, 128, 256}) {
    VoxelizeOptions o;
    o.resolution = n;
    const VoxelGrid g = voxelize(s, o);
    const double h = g.voxel_size();
    const double error = std::abs(static_cast<double>(g.count()) * h * h * h - exact.volume);
    EXPECT_LE(error, 3 * area * h) << n;
    errors.push_back(error / exact.volume);
  }
  EXPECT_LT(errors.back(), errors.front() / 8);
  EXPECT_LT(errors.back(), 0.005);
}

TEST(Voxelize, SameGridWithOneAndTwoThreadsAndComplement) {
  const Solid s = subtract({mesh("elephant.off"), make_leaf(make_sphere({0, 0, 0}, 0.2, 24), "s")});
  VoxelizeOptions o;
  o.resolution = 96;
  VoxelGrid a, b;
  {
    ThreadLimit limit(1);
    a = voxelize(s, o);
  }
  {
    ThreadLimit limit(2);
    b = voxelize(s, o);
  }
  EXPECT_EQ(a.bits, b.bits);
  // The complement fills exactly the other voxels of the same grid.
  o.bounds = VoxelBounds{a.lattice.origin, *a.lattice.cube_size};
  const VoxelGrid c = voxelize(complement(s), o);
  EXPECT_EQ(c.count() + a.count(), static_cast<uint64_t>(96) * 96 * 96);
}

}  // namespace
}  // namespace cover
