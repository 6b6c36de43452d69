// Voxel export (io/voxel_io.h) and grid helpers (voxel/voxel_grid.h). Every written file is
// read back by a reader that shares no code with the writer: numpy (.npy), Python's xml + struct
// (.vti) and numpy + json (.raw) through tests/io/read_voxels.py, a binvox decoder written
// here from the binvox 1 specification, and nlohmann::json for the .raw sidecar. Each check
// compares every voxel against VoxelGrid::get.

#include "cover/io/voxel_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "cover/solid/errors.h"
#include "cover/voxel/voxel_grid.h"
#include "helpers.h"
#include "voxel_grids.h"

namespace cover {
namespace {

using test::empty_grid;
using test::random_grid;
using test::sphere_grid;

namespace fs = std::filesystem;

VoxelGrid full_grid(int n) {
  VoxelGrid grid = empty_grid(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) grid.set(i, j, k);
  return grid;
}

/// Voxel (x, y, z) set iff x + 2y + 3z is odd: every binvox run has length 1 or so.
VoxelGrid checker_grid(int n) {
  VoxelGrid grid = empty_grid(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        if ((i + 2 * j + 3 * k) % 2 == 1) grid.set(i, j, k);
  return grid;
}

/// Test grids: name and grid, covering one and several words per column, partial words, and
/// binvox runs that cross x-slabs (full) or never exceed a few voxels (checker).
std::vector<std::pair<std::string, VoxelGrid>> grids() {
  std::vector<std::pair<std::string, VoxelGrid>> all;
  for (int n : {5, 17, 64, 65, 130}) {
    all.emplace_back("random" + std::to_string(n), random_grid(n, 0.3, 1234 + n));
    all.emplace_back("sphere" + std::to_string(n), sphere_grid(n));
  }
  all.emplace_back("full17", full_grid(17));
  all.emplace_back("empty9", empty_grid(9));
  all.emplace_back("checker33", checker_grid(33));
  all.emplace_back("single1", full_grid(1));
  return all;
}

size_t xyz_index(const VoxelGrid& grid, int x, int y, int z) {
  const size_t n = static_cast<size_t>(grid.nx());
  return (static_cast<size_t>(x) * n + static_cast<size_t>(y)) * n + static_cast<size_t>(z);
}

/// Compares N³ bytes in [x][y][z] order with the grid, voxel by voxel (reports the first few).
void expect_xyz_bytes(const VoxelGrid& grid, const std::string& bytes, const std::string& what) {
  const size_t n = static_cast<size_t>(grid.nx());
  ASSERT_EQ(bytes.size(), n * n * n) << what;
  int mismatches = 0;
  for (int x = 0; x < grid.nx(); ++x)
    for (int y = 0; y < grid.nx(); ++y)
      for (int z = 0; z < grid.nx(); ++z) {
        const auto value = static_cast<unsigned char>(bytes[xyz_index(grid, x, y, z)]);
        const unsigned expected = grid.get(x, y, z) ? 1 : 0;
        if (value != expected && ++mismatches <= 5)
          ADD_FAILURE() << what << ": voxel (" << x << ", " << y << ", " << z << ") is "
                        << int(value) << ", expected " << expected;
      }
  EXPECT_EQ(mismatches, 0) << what;
}

/// Header fields and decoded voxels (index x·N·N + z·N + y) of a binvox file.
struct Binvox {
  int n = 0;
  Vec3 translate;
  double scale = 0;
  std::vector<uint8_t> voxels;
};

/// A binvox 1 reader written from the format specification: text header lines "#binvox 1",
/// "dim D D D", "translate tx ty tz", "scale s", "data", then (value, count) byte pairs.
Binvox read_binvox(const fs::path& file) {
  const std::string data = test::read_file(file);
  size_t pos = 0;
  auto line = [&]() {
    const size_t end = data.find('\n', pos);
    if (end == std::string::npos) throw std::runtime_error("binvox: unterminated header");
    std::string text = data.substr(pos, end - pos);
    pos = end + 1;
    return text;
  };
  Binvox out;
  if (line() != "#binvox 1") throw std::runtime_error("binvox: bad magic");
  int dims[3] = {0, 0, 0};
  if (std::sscanf(line().c_str(), "dim %d %d %d", &dims[0], &dims[1], &dims[2]) != 3)
    throw std::runtime_error("binvox: bad dim");
  if (dims[0] != dims[1] || dims[1] != dims[2] || dims[0] <= 0)
    throw std::runtime_error("binvox: not a cube");
  out.n = dims[0];
  const std::string translate = line();
  char* end = nullptr;
  if (translate.rfind("translate ", 0) != 0) throw std::runtime_error("binvox: no translate");
  out.translate.x = std::strtod(translate.c_str() + 10, &end);
  out.translate.y = std::strtod(end, &end);
  out.translate.z = std::strtod(end, &end);
  if (*end != '\0') throw std::runtime_error("binvox: bad translate");
  const std::string scale = line();
  if (scale.rfind("scale ", 0) != 0) throw std::runtime_error("binvox: no scale");
  out.scale = std::strtod(scale.c_str() + 6, &end);
  if (*end != '\0') throw std::runtime_error("binvox: bad scale");
  if (line() != "data") throw std::runtime_error("binvox: no data line");
  const size_t total = static_cast<size_t>(out.n) * out.n * out.n;
  out.voxels.reserve(total);
  while (pos < data.size()) {
    if (pos + 2 > data.size()) throw std::runtime_error("binvox: odd trailing byte");
    const auto value = static_cast<uint8_t>(data[pos]);
    const auto count = static_cast<uint8_t>(data[pos + 1]);
    pos += 2;
    if (value > 1 || count == 0) throw std::runtime_error("binvox: bad run");
    if (out.voxels.size() + count > total) throw std::runtime_error("binvox: too many voxels");
    out.voxels.insert(out.voxels.end(), count, value);
  }
  if (out.voxels.size() != total) throw std::runtime_error("binvox: too few voxels");
  return out;
}

TEST(VoxelIo, NpyReadByNumpy) {
  const fs::path dir = test::temp_dir("voxel-npy");
  for (const auto& [name, grid] : grids()) {
    const fs::path file = dir / (name + ".npy");
    write_voxels(file, grid);
    std::string bytes;
    const nlohmann::json summary = test::python_read(file, bytes);
    ASSERT_FALSE(summary.is_null()) << name;
    EXPECT_EQ(summary["shape"], nlohmann::json({grid.nx(), grid.nx(), grid.nx()})) << name;
    EXPECT_EQ(summary["sum"].get<uint64_t>(), grid.count()) << name;
    expect_xyz_bytes(grid, bytes, name + ".npy");
  }
  fs::remove_all(dir);
}

TEST(VoxelIo, VtiReadByPythonXml) {
  const fs::path dir = test::temp_dir("voxel-vti");
  for (const auto& [name, grid] : grids()) {
    const fs::path file = dir / (name + ".vti");
    write_voxels(file, grid);
    std::string bytes;
    const nlohmann::json summary = test::python_read(file, bytes);
    ASSERT_FALSE(summary.is_null()) << name;
    EXPECT_EQ(summary["shape"], nlohmann::json({grid.nx(), grid.nx(), grid.nx()})) << name;
    EXPECT_EQ(summary["sum"].get<uint64_t>(), grid.count()) << name;
    // Shortest round-trip decimals: Python reads back exactly the doubles of the grid.
    EXPECT_EQ(summary["origin"][0].get<double>(), grid.lattice.origin.x) << name;
    EXPECT_EQ(summary["origin"][1].get<double>(), grid.lattice.origin.y) << name;
    EXPECT_EQ(summary["origin"][2].get<double>(), grid.lattice.origin.z) << name;
    EXPECT_EQ(summary["spacing"].get<double>(), grid.voxel_size()) << name;
    expect_xyz_bytes(grid, bytes, name + ".vti");
  }
  fs::remove_all(dir);
}

TEST(VoxelIo, RawAndSidecar) {
  const fs::path dir = test::temp_dir("voxel-raw");
  for (const auto& [name, grid] : grids()) {
    const fs::path file = dir / (name + ".raw");
    write_voxels(file, grid);
    expect_xyz_bytes(grid, test::read_file(file), name + ".raw");
    const fs::path sidecar = dir / (name + ".raw.json");
    ASSERT_TRUE(fs::exists(sidecar)) << name;
    const nlohmann::json meta = nlohmann::json::parse(test::read_file(sidecar));
    EXPECT_EQ(meta["dims"], nlohmann::json({grid.nx(), grid.nx(), grid.nx()})) << name;
    EXPECT_EQ(meta["order"], "xyz (z fastest)") << name;
    EXPECT_EQ(meta["dtype"], "uint8") << name;
    EXPECT_EQ(meta["bounds"]["min"][0].get<double>(), grid.lattice.origin.x) << name;
    EXPECT_EQ(meta["bounds"]["min"][1].get<double>(), grid.lattice.origin.y) << name;
    EXPECT_EQ(meta["bounds"]["min"][2].get<double>(), grid.lattice.origin.z) << name;
    EXPECT_EQ(meta["bounds"]["size"].get<double>(), *grid.lattice.cube_size) << name;
    EXPECT_EQ(meta["voxel_size"].get<double>(), grid.voxel_size()) << name;
    // And through numpy.fromfile + the sidecar's dims.
    std::string bytes;
    const nlohmann::json summary = test::python_read(file, bytes);
    ASSERT_FALSE(summary.is_null()) << name;
    EXPECT_EQ(summary["sum"].get<uint64_t>(), grid.count()) << name;
    expect_xyz_bytes(grid, bytes, name + ".raw via numpy");
  }
  fs::remove_all(dir);
}

TEST(VoxelIo, BinvoxDecodedFromSpecification) {
  const fs::path dir = test::temp_dir("voxel-binvox");
  for (const auto& [name, grid] : grids()) {
    const fs::path file = dir / (name + ".binvox");
    write_voxels(file, grid);
    Binvox binvox;
    ASSERT_NO_THROW(binvox = read_binvox(file)) << name;
    ASSERT_EQ(binvox.n, grid.nx()) << name;
    EXPECT_EQ(binvox.translate, grid.lattice.origin) << name;
    EXPECT_EQ(binvox.scale, *grid.lattice.cube_size) << name;
    const size_t n = static_cast<size_t>(grid.nx());
    int mismatches = 0;
    for (int x = 0; x < grid.nx(); ++x)
      for (int z = 0; z < grid.nx(); ++z)
        for (int y = 0; y < grid.nx(); ++y) {
          const size_t index = (static_cast<size_t>(x) * n + z) * n + y;
          if (binvox.voxels[index] != (grid.get(x, y, z) ? 1 : 0) && ++mismatches <= 5)
            ADD_FAILURE() << name << ".binvox: voxel (" << x << ", " << y << ", " << z << ")";
        }
    EXPECT_EQ(mismatches, 0) << name;
  }
  fs::remove_all(dir);
}

TEST(VoxelIo, BinvoxRunsAreMaximal) {
  // A full 17³ grid is one run of 4913 voxels: 19 pairs of 255 and one of 68, across x-slabs.
  const fs::path dir = test::temp_dir("voxel-binvox-runs");
  write_voxels(dir / "full.binvox", full_grid(17));
  const std::string data = test::read_file(dir / "full.binvox");
  const std::string header = "#binvox 1\ndim 17 17 17\ntranslate -1.25 0.5 3\nscale 2.5\ndata\n";
  ASSERT_EQ(data.substr(0, header.size()), header);
  std::string runs;
  for (int i = 0; i < 19; ++i) runs += std::string("\x01\xff", 2);
  runs += std::string("\x01\x44", 2);
  EXPECT_EQ(data.substr(header.size()), runs);
  fs::remove_all(dir);
}

TEST(VoxelIo, NpyHeaderLayout) {
  const fs::path dir = test::temp_dir("voxel-npy-header");
  write_voxels(dir / "a.npy", empty_grid(7));
  const std::string data = test::read_file(dir / "a.npy");
  ASSERT_GE(data.size(), 64u);
  EXPECT_EQ(data.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const size_t header_len =
      static_cast<unsigned char>(data[8]) | (static_cast<unsigned char>(data[9]) << 8);
  EXPECT_EQ((10 + header_len) % 64, 0u);
  const std::string dict = "{'descr': '|u1', 'fortran_order': False, 'shape': (7, 7, 7), }";
  EXPECT_EQ(data.substr(10, dict.size()), dict);
  EXPECT_EQ(data[10 + header_len - 1], '\n');
  EXPECT_EQ(data.size(), 10 + header_len + 343);
  fs::remove_all(dir);
}

/// Names in `dir` (to check that no temporary file is left behind).
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(VoxelIo, UnsupportedExtensionThrows) {
  const fs::path dir = test::temp_dir("voxel-ext");
  const VoxelGrid grid = random_grid(5, 0.5, 1);
  for (const char* name : {"a.png", "a.vtk", "a", "a.binvox.txt"}) {
    try {
      write_voxels(dir / name, grid);
      ADD_FAILURE() << name << ": no exception";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find((dir / name).string()), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(listing(dir).empty());
  fs::remove_all(dir);
}

TEST(VoxelIo, ExtensionsAreCaseInsensitive) {
  EXPECT_TRUE(is_voxel_extension("a.binvox"));
  EXPECT_TRUE(is_voxel_extension("dir.x/a.vti"));
  EXPECT_TRUE(is_voxel_extension("a.NPY"));
  EXPECT_TRUE(is_voxel_extension("a.Raw"));
  EXPECT_FALSE(is_voxel_extension("a.json"));
  EXPECT_FALSE(is_voxel_extension("npy"));
  EXPECT_FALSE(is_voxel_extension("a.npz"));
  const fs::path dir = test::temp_dir("voxel-case");
  const VoxelGrid grid = sphere_grid(9);
  write_voxels(dir / "A.NPY", grid);
  std::string bytes;
  test::python_read(dir / "A.NPY", bytes);
  expect_xyz_bytes(grid, bytes, "A.NPY");
  fs::remove_all(dir);
}

TEST(VoxelIo, MissingFolderThrowsAndLeavesNothing) {
  const fs::path dir = test::temp_dir("voxel-missing");
  const VoxelGrid grid = random_grid(6, 0.5, 2);
  for (const char* name : {"a.binvox", "a.vti", "a.npy", "a.raw"}) {
    const fs::path target = dir / "missing" / name;
    try {
      write_voxels(target, grid);
      ADD_FAILURE() << name << ": no exception";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(listing(dir).empty());
  fs::remove_all(dir);
}

TEST(VoxelIo, FailedRenameLeavesNoTemporary) {
  // The target is a folder: the temporary file is written, the rename fails.
  const fs::path dir = test::temp_dir("voxel-rename");
  const VoxelGrid grid = random_grid(6, 0.5, 3);
  fs::create_directory(dir / "a.npy");
  EXPECT_THROW(write_voxels(dir / "a.npy", grid), InputError);
  EXPECT_EQ(listing(dir), std::vector<std::string>{"a.npy"});
  // .raw whose sidecar cannot be renamed: neither file is left, and the error names the sidecar.
  fs::create_directory(dir / "b.raw.json");
  try {
    write_voxels(dir / "b.raw", grid);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "b.raw.json").string()), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(listing(dir), (std::vector<std::string>{"a.npy", "b.raw.json"}));
  fs::remove_all(dir);
}

TEST(VoxelIo, OverwritesExistingFile) {
  const fs::path dir = test::temp_dir("voxel-overwrite");
  const fs::path file = dir / "a.raw";
  write_voxels(file, full_grid(8));
  const VoxelGrid grid = random_grid(5, 0.4, 4);
  write_voxels(file, grid);
  expect_xyz_bytes(grid, test::read_file(file), "a.raw");
  EXPECT_EQ(nlohmann::json::parse(test::read_file(dir / "a.raw.json"))["dims"][0], 5);
  EXPECT_EQ(listing(dir), (std::vector<std::string>{"a.raw", "a.raw.json"}));
  fs::remove_all(dir);
}

TEST(VoxelGrid, CountMatchesBruteForce) {
  for (const auto& [name, grid] : grids()) {
    uint64_t brute = 0;
    for (int i = 0; i < grid.nx(); ++i)
      for (int j = 0; j < grid.nx(); ++j)
        for (int k = 0; k < grid.nx(); ++k) brute += grid.get(i, j, k) ? 1 : 0;
    EXPECT_EQ(grid.count(), brute) << name;
  }
  EXPECT_EQ(VoxelGrid{}.count(), 0u);
  // Padding bits above k = N − 1 are not voxels.
  VoxelGrid grid = empty_grid(70);
  grid.set(3, 4, 69);
  grid.bits[grid.column_word(3, 4) + 1] |= uint64_t{1} << 63;
  EXPECT_EQ(grid.count(), 1u);
}

}  // namespace
}  // namespace cover
