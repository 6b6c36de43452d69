// Voxelization and octree benchmark, one process, same machine (issue: voxels and octrees):
//   cover      voxelize() into a reused grid (2 threads by default)
//   floor      one memset + one XOR pass over a bit grid of the same size (memory-bandwidth
//              floor): "cold" = mapped memory not in cache (a 256 MiB sweep evicts it first: the
//              memory-bandwidth floor proper), "warm" = right after another pass (at 512³ the
//              16 MiB grid sits in the 32 MiB L3: a cache-bandwidth figure), "fresh" = newly
//              allocated memory (page faults included, as a new grid pays them; huge pages as a
//              grid's, solid/large_vector.h)
//   openvdb    tools::meshToVolume at the same voxel size, through its world-space wrappers:
//              meshToLevelSet (narrow band, half width 3) and, up to 512³,
//              meshToSignedDistanceField with the interior band unlimited (the filled volume that
//              Cover's occupancy corresponds to); same thread count
//   octree     build_octree() at the given depths, median of 3, interleaved with voxelize() of
//              the same cube at (2^D)³ (its finest cells) into a reused and a fresh grid
//   peak       ru_maxrss after the runs (run --peak-only to measure one voxelization alone)
// Usage: voxel_bench MESH --res N [--res N ...] [--octree D ...] [--threads T] [--no-openvdb]
//                     [--peak-only]
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "cover/io/scene.h"
#include "cover/octree/octree.h"
#include "cover/solid/large_vector.h"
#include "cover/solid/parallel.h"
#include "cover/voxel/voxelize.h"

