// Zarr v2 stores (io/zarr_io.h) and OpenVDB files (io/vdb_io.h), read back by the zarr and
// pyopenvdb Python packages through tests/io/read_voxels.py (not by Cover), equal the .npy of
// the same grid; a Zarr store is atomic: bad targets and failing bricks leave what was there.
#include "cover/io/zarr_io.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "cover/covering/bounds.h"
#include "cover/io/scene.h"
#include "cover/io/vdb_io.h"
#include "cover/io/voxel_io.h"
#include "cover/solid/errors.h"
#include "cover/solid/primitives.h"
#include "cover/voxel/voxelize.h"
#include "helpers.h"
#include "voxel_grids.h"

namespace cover {
namespace {

namespace fs = std::filesystem;

/// Several leaves: a box minus a sphere, with a bar through it.
Solid scene() {
  return unite({subtract({make_leaf(make_box({-1, -0.7, -0.5}, {1, 0.8, 0.6}), "a"),
                          make_leaf(make_sphere({0.2, 0.1, 0.0}, 0.6, 20), "s")}),
                make_leaf(make_box({-1.3, -0.2, -0.1}, {1.3, 0.1, 0.2}), "bar")});
}

/// A non-cubic lattice over the solid's box, and its whole grid.
VoxelLattice lattice_of(const Solid& s, std::array<int, 3> dims) {
  VoxelizeOptions o;
  o.dims = dims;
  const std::optional<Bbox> box = result_bounds(s);
  return voxel_lattice(*box, o);
}

BrickFunction bricks_of(const Solid& s, const VoxelLattice& lattice) {
  return [&s, lattice](const IndexBox& box, VoxelGrid& grid) {
    voxelize_brick(s, lattice, box, nullptr, grid);
  };
}

TEST(Zarr, StoreAndVdbEqualTheNpyOfTheSameGrid) {
  const fs::path dir = test::temp_dir("zarr");
  const Solid s = scene();
  for (const std::array<int, 3> dims :
       {std::array<int, 3>{37, 22, 29}, std::array<int, 3>{16, 16, 16}}) {
    const VoxelLattice lattice = lattice_of(s, dims);
    VoxelGrid whole;
    voxelize_brick(s, lattice, whole_box(lattice), nullptr, whole);
    write_voxels(dir / "whole.npy", whole);
    std::string npy;
    const nlohmann::json expected = test::python_read(dir / "whole.npy", npy);
    ASSERT_EQ(expected["shape"], nlohmann::json(dims));
    ASSERT_GT(expected["sum"].get<long>(), 0);
    for (const int chunk : {1, 7, 16, 64}) {
      if (chunk == 1 && dims[0] > 16) continue;  // one file per voxel: small grids only
      ZarrOptions o;
      o.chunk = chunk;
      o.level = chunk == 7 ? 9 : 1;
      const fs::path store = dir / ("c" + std::to_string(chunk) + ".zarr");
      const ZarrResult r = write_zarr(store, lattice, o, bricks_of(s, lattice));
      EXPECT_EQ(r.occupied, whole.count());
      std::string bytes;
      const nlohmann::json got = test::python_read(store, bytes);
      const int c = std::min(chunk, std::max({dims[0], dims[1], dims[2]}));
      EXPECT_EQ(got["chunks"], nlohmann::json({c, c, c}));
      EXPECT_EQ(got["stored"].get<uint64_t>(), r.chunks_written);
      if (c <= 7) {
        EXPECT_LT(r.chunks_written, r.chunks) << "all-empty chunks are not written";
      }
      EXPECT_TRUE(got["tie_rule"].get<bool>());
      EXPECT_EQ(got["origin"][0].get<double>(), lattice.origin.x);
      EXPECT_EQ(got["spacing"].get<double>(), lattice.spacing);
      EXPECT_TRUE(bytes == npy) << "chunk " << chunk;
      // The grid held in memory writes the same store, chunk file for chunk file.
      const fs::path copy = dir / ("m" + std::to_string(chunk) + ".zarr");
      EXPECT_EQ(write_zarr(copy, whole, o).chunks_written, r.chunks_written);
      for (const auto& entry : fs::directory_iterator(store))
        EXPECT_TRUE(test::read_file(entry.path()) ==
                    test::read_file(copy / entry.path().filename()))
            << entry.path();
    }
    write_vdb(dir / "grid.vdb", whole);
    std::string bytes;
    const nlohmann::json got = test::python_read(dir / "grid.vdb", bytes);
    EXPECT_EQ(got["shape"], nlohmann::json(dims));
    EXPECT_TRUE(bytes == npy);
    VoxelGrid region;
    voxelize_brick(s, lattice, {{0, 0, 0}, {2, 2, 2}}, nullptr, region);
    EXPECT_THROW(write_zarr(dir / "region.zarr", region), PreconditionError);
  }
  fs::remove_all(dir);
}

TEST(Zarr, FullChunksBecomeTilesAndSharedBytesInTheStores) {
  // A box filling most of the lattice: interior 8³ blocks are VDB tiles, interior chunks full.
  const fs::path dir = test::temp_dir("zarr-full");
  const Solid s = make_leaf(make_box({0, 0, 0}, {1, 1, 1}), "box");
  const VoxelLattice lattice{{-0.05, -0.05, -0.05}, 1.1 / 40, {40, 40, 40}, std::nullopt};
  VoxelGrid whole;
  voxelize_brick(s, lattice, whole_box(lattice), nullptr, whole);
  write_vdb(dir / "box.vdb", whole);
  write_voxels(dir / "box.npy", whole);
  ZarrOptions o;
  o.chunk = 8;
  write_zarr(dir / "box.zarr", lattice, o, bricks_of(s, lattice));
  std::string npy, vdb, zarr;
  test::python_read(dir / "box.npy", npy);
  const nlohmann::json v = test::python_read(dir / "box.vdb", vdb);
  test::python_read(dir / "box.zarr", zarr);
  EXPECT_TRUE(vdb == npy);
  EXPECT_TRUE(zarr == npy);
  EXPECT_LT(v["leaves"].get<int>(), 40 * 40 * 40 / 512) << "full leaves pruned to tiles";
  fs::remove_all(dir);
}

TEST(Zarr, BadTargetsAndFailuresLeaveWhatWasThere) {
  const fs::path dir = test::temp_dir("zarr-bad");
  const Solid s = scene();
  const VoxelLattice lattice = lattice_of(s, {12, 10, 9});
  const BrickFunction bricks = bricks_of(s, lattice);
  ZarrOptions o;
  o.chunk = 4;
  // chunk ≤ 0 and a bad level.
  o.chunk = 0;
  EXPECT_THROW(write_zarr(dir / "a.zarr", lattice, o, bricks), InputError);
  o.chunk = 4;
  o.level = 10;
  EXPECT_THROW(write_zarr(dir / "a.zarr", lattice, o, bricks), InputError);
  o.level = 1;
  EXPECT_FALSE(fs::exists(dir / "a.zarr"));
  // A regular file, a non-empty folder that is not a store: refused, untouched.
  test::write_file(dir / "file.zarr", "keep me");
  EXPECT_THROW(write_zarr(dir / "file.zarr", lattice, o, bricks), InputError);
  EXPECT_EQ(test::read_file(dir / "file.zarr"), "keep me");
  fs::create_directory(dir / "folder.zarr");
  test::write_file(dir / "folder.zarr" / "notes.txt", "mine");
  EXPECT_THROW(write_zarr(dir / "folder.zarr", lattice, o, bricks), InputError);
  EXPECT_EQ(test::read_file(dir / "folder.zarr" / "notes.txt"), "mine");
  // An unwritable place (a missing folder).
  EXPECT_THROW(write_zarr(dir / "missing" / "a.zarr", lattice, o, bricks), InputError);
  // An existing store is replaced as a whole (a chunk of an earlier, larger store does not
  // survive); a failing brick leaves it as it was.
  write_zarr(dir / "s.zarr", lattice, o, bricks);
  test::write_file(dir / "s.zarr" / "99.99.99", "old");
  write_zarr(dir / "s.zarr", lattice, o, bricks);
  EXPECT_FALSE(fs::exists(dir / "s.zarr" / "99.99.99"));
  test::write_file(dir / "s.zarr" / "99.99.99", "old");
  int calls = 0;
  EXPECT_THROW(write_zarr(dir / "s.zarr", lattice, o,
                          [&](const IndexBox& box, VoxelGrid& grid) {
                            if (++calls == 3) throw std::runtime_error("brick failed");
                            bricks(box, grid);
                          }),
               std::runtime_error);
  EXPECT_EQ(test::read_file(dir / "s.zarr" / "99.99.99"), "old");
  // A store holding a file Cover does not write is not Cover's own: refused, kept.
  test::write_file(dir / "s.zarr" / "notes.txt", "mine");
  EXPECT_THROW(write_zarr(dir / "s.zarr", lattice, o, bricks), InputError);
  EXPECT_EQ(test::read_file(dir / "s.zarr" / "notes.txt"), "mine");
  fs::remove(dir / "s.zarr" / "notes.txt");
  // Through a link: the folder it names gets the store, the link stays.
  fs::create_directory_symlink("s.zarr", dir / "link.zarr");
  write_zarr(dir / "link.zarr", lattice, o, bricks);
  EXPECT_TRUE(fs::is_symlink(dir / "link.zarr"));
  EXPECT_FALSE(fs::exists(dir / "s.zarr" / "99.99.99"));
  EXPECT_TRUE(fs::is_regular_file(dir / "s.zarr" / ".zarray"));
  fs::remove(dir / "link.zarr");
  // Nothing but the targets is left in the folder (no temporary or old stores).
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"file.zarr", "folder.zarr", "s.zarr"}));
  // A memory budget below one brick is refused before anything is written.
  o.max_bytes = 1000;
  EXPECT_THROW(write_zarr(dir / "m.zarr", lattice, o, bricks), InputError);
  EXPECT_FALSE(fs::exists(dir / "m.zarr"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cover
