// Voxel bounds (solid/voxel_bounds.h): the default cube around a box.
#include "cover/solid/voxel_bounds.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "cover/solid/errors.h"

namespace cover {
namespace {

TEST(VoxelBounds, DefaultBoundsCentredCubeWithMargin) {
  Bbox box;
  box.add(Vec3{1, -2, 3});
  box.add(Vec3{4, 0.5, 3.5});  // extents 3, 2.5, 0.5
  for (int n : {3, 10, 64, 255, 2048}) {
    const VoxelBounds b = default_voxel_bounds(box, n);
    EXPECT_NEAR(b.size, 3.0 * n / (n - 2), 1e-12) << n;
    const double h = b.size / n;
    for (int axis = 0; axis < 3; ++axis) {
      const double lo = b.min[axis], hi = b.min[axis] + b.size;
      EXPECT_LE(lo, box.min[axis]) << n;
      EXPECT_GE(hi, box.max[axis]) << n;
      EXPECT_NEAR(lo + hi, box.min[axis] + box.max[axis], 1e-12) << n;  // centred
    }
    // The largest extent keeps one voxel of margin on each side.
    EXPECT_NEAR(box.min.x - b.min.x, h, 1e-12) << n;
  }
  // Degenerate boxes still give a positive size.
  Bbox point;
  point.add(Vec3{1, 2, 3});
  const VoxelBounds b = default_voxel_bounds(point, 10);
  EXPECT_GT(b.size, 0);
  EXPECT_NEAR(b.min.x + b.size / 2, 1, 1e-12);
  EXPECT_GT(default_voxel_bounds(Bbox{}, 10).size, 0);
  EXPECT_THROW(default_voxel_bounds(box, 2), PreconditionError);
}

}  // namespace
}  // namespace cover
