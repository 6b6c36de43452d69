// `cover voxelize` and `cover octree` (docs/cli.md).
#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cover/cli/commands.h"
#include "cover/cli/output.h"
#include "cover/covering/bounds.h"
#include "cover/io/atomic_file.h"
#include "cover/io/mesh_io.h"
#include "cover/io/octree_io.h"
#include "cover/io/scene.h"
#include "cover/io/vdb_io.h"
#include "cover/io/voxel_io.h"
#include "cover/io/zarr_io.h"
#include "cover/octree/octree.h"
#include "cover/solid/errors.h"
#include "cover/solid/memory_limit.h"
#include "cover/voxel/voxel_surface.h"

namespace cover::cli {
namespace {

using nlohmann::json;

/// --bounds xmin,ymin,zmin,size, or the default cube around the result's box (Model::
/// voxel_bounds; an unbounded result has none: it needs --bounds).
VoxelBounds bounds_option(const std::string& text, const Model& model, int n,
                          const std::string& input) {
  if (text.empty()) {
    if (!model.bounded()) throw InputError(unbounded_message(input) + " (or give --bounds)");
    return model.voxel_bounds(n);
  }
  double v[4];
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &v[3], &tail) != 4 ||
      !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) || !(v[3] > 0) ||
      !std::isfinite(v[3]))
    throw InputError("--bounds: expected xmin,ymin,zmin,size with size > 0, got '" + text + "'");
  check_bounds_range({v[0], v[1], v[2]}, v[3]);
  return {{v[0], v[1], v[2]}, v[3]};
}

json bounds_json(const VoxelBounds& b) { return json{{"min", to_json(b.min)}, {"size", b.size}}; }

/// {"min", "size"} of a cubic grid's cube, else {"min", "max"} (max = origin + dims·h).
json bounds_json(const VoxelLattice& l) {
  if (l.cube_size) return bounds_json(VoxelBounds{l.origin, *l.cube_size});
  const Vec3 max{l.origin.x + l.dims[0] * l.spacing, l.origin.y + l.dims[1] * l.spacing,
                 l.origin.z + l.dims[2] * l.spacing};
  return json{{"min", to_json(l.origin)}, {"max", to_json(max)}};
}

/// --dims NX,NY,NZ (each 1 to kMaxVoxelDims).
std::array<int, 3> dims_option(const std::string& text) {
  int d[3];
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d,%d,%d%c", &d[0], &d[1], &d[2], &tail) != 3 || d[0] < 1 ||
      d[1] < 1 || d[2] < 1 || d[0] > kMaxVoxelDims || d[1] > kMaxVoxelDims || d[2] > kMaxVoxelDims)
    throw InputError("--dims: expected NX,NY,NZ, whole numbers from 1 to " +
                     std::to_string(kMaxVoxelDims) + ", got '" + text + "'");
  return {d[0], d[1], d[2]};
}

std::string dims_text(const std::array<int, 3>& d) {
  return std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]);
}

}  // namespace

