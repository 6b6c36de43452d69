// Point-set classification against CGAL's Poisson surface reconstruction (one process, one
// machine, the same oriented points and the same query points):
//   cover  cover::point_set (points/point_set.h: kNN, tangent-plane Voronoi areas, dipole
//          triangles) as a Model, its BVH and generalized-winding-number trees built (build
//          time), then Model::classify of the queries (query time); inside = not kOutside
//   cgal   CGAL::Poisson_reconstruction_function<Epick> over the same points and normals,
//          compute_implicit_function() (Delaunay refinement + the Poisson equation by Eigen's
//          ConjugateGradient, CGAL's default Eigen_solver_traits; build time), then the function
//          at every query point (query time); inside where the value is < 0 (CGAL shifts the
//          function to 0 at the input points' median and negative inside; checked below on a
//          sampled sphere's centre). The build is sequential; the queries run on --threads
//          threads, each with its own copy of the function (the copies share the triangulation
//          and CGAL's thread-safe barycentric cache; each has its own locate hint)
// Data: an oriented point cloud sampled from a closed mesh (MESH): --samples-a and --samples-b
// points, area-weighted on the mesh's triangles (fans of its faces; mt19937_64, --seed), each
// with its triangle's unit normal. Queries: --queries points uniform in the mesh's box grown by
// 5% per side (mt19937_64, --seed + 1).
// Reference: cover::load(MESH).classify of the queries, exact; a point counts inside unless it is
// kOutside. Agreement: the fraction of queries whose inside/outside equals the reference's, over
// all queries and over those farther than 1% of the box diagonal from the mesh
// (cover::nearest_distances on the mesh's BVH, in doubles).
// Timing: wall clock, --rounds rounds, each Cover then CGAL at each cloud size, interleaved;
// min and median, with the process's CPU seconds (every thread; steadier than wall clock when other
// load shares the machine). 2 threads by default (tbb::global_control for Cover; CGAL's build is
// serial).
// Usage: points_vs_poisson MESH [--samples-a N] [--samples-b N] [--queries N] [--seed S]
//                               [--threads T] [--rounds R] [--neighbours K]
#include <CGAL/Eigen_solver_traits.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Poisson_reconstruction_function.h>
#include <CGAL/property_map.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bench_cli.h"
#include "cover/covering/distance.h"
#include "cover/io/mesh_io.h"
#include "cover/model/model.h"
#include "cover/points/point_set.h"
#include "cover/solid/polygon_mesh.h"

namespace {

using bench::Clock;
using bench::since;
using cover::PointClass;
using cover::Vec3;

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using PointWithNormal = std::pair<Point, Vector>;
using Poisson = CGAL::Poisson_reconstruction_function<Kernel>;

/// CPU seconds of the whole process (every thread): less sensitive than wall clock to other load
/// on a shared machine.
double cpu_now() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Cloud {
  std::vector<Vec3> points;
  std::vector<Vec3> normals;
};

double norm(Vec3 a) { return std::sqrt(cover::dot(a, a)); }

/// `n` points on the mesh's triangles (fans of its faces), area-weighted, with the triangles'
/// unit normals.
Cloud sample(const cover::PolygonMesh& mesh, size_t n, uint64_t seed) {
  std::vector<std::array<uint32_t, 3>> tris;
  std::vector<double> cumulative;
  double total = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    for (size_t k = 1; k + 1 < loop.size(); ++k) {
      const std::array<uint32_t, 3> t{loop[0], loop[k], loop[k + 1]};
      const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
      const double area = norm(cover::cross(b - a, c - a)) / 2;
      if (!(area > 0)) continue;
      total += area;
      tris.push_back(t);
      cumulative.push_back(total);
    }
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  Cloud cloud;
  cloud.points.reserve(n);
  cloud.normals.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const double r = u(rng) * total;
    const size_t t =
        std::min(static_cast<size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), r) -
                                     cumulative.begin()),
                 tris.size() - 1);
    const Vec3 &a = mesh.vertices[tris[t][0]], &b = mesh.vertices[tris[t][1]],
               &c = mesh.vertices[tris[t][2]];
    const double s = std::sqrt(u(rng)), w = u(rng);
    const double wa = 1 - s, wb = s * (1 - w), wc = s * w;
    cloud.points.push_back({wa * a.x + wb * b.x + wc * c.x, wa * a.y + wb * b.y + wc * c.y,
                            wa * a.z + wb * b.z + wc * c.z});
    const Vec3 nrm = cover::cross(b - a, c - a);
    const double len = norm(nrm);
    cloud.normals.push_back({nrm.x / len, nrm.y / len, nrm.z / len});
  }
  return cloud;
}

