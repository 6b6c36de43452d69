// How query time scales from ~10k to ~1M triangles, Cover and CGAL side by side in one process:
// the same bumpy spheres, points and rays as bench_queries (bench_models.h), one thread.
//   classify     Cover classify() of batches of 1000 points (BVH prebuilt, empty-cell grid
//                off: BM_ClassifyPoint) | CGAL Side_of_triangle_mesh, tree prebuilt, per point
//   rays         Cover cast() of one ray, all hits + CSG spans (BM_CastRay), and the batch cast()
//                of 1000 rays (BM_CastRays) | CGAL AABB_tree all_intersections (every hit, as
//                cast() finds) and first_intersection, tree prebuilt, per ray
// Each round times one pass of every method over its Q queries at every size, so the host's
// slow spells fall on all of them alike; per query, min and median over the rounds. The last
// lines are the 1M / 10k ratios of each column next to log n's (docs/benchmarks.md).
// Hits are compared too: Cover's hit count per ray against CGAL's all_intersections (a ray
// through an edge or vertex may differ: CGAL reports a point per triangle touched).
// Usage: scaling_vs_cgal [--queries Q (64000)] [--rounds R (5)] [--max N (1000000)]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "bench_models.h"
#include "cgal_query_types.h"
#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/covering/ray.h"
#include "cover/solid/parallel.h"

namespace {

using bench::arg;
using bench::Clock;
using bench::K;
using bench::Mesh;
using bench::Tree;
constexpr uint64_t kSeed = 20240601;  ///< bench_queries' seed: the same points and rays
constexpr size_t kBatch = 1000;       ///< queries per Cover call in the batch columns

/// One size: the Cover solid and BVH, the same mesh in CGAL with both peer structures, queries.
struct Size {
  cover::Solid solid;
  std::unique_ptr<cover::Prepared> prepared;
  const cover::Bvh* bvh = nullptr;  ///< prepared->bvh()
  Mesh mesh;
  std::unique_ptr<Tree> tree;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, K>> side;
  std::vector<cover::Vec3> points;
  std::vector<cover::Ray> rays;
  std::vector<K::Point_3> cgal_points;
  std::vector<K::Ray_3> cgal_rays;
};

std::unique_ptr<Size> make_size(int64_t target, size_t queries) {
  auto s = std::make_unique<Size>();
  const cover::PolygonMesh poly = bench::bumpy_sphere(bench::segments_for(target));
  s->solid = cover::make_leaf(poly, "sphere");
  s->prepared = std::make_unique<cover::Prepared>(s->solid);
  s->bvh = &s->prepared->bvh();
  std::vector<Mesh::Vertex_index> v;
  v.reserve(poly.vertices.size());
  for (const cover::Vec3& p : poly.vertices)
    v.push_back(s->mesh.add_vertex(K::Point_3(p.x, p.y, p.z)));
  for (size_t f = 0; f < poly.face_count(); ++f) {
    const auto loop = poly.face(f);
    s->mesh.add_face(v[loop[0]], v[loop[1]], v[loop[2]]);
  }
  s->tree = std::make_unique<Tree>(faces(s->mesh).first, faces(s->mesh).second, s->mesh);
  s->tree->build();
  s->side = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh, K>>(s->mesh);
  s->points = bench::random_points(s->solid, queries, kSeed);
  s->rays = bench::random_rays(s->solid, queries, kSeed);
  for (const cover::Vec3& p : s->points) s->cgal_points.emplace_back(p.x, p.y, p.z);
  for (const cover::Ray& r : s->rays)
    s->cgal_rays.emplace_back(K::Point_3(r.origin.x, r.origin.y, r.origin.z),
                              K::Vector_3(r.dir.x, r.dir.y, r.dir.z));
  (*s->side)(s->cgal_points[0]);  // the side test builds its own tree on first use
  return s;
}

struct Method {
  const char* name;
  std::function<size_t(Size&)> pass;  ///< one pass over the queries; returns a checksum
  bool rays;                          ///< per ray (else per point)
};

}  // namespace