int run_voxelize(const VoxelizeCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  const bool zarr = is_zarr_extension(o.output), vdb = is_vdb_extension(o.output);
  if (!is_voxel_extension(o.output) && !zarr && !vdb)
    throw InputError(
        o.output + ": unsupported voxel format (expected .binvox, .vti, .npy, .raw, .zarr, .vdb)");
  if (!o.surface.empty() && !is_mesh_output_extension(o.surface))
    throw InputError(o.surface + ": unsupported mesh format for --surface (expected " +
                     kMeshOutputFormats + ")");
  if (!o.surface.empty() && zarr)
    throw InputError("--surface: needs the grid in memory, not with a .zarr output");
  if (o.res == 0 && o.voxel_size == 0 && o.dims.empty())
    throw InputError("voxelize: give the grid: --res N, --voxel-size h or --dims NX,NY,NZ");
  const bool cubic = o.res > 0;
  if (cubic && !zarr && o.res > kMaxVoxelResolution)
    throw InputError("--res: expected a whole number from 1 to " +
                     std::to_string(kMaxVoxelResolution) + " (up to " +
                     std::to_string(kMaxVoxelDims) + " for .zarr), got " + std::to_string(o.res));
  VoxelizeOptions vo;
  vo.resolution = cubic ? o.res : 128;
  vo.voxel_size = o.voxel_size;
  if (!o.dims.empty()) vo.dims = dims_option(o.dims);
  // The bit grid needs N³/8 bytes (when its dims are known before loading).
  if (cubic && !zarr)
    check_memory(std::pow(static_cast<double>(o.res), 3) / 8, common.max_memory_bytes(),
                 "--res " + std::to_string(o.res) + ": the grid");
  const Model model = load_model(o.input, common.load_options());
  timing.lap(Timing::kLoad);
  if (o.bounds.empty() && !model.bounded())
    throw InputError(unbounded_message(o.input) + " (or give --bounds)");
  if (!o.bounds.empty()) vo.bounds = bounds_option(o.bounds, model, vo.resolution, o.input);
  const VoxelLattice lattice = model.voxel_lattice(vo);
  std::string ext = std::filesystem::path(o.output).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (!lattice.cubic() && ext == ".binvox")  // refused before the work, as write_voxels would
    throw InputError(o.output + ": .binvox holds cubic grids only (dim N N N), got " +
                     dims_text(lattice.dims) + " (use .npy, .raw, .vti, .zarr or .vdb)");
  if (!o.surface.empty() && !lattice.cubic())
    throw InputError("--surface: needs a cubic grid, got " + dims_text(lattice.dims));
  if (!cubic && !zarr)
    check_memory(static_cast<double>(lattice.voxel_count()) / 8, common.max_memory_bytes(),
                 "--dims " + dims_text(lattice.dims) + ": the grid");
  Progress progress("voxelize", common.quiet);
  auto report = [&progress](double done) {
    progress.update(static_cast<size_t>(done * 1000), 1000);
  };
  json j;
  uint64_t occupied = 0;
  if (zarr) {
    ZarrOptions zo;
    zo.chunk = o.chunk;
    zo.max_bytes = common.max_memory_bytes();
    zo.progress = report;
    const ZarrResult r = model.voxelize_to_zarr(o.output, vo, zo);
    progress.finish();
    timing.lap(Timing::kKernel);
    occupied = r.occupied;
    j["chunk"] = std::min(o.chunk, std::max({lattice.dims[0], lattice.dims[1], lattice.dims[2]}));
    j["chunks"] = r.chunks;
    j["chunks_written"] = r.chunks_written;
    j["bricks_in_flight"] = r.bricks_in_flight;
  } else {
    vo.progress = report;
    const VoxelGrid grid = model.voxelize(vo);
    progress.finish();
    timing.lap(Timing::kKernel);
    OutputBatch outputs;
    if (vdb)
      write_vdb(o.output, grid);
    else
      write_voxels(o.output, grid);
    if (!o.surface.empty()) write_mesh(o.surface, voxel_surface(grid));
    outputs.commit();
    timing.lap(Timing::kWrite);
    occupied = grid.count();
  }
  const double h = lattice.spacing;
  if (lattice.cube_size) j["res"] = lattice.dims[0];
  j["dims"] = lattice.dims;
  j["voxel_size"] = h;
  j["bounds"] = bounds_json(lattice);
  j["occupied"] = occupied;
  j["volume_estimate"] = static_cast<double>(occupied) * h * h * h;
  timing.put(j);
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::printf("%s: %s voxels, %llu occupied, volume estimate %.9g, %.3f s\n", o.output.c_str(),
                lattice.cubic() ? (std::to_string(lattice.dims[0]) + "^3").c_str()
                                : dims_text(lattice.dims).c_str(),
                static_cast<unsigned long long>(occupied), j["volume_estimate"].get<double>(),
                j["seconds"].get<double>());
  }
  return 0;
}

int run_octree(const OctreeCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  if (!is_octree_extension(o.output))
    throw InputError(o.output + ": unsupported octree format (expected .htg, .bt, .json)");
  const Model model = load_model(o.input, common.load_options());
  timing.lap(Timing::kLoad);
  OctreeOptions oo;
  oo.depth = o.depth;
  oo.max_bytes = common.max_memory_bytes();
  Progress progress("octree", common.quiet);
  oo.progress = [&progress](double done) {
    progress.update(static_cast<size_t>(done * 1000), 1000);
  };
  // A .bt's cube lies on OctoMap's grid (io/octree_io.h); given --bounds are checked there.
  const bool bt = lower_extension(o.output) == ".bt";
  VoxelBounds bounds;
  if (bt && o.bounds.empty() && o.depth >= 1 && model.bounded())
    bounds = octomap_bounds(*model.bounds(), o.depth);
  else
    bounds = bounds_option(o.bounds, model, 1 << o.depth, o.input);
  if (bt && o.depth >= 1) check_octomap_cube(o.output, bounds, o.depth);
  const Octree tree = model.octree(oo, bounds);
  progress.finish();
  timing.lap(Timing::kKernel);
  OutputBatch outputs;
  write_octree(o.output, tree, o.threshold);
  outputs.commit();
  timing.lap(Timing::kWrite);
  const auto counts = tree.leaf_counts();
  json j;
  j["depth"] = o.depth;
  j["nodes"] = tree.nodes.size();
  j["leaves"] = {{"empty", counts[0]}, {"full", counts[1]}, {"partial", counts[2]}};
  j["bounds"] = bounds_json(tree.bounds);
  timing.put(j);
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::printf("%s: depth %d, %zu nodes, leaves: %llu full, %llu empty, %llu partial, %.3f s\n",
                o.output.c_str(), o.depth, tree.nodes.size(),
                static_cast<unsigned long long>(counts[1]),
                static_cast<unsigned long long>(counts[0]),
                static_cast<unsigned long long>(counts[2]), j["seconds"].get<double>());
  }
  return 0;
}

}  // namespace cover::cli
