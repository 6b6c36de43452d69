// The brick API of the facade (model/model.h voxel_lattice, voxelize_brick, classify_brick;
// docs/scale-out.md#bricks): every brick equals the same region of the whole grid, brick
// classification equals Model::classify of the centres and agrees with the voxels away from the
// boundary, the tie rule holds in bricks, and non-cubic lattices follow their documented rule.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cover/model/model.h"
#include "helpers.h"

namespace cover {
namespace {

/// A scene with several leaves (union, difference, intersection).
Model scene() {
  const Model a = box({-1, -0.8, -0.6}, {1, 0.9, 0.7});
  const Model s = sphere({0.3, 0.1, 0.2}, 0.75, 24);
  const Model c = cylinder({-1.2, 0, 0}, {1.2, 0.1, 0.05}, 0.3, 20);
  const Model b = box({-0.4, -0.3, -1.0}, {0.2, 0.5, 1.0});
  return ((a - s) | (s & b)) - c;
}

/// Bit of global voxel (i, j, k) in a whole grid.
bool whole_bit(const VoxelGrid& whole, int i, int j, int k) { return whole.get(i, j, k); }

/// Every voxel of `brick` equals the whole grid's voxel at the same global index.
void expect_brick_equals_whole(const VoxelGrid& brick, const VoxelGrid& whole, const IndexBox& box,
                               const std::string& what) {
  ASSERT_TRUE(brick.box == box) << what;
  ASSERT_EQ(brick.bits.size(), brick.word_count()) << what;
  long mismatches = 0;
  for (int i = 0; i < brick.nx(); ++i)
    for (int j = 0; j < brick.ny(); ++j)
      for (int k = 0; k < brick.nz(); ++k)
        mismatches +=
            brick.get(i, j, k) != whole_bit(whole, box.lo[0] + i, box.lo[1] + j, box.lo[2] + k);
  EXPECT_EQ(mismatches, 0) << what;
  EXPECT_EQ(brick.voxel_centre(0, 0, 0), whole.voxel_centre(box.lo[0], box.lo[1], box.lo[2]))
      << what;
}

/// Seeded bricks: 1-voxel ones, thin slabs, ragged edges, the whole lattice, a random mix.
std::vector<IndexBox> bricks(const std::array<int, 3>& dims, uint64_t seed, int random_count) {
  std::vector<IndexBox> out;
  out.push_back({{0, 0, 0}, dims});
  out.push_back({{0, 0, 0}, {1, 1, 1}});
  out.push_back({{dims[0] - 1, dims[1] - 1, dims[2] - 1}, dims});
  out.push_back({{dims[0] / 2, 0, 0}, {dims[0] / 2 + 1, dims[1], dims[2]}});
  out.push_back({{0, dims[1] / 3, dims[2] / 2}, {dims[0], dims[1] / 3 + 1, dims[2]}});
  // Chunk-like tiling with a ragged edge (chunk 7).
  for (int i = 0; i < dims[0]; i += 7)
    for (int k = 0; k < dims[2]; k += 7)
      out.push_back(
          {{i, 7, k}, {std::min(dims[0], i + 7), std::min(dims[1], 14), std::min(dims[2], k + 7)}});
  std::mt19937_64 rng(seed);
  for (int r = 0; r < random_count; ++r) {
    IndexBox b;
    for (int a = 0; a < 3; ++a) {
      std::uniform_int_distribution<int> pick(0, dims[a] - 1);
      int lo = pick(rng), hi = pick(rng);
      if (lo > hi) std::swap(lo, hi);
      b.lo[a] = lo;
      b.hi[a] = hi + 1;
    }
    out.push_back(b);
  }
  return out;
}

TEST(Bricks, EveryBrickEqualsTheWholeGridOnASceneAndARealMesh) {
  struct Case {
    std::string name;
    Model model;
    VoxelizeOptions options;
  };
  std::vector<Case> cases;
  {
    VoxelizeOptions o;
    o.dims = {23, 17, 29};  // non-cubic, ragged against chunk 7
    cases.push_back({"scene dims", scene(), o});
    VoxelizeOptions c;
    c.resolution = 40;
    cases.push_back({"scene cubic", scene(), c});
    VoxelizeOptions m;
    m.resolution = 48;
    cases.push_back({"bunny00", load(test::cgal_mesh("bunny00.off")), m});
    VoxelizeOptions far;  // a lattice much larger than the object: bricks outside it
    far.resolution = 30;
    far.bounds = VoxelBounds{{-3, -3, -3}, 6};
    cases.push_back({"scene far", scene(), far});
  }
  for (const Case& c : cases) {
    const VoxelLattice lattice = c.model.voxel_lattice(c.options);
    const VoxelGrid whole = c.model.voxelize(c.options);
    ASSERT_TRUE(whole.whole());
    EXPECT_GT(whole.count(), 0u) << c.name;
    VoxelGrid brick;  // reused across bricks, as a worker does
    for (const IndexBox& box : bricks(lattice.dims, 7, 40)) {
      c.model.voxelize_brick(lattice, box, brick);
      expect_brick_equals_whole(
          brick, whole, box,
          c.name + " brick [" + std::to_string(box.lo[0]) + "," + std::to_string(box.lo[1]) + "," +
              std::to_string(box.lo[2]) + ")-[" + std::to_string(box.hi[0]) + "," +
              std::to_string(box.hi[1]) + "," + std::to_string(box.hi[2]) + ")");
    }
    // The raster function without a face list (every face scanned) gives the same bricks.
    const IndexBox some{{1, 2, 3},
                        {lattice.dims[0] - 1, lattice.dims[1] / 2 + 1, lattice.dims[2] - 2}};
    VoxelGrid scanned;
    voxelize_brick(c.model.solid(), lattice, some, nullptr, scanned);
    expect_brick_equals_whole(scanned, whole, some, c.name + " scanned");
  }
}

TEST(Bricks, ClassifyBrickEqualsClassifyAndAgreesWithTheVoxels) {
  const Model m = scene();
  VoxelizeOptions o;
  o.dims = {19, 26, 15};
  const VoxelLattice lattice = m.voxel_lattice(o);
  for (const IndexBox& box : bricks(lattice.dims, 11, 6)) {
    const std::vector<PointClass> cls = m.classify_brick(lattice, box);
    const VoxelGrid g = m.voxelize_brick(lattice, box);
    std::vector<Vec3> centres;
    for (int i = box.lo[0]; i < box.hi[0]; ++i)
      for (int j = box.lo[1]; j < box.hi[1]; ++j)
        for (int k = box.lo[2]; k < box.hi[2]; ++k) centres.push_back(lattice.centre(i, j, k));
    ASSERT_EQ(cls, m.classify(centres));
    size_t idx = 0;
    long mismatches = 0;
    for (int i = 0; i < g.nx(); ++i)
      for (int j = 0; j < g.ny(); ++j)
        for (int k = 0; k < g.nz(); ++k, ++idx)
          if (cls[idx] == PointClass::kInside || cls[idx] == PointClass::kOutside)
            mismatches += g.get(i, j, k) != (cls[idx] == PointClass::kInside);
    EXPECT_EQ(mismatches, 0);
  }
}

TEST(Bricks, TieRuleOnBoxFacesInEveryBrick) {
  // Centres at integers 0..7 (origin −½, spacing 1); the box's faces pass through centres.
  // A centre on the surface takes the membership of c + (ε, ε², ε³): set iff lo ≤ c < hi.
  const Vec3 lo{1, 2, 0}, hi{5, 6, 3};
  const Model m = box(lo, hi) | box({5, 2, 0}, {7, 4, 3});  // a shared face at x = 5: no seam
  const VoxelLattice lattice{{-0.5, -0.5, -0.5}, 1, {8, 8, 8}, std::nullopt};
  for (const IndexBox& b : bricks(lattice.dims, 3, 20)) {
    const VoxelGrid g = m.voxelize_brick(lattice, b);
    for (int i = 0; i < g.nx(); ++i)
      for (int j = 0; j < g.ny(); ++j)
        for (int k = 0; k < g.nz(); ++k) {
          const Vec3 c = g.voxel_centre(i, j, k);
          const bool in_a =
              lo.x <= c.x && c.x < hi.x && lo.y <= c.y && c.y < hi.y && lo.z <= c.z && c.z < hi.z;
          const bool in_b = 5 <= c.x && c.x < 7 && 2 <= c.y && c.y < 4 && 0 <= c.z && c.z < 3;
          EXPECT_EQ(g.get(i, j, k), in_a || in_b) << c.x << " " << c.y << " " << c.z;
        }
  }
}

TEST(Bricks, NonCubicLatticesFollowTheirRuleAndMatchClassification) {
  const Model m = scene();
  const Bbox box = *m.bounds();
  const double extent[3] = {box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z};
  VoxelizeOptions by_size;
  by_size.voxel_size = 0.07;
  const VoxelLattice a = m.voxel_lattice(by_size);
  EXPECT_EQ(a.origin, box.min);
  EXPECT_EQ(a.spacing, 0.07);
  EXPECT_FALSE(a.cube_size);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(a.dims[k] * a.spacing, extent[k]) << k;
    EXPECT_LT((a.dims[k] - 1) * a.spacing, extent[k]) << k;
  }
  VoxelizeOptions by_dims;
  by_dims.dims = {30, 12, 21};
  const VoxelLattice b = m.voxel_lattice(by_dims);
  EXPECT_EQ(b.origin, box.min);
  EXPECT_EQ(b.dims, by_dims.dims);
  bool tight = false;
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(b.dims[k] * b.spacing, extent[k]) << k;
    tight |= b.dims[k] * std::nextafter(b.spacing, 0.0) < extent[k];
  }
  EXPECT_TRUE(tight) << "the spacing is the smallest that covers the box";
  for (const VoxelizeOptions& o : {by_size, by_dims}) {
    const VoxelGrid g = m.voxelize(o);
    ASSERT_EQ(g.lattice.dims, m.voxel_lattice(o).dims);
    const std::vector<PointClass> cls = m.classify_brick(g.lattice, whole_box(g.lattice));
    size_t idx = 0;
    long mismatches = 0, inside = 0;
    for (int i = 0; i < g.nx(); ++i)
      for (int j = 0; j < g.ny(); ++j)
        for (int k = 0; k < g.nz(); ++k, ++idx)
          if (cls[idx] == PointClass::kInside || cls[idx] == PointClass::kOutside) {
            mismatches += g.get(i, j, k) != (cls[idx] == PointClass::kInside);
            inside += cls[idx] == PointClass::kInside;
          }
    EXPECT_EQ(mismatches, 0);
    EXPECT_GT(inside, 100);
  }
  // The cubic path keeps its spacing: size / N, the cube's size recorded.
  VoxelizeOptions cubic;
  cubic.resolution = 37;
  const VoxelLattice c = m.voxel_lattice(cubic);
  const VoxelBounds vb = m.voxel_bounds(37);
  EXPECT_EQ(c.spacing, vb.size / 37);
  EXPECT_EQ(c.origin, vb.min);
  EXPECT_EQ(*c.cube_size, vb.size);
}

