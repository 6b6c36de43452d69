// How Cover's exact queries scale with mesh size (Google Benchmark).
//
// Model: a closed bumpy sphere (make_sphere's UV sphere, vertices displaced radially by a smooth
// positive function of the direction, quads fan-triangulated) at about 10k, 100k and 1M
// triangles; the benchmark argument is the target count, the counter `triangles` the exact one.
// Measured (single thread unless stated, so the numbers show algorithmic scaling):
//   BM_BvhBuild        cover::Bvh construction; time per triangle and BVH bytes per triangle.
//   BM_ClassifyPoint   classify() of batches of 1000 uniform points in the bounding box with the
//                      BVH prebuilt and the empty-cell grid off (pure BVH path); time per point,
//                      and the BVH nodes a point's walk tests and the leaves it reaches.
//   BM_ClassifyMillion end to end on 2 threads: BVH build + classify() of 1,000,000 points with
//                      default options (grid on).
//   BM_ClassifyBulk    classify() of 1,000,000 points in one call, BVH prebuilt, 1 thread, grid
//                      off: per-query cost of the BVH path in bulk (spatially ordered) use.
//   BM_CastRay         cast() of one ray (all hits + CSG spans) from outside the bounding sphere
//                      toward a uniform point in the box, BVH prebuilt; time per ray (latency).
//   BM_CastRays        the same rays through the batch cast(), 1000 per call; time per ray, and
//                      the nodes a ray's walk tests and the leaves it reaches.
// Usage: bench_queries [--benchmark_min_time=0.2] [--benchmark_filter=REGEX]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "bench_models.h"
#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/covering/ray.h"
#include "cover/solid/parallel.h"