int main(int argc, char** argv) {
  // Whole batches of kBatch queries, at least one.
  const size_t queries =
      std::max<size_t>(
          1, static_cast<size_t>(std::max(0L, arg(argc, argv, "--queries", 64000))) / kBatch) *
      kBatch;
  const int rounds = static_cast<int>(std::max(1L, arg(argc, argv, "--rounds", 5)));
  const long max_target = arg(argc, argv, "--max", 1000000);
  std::vector<std::unique_ptr<Size>> sizes;
  for (long target = 10000; target <= max_target; target *= 10) {
    std::fprintf(stderr, "building %ld triangles...\n", target);
    sizes.push_back(make_size(target, queries));
  }
  if (sizes.size() < 2) {
    std::fprintf(stderr, "scaling_vs_cgal: --max must be at least 100000\n");
    return 2;
  }
  cover::ThreadLimit limit(1);
  const cover::ClassifyOptions no_grid{.grid_min_points = SIZE_MAX};
  const std::vector<Method> methods = {
      {"Cover classify",
       [&](Size& s) {
         size_t inside = 0;
         for (size_t b = 0; b + kBatch <= s.points.size(); b += kBatch)
           for (const cover::PointClass c :
                cover::classify(*s.prepared, std::span(s.points).subspan(b, kBatch), no_grid))
             inside += c == cover::PointClass::kInside;
         return inside;
       },
       false},
      {"CGAL side",
       [&](Size& s) {
         size_t inside = 0;
         for (const K::Point_3& p : s.cgal_points) inside += (*s.side)(p) == CGAL::ON_BOUNDED_SIDE;
         return inside;
       },
       false},
      {"Cover ray",
       [&](Size& s) {
         size_t hits = 0;
         for (const cover::Ray& r : s.rays)
           hits += cover::cast(*s.bvh, s.solid.tree, s.solid.leaves.size(), r).hits.size();
         return hits;
       },
       true},
      {"Cover rays batch",
       [&](Size& s) {
         size_t hits = 0;
         for (size_t b = 0; b + kBatch <= s.rays.size(); b += kBatch)
           for (const cover::RayResult& r :
                cover::cast(*s.prepared, std::span(s.rays).subspan(b, kBatch)))
             hits += r.hits.size();
         return hits;
       },
       true},
      {"CGAL all hits",
       [&](Size& s) {
         size_t hits = 0;
         std::vector<Tree::Intersection_and_primitive_id<K::Ray_3>::Type> out;
         for (const K::Ray_3& r : s.cgal_rays) {
           out.clear();
           s.tree->all_intersections(r, std::back_inserter(out));
           hits += out.size();
         }
         return hits;
       },
       true},
      {"CGAL first hit",
       [&](Size& s) {
         size_t hits = 0;
         for (const K::Ray_3& r : s.cgal_rays) hits += s.tree->first_intersection(r).has_value();
         return hits;
       },
       true},
  };
  // seconds per query, [method][size][round]
  std::vector<std::vector<std::vector<double>>> t(methods.size(),
                                                  std::vector<std::vector<double>>(sizes.size()));
  std::vector<std::vector<size_t>> check(methods.size(), std::vector<size_t>(sizes.size()));
  for (int round = 0; round < rounds; ++round) {
    std::fprintf(stderr, "round %d of %d\n", round + 1, rounds);
    for (size_t m = 0; m < methods.size(); ++m)
      for (size_t z = 0; z < sizes.size(); ++z) {
        const size_t n = methods[m].rays ? sizes[z]->rays.size() : sizes[z]->points.size();
        const auto t0 = Clock::now();
        check[m][z] = methods[m].pass(*sizes[z]);
        t[m][z].push_back(bench::since(t0) / static_cast<double>(n));
      }
  }
  auto min_of = [](std::vector<double> v) { return *std::min_element(v.begin(), v.end()); };
  auto median_of = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::printf("%zu queries per pass, %d rounds, 1 thread; per query: min / median (ns)\n", queries,
              rounds);
  std::printf("%-18s", "triangles");
  for (const auto& s : sizes) std::printf(" %21zu", s->solid.face_count());
  std::printf(" %21s\n", "largest / smallest");
  for (size_t m = 0; m < methods.size(); ++m) {
    std::printf("%-18s", methods[m].name);
    for (size_t z = 0; z < sizes.size(); ++z)
      std::printf(" %10.0f / %8.0f", min_of(t[m][z]) * 1e9, median_of(t[m][z]) * 1e9);
    std::printf("     x%.2f / x%.2f\n", min_of(t[m].back()) / min_of(t[m].front()),
                median_of(t[m].back()) / median_of(t[m].front()));
  }
  const double n0 = static_cast<double>(sizes.front()->solid.face_count());
  const double n1 = static_cast<double>(sizes.back()->solid.face_count());
  std::printf("log n: x%.2f\n", std::log(n1) / std::log(n0));
  // Sanity: the same answers (classification: inside counts; rays: hit counts). Cover and CGAL
  // classify alike here (no query point lies on the surface), and Cover's single and batch casts
  // find the same hits; CGAL's all_intersections may count a ray through an edge twice.
  bool same = true;
  for (size_t z = 0; z < sizes.size(); ++z) {
    std::printf(
        "%zu triangles: inside %zu (Cover) / %zu (CGAL); hits %zu / %zu (Cover single / "
        "batch) / %zu (CGAL all)\n",
        sizes[z]->solid.face_count(), check[0][z], check[1][z], check[2][z], check[3][z],
        check[4][z]);
    same &= check[0][z] == check[1][z] && check[2][z] == check[3][z];
  }
  if (!same) std::printf("DISAGREEMENT between Cover and CGAL or between Cover's casts\n");
  return same ? 0 : 1;
}