std::vector<PointWithNormal> to_cgal(const Cloud& cloud) {
  std::vector<PointWithNormal> out;
  out.reserve(cloud.points.size());
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const Vec3 &p = cloud.points[i], &n = cloud.normals[i];
    out.emplace_back(Point(p.x, p.y, p.z), Vector(n.x, n.y, n.z));
  }
  return out;
}

/// The function built from the points (constructor + compute_implicit_function); nullptr when the
/// solver fails.
std::unique_ptr<Poisson> poisson_build(const std::vector<PointWithNormal>& pwn) {
  auto f = std::make_unique<Poisson>(pwn.begin(), pwn.end(),
                                     CGAL::First_of_pair_property_map<PointWithNormal>(),
                                     CGAL::Second_of_pair_property_map<PointWithNormal>());
  if (!f->compute_implicit_function()) return nullptr;
  return f;
}

/// Inside (value < 0) per query, on `threads` threads, each with its own copy of the function.
std::vector<uint8_t> poisson_inside(const Poisson& f, const std::vector<Vec3>& q, int threads) {
  std::vector<uint8_t> inside(q.size());
  auto work = [&](size_t b, size_t e) {
    const Poisson mine = f;  // own locate hint
    for (size_t i = b; i < e; ++i) inside[i] = mine(Point(q[i].x, q[i].y, q[i].z)) < 0;
  };
  std::vector<std::thread> pool;
  const size_t chunk = (q.size() + threads - 1) / threads;
  for (int t = 1; t < threads; ++t)
    pool.emplace_back(work, std::min(q.size(), t * chunk), std::min(q.size(), (t + 1) * chunk));
  work(0, std::min(q.size(), chunk));
  for (std::thread& th : pool) th.join();
  return inside;
}

std::vector<uint8_t> cover_inside(const std::vector<PointClass>& classes) {
  std::vector<uint8_t> inside(classes.size());
  for (size_t i = 0; i < classes.size(); ++i) inside[i] = classes[i] != PointClass::kOutside;
  return inside;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
double minimum(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

/// The sign conventions on a sphere of radius 1 sampled with outward normals: the function at
/// the centre (expected < 0) and at (3, 0, 0) (expected > 0); Cover's class at both.
void check_sign_convention(uint64_t seed, int neighbours) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, 1);
  Cloud sphere;
  for (int i = 0; i < 4000; ++i) {
    Vec3 p{g(rng), g(rng), g(rng)};
    const double len = norm(p);
    p = {p.x / len, p.y / len, p.z / len};
    sphere.points.push_back(p);
    sphere.normals.push_back(p);
  }
  const auto f = poisson_build(to_cgal(sphere));
  const std::vector<Vec3> probes{{0, 0, 0}, {3, 0, 0}};
  cover::PointSetOptions o;
  o.neighbours = neighbours;
  const auto classes = cover::point_set(sphere.points, sphere.normals, o).classify(probes);
  std::printf(
      "sign check, unit sphere (4000 points, outward normals): cgal f(centre) = %.6g, "
      "f(3,0,0) = %.6g; cover centre %s, (3,0,0) %s\n",
      f ? (*f)(Point(0, 0, 0)) : NAN, f ? (*f)(Point(3, 0, 0)) : NAN,
      std::string(cover::to_string(classes[0])).c_str(),
      std::string(cover::to_string(classes[1])).c_str());
}