TEST(Bricks, BadBoxesAndOptionsThrowInputError) {
  const Model m = scene();
  VoxelizeOptions o;
  o.resolution = 10;
  const VoxelLattice l = m.voxel_lattice(o);
  EXPECT_THROW(m.voxelize_brick(l, {{0, 0, 0}, {0, 5, 5}}), InputError);
  EXPECT_THROW(m.voxelize_brick(l, {{-1, 0, 0}, {5, 5, 5}}), InputError);
  EXPECT_THROW(m.voxelize_brick(l, {{0, 0, 0}, {5, 5, 11}}), InputError);
  EXPECT_THROW(m.classify_brick(l, {{3, 3, 3}, {2, 5, 5}}), InputError);
  VoxelLattice bad = l;
  bad.spacing = 0;
  EXPECT_THROW(m.voxelize_brick(bad, {{0, 0, 0}, {1, 1, 1}}), InputError);
  VoxelizeOptions both;
  both.voxel_size = 0.1;
  both.dims = {3, 3, 3};
  EXPECT_THROW(m.voxel_lattice(both), InputError);
  VoxelizeOptions tiny;
  tiny.voxel_size = 1e-9;
  EXPECT_THROW(m.voxel_lattice(tiny), InputError);
  VoxelizeOptions big;
  big.resolution = 5000;
  EXPECT_NO_THROW(m.voxel_lattice(big));  // a brick lattice may exceed the in-memory limit
  EXPECT_THROW(m.voxelize(big), InputError);
}

}  // namespace
}  // namespace cover
