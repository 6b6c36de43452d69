// Cover vs CGAL on the same mesh, the same points and the same rays, in one process:
//   classification: Cover (BVH build + classify, T threads) vs CGAL Side_of_triangle_mesh
//                   (AABB tree build + queries, 1 thread); disagreements counted (CGAL's
//                   ON_BOUNDARY points excluded); Cover's BVH path vs its brute-force path.
//   rays:           Cover first_hit vs CGAL AABB_tree first_intersection (1 thread each), Cover
//                   both one cast() per ray and one batch cast() of all rays (same hits).
// Timings are the median of --repeat runs (default 3) of each side, interleaved.
// Usage: compare_cgal MESH [--points N] [--brute N] [--rays N] [--threads T] [--seed S]
//                          [--repeat R]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <random>
#include <string>

#include "bench_cli.h"
#include "cgal_query_types.h"
#include "cover/covering/classify.h"
#include "cover/covering/ray.h"
#include "cover/io/scene.h"
#include "cover/solid/parallel.h"

namespace {

using bench::arg;
using bench::Clock;
using bench::K;
using bench::Mesh;
using bench::since;
using bench::Tree;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr,
                 "usage: compare_cgal MESH [--points N] [--brute N] [--rays N] [--threads T] "
                 "[--seed S] [--repeat R]\n");
    return 2;
  }
  const std::string path = argv[1];
  const long n_points = arg(argc, argv, "--points", 1000000);
  const long n_brute = arg(argc, argv, "--brute", 100000);
  const long n_rays = arg(argc, argv, "--rays", 100000);
  const int threads = static_cast<int>(arg(argc, argv, "--threads", 2));
  const auto seed = static_cast<uint64_t>(arg(argc, argv, "--seed", 1));

  cover::Solid solid;
  try {
    solid = cover::load_input(path).solid;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "compare_cgal: %s\n", e.what());
    return 2;
  }
  Mesh mesh;
  if (!CGAL::IO::read_polygon_mesh(path, mesh)) {
    std::fprintf(stderr, "CGAL cannot read %s\n", path.c_str());
    return 2;
  }
  const cover::Bbox box = solid.bbox();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(box.min.x, box.max.x), uy(box.min.y, box.max.y),
      uz(box.min.z, box.max.z);
  std::vector<cover::Vec3> pts(static_cast<size_t>(n_points));
  for (auto& p : pts) p = {ux(rng), uy(rng), uz(rng)};

  const int repeat = static_cast<int>(std::max(1L, arg(argc, argv, "--repeat", 3)));
  std::vector<cover::PointClass> ours;
  std::vector<CGAL::Bounded_side> theirs(pts.size());
  std::vector<double> cover_builds, cover_totals, cgal_totals;
  for (int rep = 0; rep < repeat; ++rep) {
    {  // Cover: BVH build + classification on `threads` threads.
      cover::ThreadLimit limit(threads);
      const auto t0 = Clock::now();
      const cover::Prepared prepared(solid);
      prepared.bvh();
      cover_builds.push_back(since(t0));
      ours = cover::classify(prepared, pts);
      cover_totals.push_back(since(t0));
    }
    // CGAL: tree build + queries on one thread.
    const auto t1 = Clock::now();
    CGAL::Side_of_triangle_mesh<Mesh, K> side(mesh);
    for (size_t i = 0; i < pts.size(); ++i)
      theirs[i] = side(K::Point_3(pts[i].x, pts[i].y, pts[i].z));
    cgal_totals.push_back(since(t1));
  }
  const double cover_build = median(cover_builds), cover_total = median(cover_totals),
               cgal_total = median(cgal_totals);

  long disagree = 0, boundary = 0, inside = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    if (theirs[i] == CGAL::ON_BOUNDARY) {
      ++boundary;
      continue;
    }
    const bool in = theirs[i] == CGAL::ON_BOUNDED_SIDE;
    inside += in;
    disagree += in != (ours[i] == cover::PointClass::kInside) ||
                (ours[i] != cover::PointClass::kInside && ours[i] != cover::PointClass::kOutside);
  }
  // Cover BVH vs brute force on the first n_brute points.
  const size_t nb = std::min(pts.size(), static_cast<size_t>(n_brute));
  const auto t2 = Clock::now();
  const auto brute = cover::classify_brute_force(solid, std::span(pts.data(), nb));
  const double brute_time = since(t2);
  long brute_disagree = 0;
  for (size_t i = 0; i < nb; ++i) brute_disagree += brute[i] != ours[i];

  // Rays: random origins on a sphere around the box, aimed at random points inside it.
  std::vector<cover::Ray> rays(static_cast<size_t>(n_rays));
  const cover::Vec3 c = 0.5 * (box.min + box.max);
  const double r = std::sqrt(cover::dot(box.max - box.min, box.max - box.min));
  std::normal_distribution<double> nd;
  for (auto& ray : rays) {
    cover::Vec3 u{nd(rng), nd(rng), nd(rng)};
    u = (r / std::sqrt(cover::dot(u, u))) * u;
    ray.origin = c + u;
    ray.dir = cover::Vec3{ux(rng), uy(rng), uz(rng)} - ray.origin;
  }
  double cover_rays, cgal_rays;
  long ray_hits_ours = 0, ray_hits_cgal = 0, ray_disagree = 0;
  std::vector<double> t_ours(rays.size(), -1);
  {
    cover::ThreadLimit limit(1);
    const auto t3 = Clock::now();
    const cover::Bvh bvh(solid);
    for (size_t i = 0; i < rays.size(); ++i) {
      const auto res = cover::cast(bvh, solid.tree, solid.leaves.size(), rays[i]);
      const auto f = cover::first_hit(bvh, res);
      if (f.hit) t_ours[i] = f.t;
    }
    cover_rays = since(t3);
  }
  // The same rays through the batch cast() (one call, 1 thread): the API for many rays.
  double cover_rays_batch;
  long batch_disagree = 0;
  {
    cover::ThreadLimit limit(1);
    const auto t5 = Clock::now();
    const cover::Prepared prepared(solid);
    const cover::Bvh& bvh = prepared.bvh();
    const std::vector<cover::RayResult> all = cover::cast(prepared, rays);
    for (size_t i = 0; i < rays.size(); ++i) {
      const auto f = cover::first_hit(bvh, all[i]);
      batch_disagree += (f.hit ? f.t : -1) != t_ours[i];
    }
    cover_rays_batch = since(t5);
  }
  const auto t4 = Clock::now();
  Tree tree(faces(mesh).first, faces(mesh).second, mesh);
  tree.accelerate_distance_queries();
  std::vector<double> t_cgal(rays.size(), -1);
  for (size_t i = 0; i < rays.size(); ++i) {
    const auto& o = rays[i].origin;
    const auto& d = rays[i].dir;
    const K::Ray_3 ray(K::Point_3(o.x, o.y, o.z), K::Vector_3(d.x, d.y, d.z));
    if (const auto hit = tree.first_intersection(ray)) {
      if (const K::Point_3* p = boost::get<K::Point_3>(&hit->first))
        t_cgal[i] = (p->x() - o.x) * d.x + (p->y() - o.y) * d.y + (p->z() - o.z) * d.z;
    }
  }
  cgal_rays = since(t4);
  for (size_t i = 0; i < rays.size(); ++i) {
    const cover::Vec3& d = rays[i].dir;
    const double dd = cover::dot(d, d);
    ray_hits_ours += t_ours[i] >= 0;
    ray_hits_cgal += t_cgal[i] >= 0;
    if ((t_ours[i] >= 0) != (t_cgal[i] >= 0)) {
      ++ray_disagree;
    } else if (t_ours[i] >= 0 && std::abs(t_ours[i] - t_cgal[i] / dd) > 1e-9 * (1 + t_ours[i])) {
      ++ray_disagree;
    }
  }

  std::printf("{\"mesh\": \"%s\", \"triangles\": %zu, \"points\": %ld, \"threads\": %d,\n",
              path.c_str(), solid.face_count(), n_points, threads);
  std::printf(
      " \"cover_bvh_build_s\": %.4f, \"cover_classify_total_s\": %.4f, "
      "\"cgal_side_total_s\": %.4f, \"speedup\": %.2f,\n",
      cover_build, cover_total, cgal_total, cgal_total / cover_total);
  std::printf(" \"inside\": %ld, \"cgal_on_boundary\": %ld, \"disagreements_vs_cgal\": %ld,\n",
              inside, boundary, disagree);
  std::printf(" \"brute_points\": %zu, \"brute_s\": %.3f, \"disagreements_vs_brute\": %ld,\n", nb,
              brute_time, brute_disagree);
  std::printf(
      " \"rays\": %ld, \"cover_rays_s\": %.4f, \"cgal_rays_s\": %.4f, \"ray_speedup\": %.2f, "
      "\"hits_cover\": %ld, \"hits_cgal\": %ld, \"ray_disagreements\": %ld,\n",
      n_rays, cover_rays, cgal_rays, cgal_rays / cover_rays, ray_hits_ours, ray_hits_cgal,
      ray_disagree);
  std::printf(
      " \"cover_rays_batch_s\": %.4f, \"ray_batch_speedup\": %.2f, "
      "\"batch_vs_single_disagreements\": %ld}\n",
      cover_rays_batch, cgal_rays / cover_rays_batch, batch_disagree);
  return disagree == 0 && brute_disagree == 0 && batch_disagree == 0 ? 0 : 1;
}