struct Agreement {
  double all = 0, far = 0;  // fractions that agree
  size_t wrong = 0, far_wrong = 0, inside = 0;
};

Agreement agreement(const std::vector<uint8_t>& got, const std::vector<uint8_t>& ref,
                    const std::vector<uint8_t>& far) {
  size_t same = 0, far_n = 0, far_same = 0, inside = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    const bool s = got[i] == ref[i];
    same += s;
    far_n += far[i];
    far_same += far[i] && s;
    inside += got[i];
  }
  return {static_cast<double>(same) / got.size(), static_cast<double>(far_same) / far_n,
          got.size() - same, far_n - far_same, inside};
}

struct Side {
  std::vector<double> build, query, build_cpu, query_cpu;
  Agreement agree;
  std::string note;
};

std::string times(const std::vector<double>& v) {
  std::string s;
  char buf[32];
  for (double t : v) {
    std::snprintf(buf, sizeof buf, "%s%.3f", s.empty() ? "" : " ", t);
    s += buf;
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr,
                 "usage: points_vs_poisson MESH [--samples-a N] [--samples-b N] [--queries N] "
                 "[--seed S] [--threads T] [--rounds R] [--neighbours K]\n");
    return 2;
  }
  const std::string path = argv[1];
  const size_t samples_a = static_cast<size_t>(bench::arg(argc, argv, "--samples-a", 20000));
  const size_t samples_b = static_cast<size_t>(bench::arg(argc, argv, "--samples-b", 100000));
  const size_t nq = static_cast<size_t>(bench::arg(argc, argv, "--queries", 1000000));
  const uint64_t seed = static_cast<uint64_t>(bench::arg(argc, argv, "--seed", 1));
  const int threads = static_cast<int>(bench::arg(argc, argv, "--threads", 2));
  const int rounds = static_cast<int>(bench::arg(argc, argv, "--rounds", 3));
  const int neighbours = static_cast<int>(bench::arg(argc, argv, "--neighbours", 16));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  std::printf("threads %d (cover build and classify; cgal queries; cgal's build is serial)\n",
              threads);
  check_sign_convention(seed, neighbours);

  const cover::PolygonMesh mesh = cover::read_mesh(path);
  const cover::Model reference = cover::load(path);
  const cover::Bbox box = *reference.bounds();
  const Vec3 ext = box.max - box.min;
  const double diagonal = norm(ext);
  std::vector<Vec3> queries(nq);
  {
    std::mt19937_64 rng(seed + 1);
    std::uniform_real_distribution<double> ux(box.min.x - 0.05 * ext.x, box.max.x + 0.05 * ext.x),
        uy(box.min.y - 0.05 * ext.y, box.max.y + 0.05 * ext.y),
        uz(box.min.z - 0.05 * ext.z, box.max.z + 0.05 * ext.z);
    for (Vec3& q : queries) q = {ux(rng), uy(rng), uz(rng)};
  }
  auto t0 = Clock::now();
  const std::vector<uint8_t> ref = cover_inside(reference.classify(queries));
  const double ref_s = since(t0);
  t0 = Clock::now();
  const std::vector<double> dist = cover::nearest_distances(reference.bvh(), queries);
  const double dist_s = since(t0);
  std::vector<uint8_t> far(nq);
  size_t far_n = 0, ref_in = 0;
  for (size_t i = 0; i < nq; ++i) {
    far[i] = dist[i] > 0.01 * diagonal;
    far_n += far[i];
    ref_in += ref[i];
  }
  std::printf(
      "%s: %zu vertices, %zu faces; box diagonal %.6g; %zu queries, %zu inside the mesh (%.2f%%), "
      "%zu farther than 1%% of the diagonal (%.2f%%); reference classify %.3f s, distances "
      "%.3f s\n",
      path.c_str(), mesh.vertices.size(), mesh.face_count(), diagonal, nq, ref_in,
      100.0 * ref_in / nq, far_n, 100.0 * far_n / nq, ref_s, dist_s);

  const std::vector<size_t> sizes{samples_a, samples_b};
  std::vector<Cloud> clouds;
  std::vector<std::vector<PointWithNormal>> pwns;
  for (size_t k = 0; k < sizes.size(); ++k) {
    clouds.push_back(sample(mesh, sizes[k], seed + 2 + k));
    pwns.push_back(to_cgal(clouds.back()));
  }
  std::vector<Side> cover_side(sizes.size()), cgal_side(sizes.size());
  cover::PointSetOptions options;
  options.neighbours = neighbours;
  for (int round = 0; round < rounds; ++round)
    for (size_t k = 0; k < sizes.size(); ++k) {
      {
        Side& s = cover_side[k];
        double c0 = cpu_now();
        t0 = Clock::now();
        const cover::Model m = cover::point_set(clouds[k].points, clouds[k].normals, options);
        m.bvh();
        m.gwn();
        s.build.push_back(since(t0));
        s.build_cpu.push_back(cpu_now() - c0);
        c0 = cpu_now();
        t0 = Clock::now();
        const std::vector<PointClass> classes = m.classify(queries);
        s.query.push_back(since(t0));
        s.query_cpu.push_back(cpu_now() - c0);
        if (round == 0) {
          size_t boundary = 0;
          for (PointClass c : classes)
            boundary += c != PointClass::kOutside && c != PointClass::kInside;
          s.agree = agreement(cover_inside(classes), ref, far);
          s.note = std::to_string(boundary) + " on the boundary";
        }
        std::printf(
            "  round %d, %zu points: cover build %.3f s (cpu %.3f), classify %.3f s (cpu %.3f)\n",
            round, sizes[k], s.build.back(), s.build_cpu.back(), s.query.back(),
            s.query_cpu.back());
        std::fflush(stdout);
      }
      {
        Side& s = cgal_side[k];
        double c0 = cpu_now();
        t0 = Clock::now();
        const auto f = poisson_build(pwns[k]);
        s.build.push_back(since(t0));
        s.build_cpu.push_back(cpu_now() - c0);
        if (!f) {
          std::printf("  round %d, %zu points: cgal compute_implicit_function FAILED\n", round,
                      sizes[k]);
          s.note = "solver failed";
          s.query.push_back(NAN);
          s.query_cpu.push_back(NAN);
          continue;
        }
        c0 = cpu_now();
        t0 = Clock::now();
        const std::vector<uint8_t> inside = poisson_inside(*f, queries, threads);
        s.query.push_back(since(t0));
        s.query_cpu.push_back(cpu_now() - c0);
        if (round == 0) {
          s.agree = agreement(inside, ref, far);
          s.note = std::to_string(f->tr().number_of_vertices()) + " triangulation vertices";
        }
        std::printf(
            "  round %d, %zu points: cgal build %.3f s (cpu %.3f), evaluate %.3f s (cpu %.3f)\n",
            round, sizes[k], s.build.back(), s.build_cpu.back(), s.query.back(),
            s.query_cpu.back());
        std::fflush(stdout);
      }
    }

  std::printf(
      "\n| points | tool | build s min / median (runs) | build CPU s, median | query s min / "
      "median "
      "(runs) | query CPU s, median | inside | agree, all (wrong) | agree, far from surface "
      "(wrong) | note |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (size_t k = 0; k < sizes.size(); ++k)
    for (const Side* s : {&cover_side[k], &cgal_side[k]})
      std::printf(
          "| %zu | %s | %.3f / %.3f (%s) | %.3f | %.3f / %.3f (%s) | %.3f | %zu | %.4f%% (%zu) | "
          "%.4f%% (%zu) | %s |\n",
          sizes[k], s == &cover_side[k] ? "cover point_set" : "cgal Poisson", minimum(s->build),
          median(s->build), times(s->build).c_str(), median(s->build_cpu), minimum(s->query),
          median(s->query), times(s->query).c_str(), median(s->query_cpu), s->agree.inside,
          100 * s->agree.all, s->agree.wrong, 100 * s->agree.far, s->agree.far_wrong,
          s->note.c_str());
  return 0;
}
