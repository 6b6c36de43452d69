#pragma once
// Shared voxel-grid generators for the raster tests (seeded, reproducible).

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <string>

#include "cover/voxel/voxel_grid.h"
#include "helpers.h"

namespace cover::test {

/// Debian's interpreter (the one with numpy, zarr and pyopenvdb), else the python3 on PATH.
inline std::string python() {
  return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

/// Runs tests/io/read_voxels.py on `file` (an independent reader: numpy, VTK, zarr,
/// pyopenvdb); returns its JSON summary and the decoded [x][y][z] bytes.
inline nlohmann::json python_read(const std::filesystem::path& file, std::string& bytes) {
  const std::filesystem::path dump = file.string() + ".dump";
  const std::filesystem::path out = file.string() + ".out";
  const std::string cmd = python() + " '" + (source_dir() / "tests/io/read_voxels.py").string() +
                          "' '" + file.string() + "' '" + dump.string() + "' >'" + out.string() +
                          "'";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(status, 0) << cmd;
  if (status != 0) return {};
  bytes = read_file(dump);
  const nlohmann::json summary = nlohmann::json::parse(read_file(out));
  std::filesystem::remove(dump);
  std::filesystem::remove(out);
  return summary;
}

/// An all-empty N³ grid over `bounds` (off the origin by default, so bounds are exercised).
inline VoxelGrid empty_grid(int n, VoxelBounds bounds = {{-1.25, 0.5, 3.0}, 2.5}) {
  const VoxelLattice lattice = cubic_lattice(bounds, n);
  return empty_voxel_grid(lattice, whole_box(lattice));
}

/// Each voxel set with probability `density`.
inline VoxelGrid random_grid(int n, double density, uint64_t seed) {
  VoxelGrid grid = empty_grid(n);
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution coin(density);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        if (coin(rng)) grid.set(i, j, k);
  return grid;
}

/// An off-centre ball in the unit cube, so that the x, y and z axes are not interchangeable.
inline VoxelGrid sphere_grid(int n) {
  VoxelGrid grid = empty_grid(n, {{0, 0, 0}, 1});
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vec3 d = grid.voxel_centre(i, j, k) - Vec3{0.45, 0.55, 0.6};
        if (dot(d, d) < 0.35 * 0.35) grid.set(i, j, k);
      }
  return grid;
}

}  // namespace cover::test
