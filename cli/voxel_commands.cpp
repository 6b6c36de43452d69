// `cover voxelize` and `cover octree` (CONTRACT.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/output.h"
#include "covering/bounds.h"
#include "octree/octree.h"
#include "octree/octree_io.h"
#include "raster/voxel_io.h"
#include "raster/voxel_surface.h"
#include "solid/atomic_file.h"
#include "solid/errors.h"
#include "solid/memory_limit.h"
#include "solid/mesh_io.h"
#include "solid/scene.h"

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
  return {{v[0], v[1], v[2]}, v[3]};
}

json bounds_json(const VoxelBounds& b) {
  return json{{"min", to_json(b.min)}, {"size", b.size}};
}

}  // namespace

int run_voxelize(const VoxelizeCommandOptions& o, const CommonOptions& common) {
  Timing timing;
  if (!is_voxel_extension(o.output))
    throw InputError(o.output + ": unsupported voxel format (expected .binvox, .vti, .npy, .raw)");
  if (!o.surface.empty() && !is_mesh_extension(o.surface))
    throw InputError(o.surface + ": unsupported mesh format for --surface (expected .obj, .stl, .off, .ply)");
  // The bit grid needs N³/8 bytes.
  check_memory(std::pow(static_cast<double>(o.res), 3) / 8, common.max_memory_bytes(),
               "--res " + std::to_string(o.res) + ": the grid");
  const Model model = load_model(o.input, common.load_options());
  timing.lap(Timing::kLoad);
  VoxelizeOptions vo;
  vo.resolution = o.res;
  vo.bounds = bounds_option(o.bounds, model, o.res, o.input);
  Progress progress("voxelize", common.quiet);
  vo.progress = [&progress](double done) { progress.update(static_cast<size_t>(done * 1000), 1000); };
  const VoxelGrid grid = model.voxelize(vo);
  progress.finish();
  timing.lap(Timing::kKernel);
  OutputBatch outputs;
  write_voxels(o.output, grid);
  if (!o.surface.empty()) write_mesh(o.surface, voxel_surface(grid));
  outputs.commit();
  timing.lap(Timing::kWrite);
  const uint64_t occupied = grid.count();
  const double h = grid.voxel_size();
  json j;
  j["res"] = o.res;
  j["bounds"] = bounds_json(grid.bounds);
  j["occupied"] = occupied;
  j["volume_estimate"] = static_cast<double>(occupied) * h * h * h;
  timing.put(j);
  if (common.json) {
    std::cout << j.dump() << "\n";
  } else {
    std::printf("%s: %d^3 voxels, %llu occupied, volume estimate %.9g, %.3f s\n", o.output.c_str(), o.res,
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
  oo.progress = [&progress](double done) { progress.update(static_cast<size_t>(done * 1000), 1000); };
  const Octree tree = model.octree(oo, bounds_option(o.bounds, model, 1 << o.depth, o.input));
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
                o.output.c_str(), o.depth, tree.nodes.size(), static_cast<unsigned long long>(counts[1]),
                static_cast<unsigned long long>(counts[0]), static_cast<unsigned long long>(counts[2]),
                j["seconds"].get<double>());
  }
  return 0;
}

}  // namespace cover::cli