namespace {

constexpr size_t kBatch = 1000;       ///< points or rays per timed iteration
constexpr size_t kBatches = 64;       ///< distinct batches cycled through (64k queries)
constexpr size_t kMillion = 1000000;  ///< points of BM_ClassifyMillion
constexpr uint64_t kSeed = 20240601;  ///< every random input is seeded

/// The solid and its BVH for one target size, built once and shared by every benchmark.
struct Model {
  cover::Solid solid;
  std::unique_ptr<cover::Prepared> prepared;
  const cover::Bvh* bvh = nullptr;  ///< prepared->bvh()
};

const Model& model(int64_t target) {
  static std::map<int64_t, Model> cache;
  Model& m = cache[target];
  if (!m.bvh) {
    m.solid = cover::make_leaf(bench::bumpy_sphere(bench::segments_for(target)), "sphere");
    m.prepared = std::make_unique<cover::Prepared>(m.solid);
    m.bvh = &m.prepared->bvh();
  }
  return m;
}

/// Counter: seconds per item (printed as e.g. "45.3ns"), `items` processed per iteration.
benchmark::Counter time_per(double items) {
  return benchmark::Counter(
      items, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// Bvh construction, one thread.
void BM_BvhBuild(benchmark::State& state) {  // NOLINT(readability-identifier-naming)
  const Model& m = model(state.range(0));
  const auto triangles = static_cast<double>(m.solid.face_count());
  cover::ThreadLimit limit(1);
  size_t bytes = 0;
  for (auto _ : state) {
    const cover::Bvh bvh(m.solid);
    bytes = bvh.memory_bytes();
    benchmark::DoNotOptimize(bvh.nodes().data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(triangles));
  state.counters["triangles"] = triangles;
  state.counters["bytes_per_triangle"] = static_cast<double>(bytes) / triangles;
  state.counters["time_per_triangle"] = time_per(triangles);
}

/// Nodes a depth-first walk tests when `meets` decides which nodes it enters (each node reached
/// is tested once, as in covering/bvh_walk.h's walk and walk_batch).
template <typename Meets>
size_t nodes_tested(const cover::Bvh& bvh, Meets&& meets) {
  size_t tested = 0;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const cover::Bvh::Node& n = bvh.nodes()[stack.back()];
    stack.pop_back();
    ++tested;
    if (!meets(n) || n.count > 0) continue;
    stack.push_back(n.first + 1);
    stack.push_back(n.first);
  }
  return tested;
}

/// BVH nodes a classification query visits (the algorithmic cost, free of cache effects):
/// the same half-line test as covering/classify.cpp, over the public node array; `leaves` gets
/// the leaf nodes it reaches per query.
double nodes_per_query(const cover::Bvh& bvh, const std::vector<cover::Vec3>& points,
                       double& leaves) {
  const cover::Bbox& all = bvh.bounds();
  size_t visited = 0, reached = 0;
  for (const cover::Vec3& p : points) {
    int k = 0, s = 1;
    double shortest = all.max.x - p.x;
    for (int a = 0; a < 3; ++a)
      for (int sa : {1, -1}) {
        const double len = sa > 0 ? all.max[a] - p[a] : p[a] - all.min[a];
        if (len < shortest) shortest = len, k = a, s = sa;
      }
    const int u = (k + 1) % 3, w = (k + 2) % 3;
    visited += nodes_tested(bvh, [&](const cover::Bvh::Node& n) {
      const bool m = !(p[u] < n.lo[u] || p[u] > n.hi[u] || p[w] < n.lo[w] || p[w] > n.hi[w] ||
                       (s > 0 ? p[k] > n.hi[k] : p[k] < n.lo[k]));
      reached += m && n.count > 0;
      return m;
    });
  }
  leaves = static_cast<double>(reached) / static_cast<double>(points.size());
  return static_cast<double>(visited) / static_cast<double>(points.size());
}

// classify() of 1000 points per iteration, BVH prebuilt, empty-cell grid off, one thread.
void BM_ClassifyPoint(benchmark::State& state) {  // NOLINT(readability-identifier-naming)
  const Model& m = model(state.range(0));
  const std::vector<cover::Vec3> points = bench::random_points(m.solid, kBatch * kBatches, kSeed);
  const cover::ClassifyOptions options{.grid_min_points = SIZE_MAX};
  cover::ThreadLimit limit(1);
  size_t batch = 0, inside = 0, classified = 0;
  for (auto _ : state) {
    const auto result =
        cover::classify(*m.prepared, std::span(points).subspan(batch * kBatch, kBatch), options);
    for (const cover::PointClass c : result) inside += c == cover::PointClass::kInside;
    classified += result.size();
    batch = (batch + 1) % kBatches;
  }
  state.SetItemsProcessed(static_cast<int64_t>(classified));
  state.counters["triangles"] = static_cast<double>(m.solid.face_count());
  state.counters["inside_fraction"] = static_cast<double>(inside) / static_cast<double>(classified);
  state.counters["time_per_point"] = time_per(kBatch);
  double leaves = 0;
  state.counters["nodes_per_query"] = nodes_per_query(*m.bvh, points, leaves);
  state.counters["leaves_per_query"] = leaves;
}

// End to end on 2 threads: BVH build + classify() of 1M points, default options (grid on).
void BM_ClassifyMillion(benchmark::State& state) {  // NOLINT(readability-identifier-naming)
  const Model& m = model(state.range(0));
  const std::vector<cover::Vec3> points = bench::random_points(m.solid, kMillion, kSeed);
  cover::ThreadLimit limit(2);
  for (auto _ : state) {
    const cover::Prepared prepared(m.solid);
    const auto result = cover::classify(prepared, points);
    benchmark::DoNotOptimize(result.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(kMillion));
  state.counters["triangles"] = static_cast<double>(m.solid.face_count());
  state.counters["time_per_point"] = time_per(kMillion);
}

// classify() of 1,000,000 points in one call, BVH prebuilt, one thread, empty-cell grid off:
// the per-query cost of the BVH path in bulk use (queries processed in spatial order).
void BM_ClassifyBulk(benchmark::State& state) {  // NOLINT(readability-identifier-naming)
  const Model& m = model(state.range(0));
  const std::vector<cover::Vec3> points = bench::random_points(m.solid, kMillion, kSeed);
  cover::ThreadLimit limit(1);
  cover::ClassifyOptions options;
  options.grid_min_points = SIZE_MAX;
  for (auto _ : state) {
    const auto result = cover::classify(*m.prepared, points, options);
    benchmark::DoNotOptimize(result.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(kMillion));
  state.counters["triangles"] = static_cast<double>(m.solid.face_count());
  state.counters["time_per_point"] = time_per(kMillion);
}

/// BVH nodes whose box a ray's walk tests (the algorithmic cost of a ray, free of cache effects):
/// the slab test of covering/ray.cpp (the same formula and slack), over the public node array;
/// `leaves` gets the leaf nodes it reaches per ray.
double nodes_per_ray(const cover::Bvh& bvh, const std::vector<cover::Ray>& rays, double& leaves) {
  size_t tested = 0, reached = 0;
  for (const cover::Ray& r : rays) {
    auto meets = [&](const cover::Bvh::Node& n) {
      double enter = -INFINITY, leave = INFINITY;
      for (int a = 0; a < 3; ++a) {
        const double inv = 1.0 / r.dir[a];
        if (std::isinf(inv)) {
          if (r.origin[a] < n.lo[a] || r.origin[a] > n.hi[a]) return false;
          continue;
        }
        const double ta = (n.lo[a] - r.origin[a]) * inv, tb = (n.hi[a] - r.origin[a]) * inv;
        enter = std::max(enter, std::min(ta, tb));
        leave = std::min(leave, std::max(ta, tb));
      }
      const bool m = std::max(0.0, enter * (1 - 1e-12)) <= leave * (1 + 1e-12);
      reached += m && n.count > 0;
      return m;
    };
    tested += nodes_tested(bvh, meets);
  }
  leaves = static_cast<double>(reached) / static_cast<double>(rays.size());
  return static_cast<double>(tested) / static_cast<double>(rays.size());
}

// cast() of 1000 rays per iteration (all hits and CSG spans), BVH prebuilt, one thread: one call
// per ray (BM_CastRay: a ray's latency) or one batch call (BM_CastRays: the API for many rays,
// which `cover volume` uses; the rays walk the BVH together).
void cast_rays(benchmark::State& state, bool batch_api) {
  const Model& m = model(state.range(0));
  const std::vector<cover::Ray> rays = bench::random_rays(m.solid, kBatch * kBatches, kSeed);
  cover::ThreadLimit limit(1);
  size_t batch = 0, hits = 0, cast = 0;
  for (auto _ : state) {
    if (batch_api) {
      const auto results =
          cover::cast(*m.prepared, std::span(rays).subspan(batch * kBatch, kBatch));
      for (const cover::RayResult& r : results) hits += r.hits.size();
    } else {
      for (size_t i = batch * kBatch; i < (batch + 1) * kBatch; ++i)
        hits += cover::cast(*m.bvh, m.solid.tree, m.solid.leaves.size(), rays[i]).hits.size();
    }
    cast += kBatch;
    batch = (batch + 1) % kBatches;
  }
  state.SetItemsProcessed(static_cast<int64_t>(cast));
  state.counters["triangles"] = static_cast<double>(m.solid.face_count());
  state.counters["hits_per_ray"] = static_cast<double>(hits) / static_cast<double>(cast);
  state.counters["time_per_ray"] = time_per(kBatch);
  double leaves = 0;
  state.counters["nodes_per_ray"] = nodes_per_ray(*m.bvh, rays, leaves);
  state.counters["leaves_per_ray"] = leaves;
}
// NOLINTNEXTLINE(readability-identifier-naming)
void BM_CastRay(benchmark::State& state) { cast_rays(state, false); }
// NOLINTNEXTLINE(readability-identifier-naming)
void BM_CastRays(benchmark::State& state) { cast_rays(state, true); }

// Targets 10k, 100k, 1M triangles; wall-clock time (the TBB workers' CPU time is not the
// calling thread's).
void sizes(benchmark::internal::Benchmark* b) {
  b->Arg(10000)->Arg(100000)->Arg(1000000)->UseRealTime();
}

BENCHMARK(BM_BvhBuild)->Apply(sizes)->Unit(benchmark::kMillisecond);
// The per-query benchmarks warm up first: on the benchmark VM the first fraction of a second after
// idling runs up to 1.5x slower (the host's clock), which skewed the 10k-vs-1M ratios.
BENCHMARK(BM_ClassifyPoint)->Apply(sizes)->Unit(benchmark::kMicrosecond)->MinWarmUpTime(0.5);
BENCHMARK(BM_ClassifyMillion)->Apply(sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClassifyBulk)->Apply(sizes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CastRay)->Apply(sizes)->Unit(benchmark::kMicrosecond)->MinWarmUpTime(0.5);
BENCHMARK(BM_CastRays)->Apply(sizes)->Unit(benchmark::kMicrosecond)->MinWarmUpTime(0.5);

}  // namespace

BENCHMARK_MAIN();