namespace {

using bench::Clock;
using bench::since;
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
/// CPU seconds of the process so far (user + system, all threads): under a loaded host a steadier
/// measure of work than wall time.
double cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
double peak_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

/// memset + XOR prefix pass over `words` (the same traffic a presence buffer needs at least).
uint64_t floor_pass(std::span<uint64_t> words) {
  std::memset(words.data(), 0, words.size() * sizeof(uint64_t));
  uint64_t acc = 0x9e3779b97f4a7c15ULL;
  for (uint64_t& w : words) w = acc ^= w;
  return acc;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: voxel_bench MESH --res N [--octree D] [--threads T]\n");
    return 2;
  }
  std::vector<int> resolutions, depths;
  int threads = 2;
  bool openvdb_on = true, peak_only = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--res" && i + 1 < argc) resolutions.push_back(std::atoi(argv[++i]));
    if (a == "--octree" && i + 1 < argc) depths.push_back(std::atoi(argv[++i]));
    if (a == "--threads" && i + 1 < argc) threads = std::atoi(argv[++i]);
    if (a == "--no-openvdb") openvdb_on = false;
    if (a == "--peak-only") peak_only = true;
  }
  const cover::Solid solid = cover::load_input(argv[1]).solid;
  const cover::Prepared prepared(solid);  // the whole-grid sweep builds no BVH
  cover::ThreadLimit limit(threads);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  std::printf("{\"mesh\": \"%s\", \"faces\": %zu, \"threads\": %d, \"runs\": [\n", argv[1],
              solid.face_count(), threads);
  for (size_t r = 0; r < resolutions.size(); ++r) {
    const int n = resolutions[r];
    cover::VoxelizeOptions o;
    o.resolution = n;
    cover::VoxelGrid grid;
    const int reps = peak_only ? 1 : 3;
    std::vector<double> t_cover, t_warm, t_fresh, t_cold;
    std::vector<uint64_t> evict(size_t{256} << 17, 1);  // 256 MiB
    for (int k = 0; k < reps; ++k) {
      auto t0 = Clock::now();
      cover::voxelize(prepared, o, grid);
      t_cover.push_back(since(t0));
    }
    const double cover_peak = peak_mib();
    const uint64_t occupied = grid.count();
    if (peak_only) {
      std::printf("  {\"res\": %d, \"cover_s\": %.4f, \"occupied\": %llu, \"peak_mib\": %.1f}\n", n,
                  t_cover[0], static_cast<unsigned long long>(occupied), cover_peak);
      continue;
    }
    uint64_t sink = 0;
    for (int k = 0; k < reps; ++k) {
      for (uint64_t& e : evict) e += k;
      auto t0 = Clock::now();
      sink ^= floor_pass(grid.bits);
      t_cold.push_back(since(t0));
      t0 = Clock::now();
      sink ^= floor_pass(grid.bits);
      t_warm.push_back(since(t0));
      t0 = Clock::now();
      std::vector<uint64_t> fresh;  // allocated as a grid is
      cover::resize_huge(fresh, grid.bits.size());
      sink ^= floor_pass(fresh);
      t_fresh.push_back(since(t0));
    }
    double vdb_band = 0, vdb_filled = 0;
    if (openvdb_on) {
      openvdb::initialize();
      std::vector<openvdb::Vec3s> points;
      std::vector<openvdb::Vec3I> triangles;
      for (const cover::Vec3& p : solid.vertices)
        points.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y),
                            static_cast<float>(p.z));
      for (size_t f = 0; f < solid.face_count(); ++f) {
        const auto face = solid.face(f);
        for (size_t i = 1; i + 1 < face.size(); ++i)
          triangles.emplace_back(face[0], face[i], face[i + 1]);
      }
      // World-space points; the transform sets the voxel size (the same as Cover's).
      const auto xform = openvdb::math::Transform::createLinearTransform(grid.voxel_size());
      auto t0 = Clock::now();
      auto band =
          openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, triangles, 3.0f);
      vdb_band = since(t0);
      sink ^= band->activeVoxelCount();
      band.reset();
      if (n <= 512) {  // the filled interior is dense: 4 bytes per inside voxel
        t0 = Clock::now();
        auto filled = openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
            *xform, points, triangles, {}, 3.0f, std::numeric_limits<float>::max());
        vdb_filled = since(t0);
        sink ^= filled->activeVoxelCount();
      }
    }
    const double c = median(t_cover), w = median(t_warm), f = median(t_fresh),
                 cold = median(t_cold);
    std::printf(
        "  {\"res\": %d, \"cover_s\": %.4f, \"floor_cold_s\": %.4f, \"x_floor_cold\": %.1f, "
        "\"floor_warm_s\": %.4f, \"floor_fresh_s\": %.4f, "
        "\"x_floor_warm\": %.1f, \"x_floor_fresh\": %.1f, \"openvdb_band_s\": %.3f, "
        "\"openvdb_filled_s\": %.3f, \"openvdb_band_over_cover\": %.1f, "
        "\"openvdb_filled_over_cover\": %.1f, \"occupied\": %llu, \"peak_mib\": %.1f, \"sink\": "
        "%llu}%s\n",
        n, c, cold, c / cold, w, f, c / w, c / f, vdb_band, vdb_filled, vdb_band / c,
        vdb_filled / c, static_cast<unsigned long long>(occupied), cover_peak,
        static_cast<unsigned long long>(sink & 1),
        r + 1 < resolutions.size() || !depths.empty() ? "," : "");
  }
  for (size_t d = 0; d < depths.size(); ++d) {
    cover::OctreeOptions oo;
    oo.depth = depths[d];
    const cover::Bbox box = solid.bbox();
    const auto bounds = cover::default_voxel_bounds(box, 1 << std::min(depths[d], 20));
    // Interleaved with the voxelization of the same cube at the octree's finest cells
    // ((2^D)³ voxels): into one reused grid (as the --res rows) and into a fresh grid (as
    // `cover voxelize` does).
    cover::VoxelizeOptions vo;
    vo.resolution = 1 << depths[d];
    vo.bounds = bounds;
    cover::VoxelGrid reused;
    cover::voxelize(prepared, vo, reused);  // the reused grid's pages, touched once
    std::vector<double> t_tree, t_reused, t_fresh, c_tree, c_reused;
    size_t nodes = 0;
    std::array<uint64_t, 3> counts{};
    for (int k = 0; k < (peak_only ? 1 : 3); ++k) {
      auto t0 = Clock::now();
      double c0 = cpu_s();
      const cover::Octree tree = cover::build_octree(solid, bounds, oo);
      t_tree.push_back(since(t0));
      c_tree.push_back(cpu_s() - c0);
      nodes = tree.nodes.size();
      counts = tree.leaf_counts();
      if (depths[d] > 12) continue;  // no grid beyond 4096³
      t0 = Clock::now();
      c0 = cpu_s();
      cover::voxelize(prepared, vo, reused);
      t_reused.push_back(since(t0));
      c_reused.push_back(cpu_s() - c0);
      t0 = Clock::now();
      cover::VoxelGrid fresh;
      cover::voxelize(prepared, vo, fresh);
      t_fresh.push_back(since(t0));
    }
    const double t = median(t_tree);
    const double v = t_reused.empty() ? 0 : median(t_reused);
    const double vf = t_fresh.empty() ? 0 : median(t_fresh);
    const double ct = median(c_tree), cv = c_reused.empty() ? 0 : median(c_reused);
    std::printf(
        "  {\"octree_depth\": %d, \"seconds\": %.3f, \"nodes\": %zu, \"full\": %llu, "
        "\"empty\": %llu, \"partial\": %llu, \"voxelize_s\": %.4f, \"voxelize_fresh_s\": %.4f, "
        "\"octree_over_voxelize\": %.1f, \"octree_over_voxelize_fresh\": %.1f, \"octree_cpu_s\": "
        "%.3f, \"voxelize_cpu_s\": %.4f, \"cpu_ratio\": %.1f}%s\n",
        depths[d], t, nodes, static_cast<unsigned long long>(counts[1]),
        static_cast<unsigned long long>(counts[0]), static_cast<unsigned long long>(counts[2]), v,
        vf, v > 0 ? t / v : 0.0, vf > 0 ? t / vf : 0.0, ct, cv, cv > 0 ? ct / cv : 0.0,
        d + 1 < depths.size() ? "," : "");
  }
  std::printf("]}\n");
  return 0;
}
