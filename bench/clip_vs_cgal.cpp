// Cover's exact plane clip and patch (both halves) vs CGAL::Polygon_mesh_processing::clip with
// clip_volume = true (two clips on copies of a Surface_mesh, one per half), in one process.
// Both start from the same in-memory polygon mesh (file reading excluded for both); each side's
// conversion into its own structure is included: Cover builds its half-edge mesh and writes two
// polygon meshes, CGAL builds the Surface_mesh (once per plane) and copies it for each half.
// Per mesh: an axis plane through the box centre, an oblique one, and one through a vertex.
// Timings are the median of --repeat runs (default 3), interleaved; Cover runs on --threads T
// (default 1, like CGAL). Also printed: Cover's time in the cap (exact points, rings, caps).
// Usage: clip_vs_cgal MESH... [--repeat R] [--threads T]
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/clip.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "cover/brep/clip.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using bench::Clock;
using bench::since;
namespace PMP = CGAL::Polygon_mesh_processing;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Mesh to_surface_mesh(const cover::PolygonMesh& m) {
  Mesh s;
  std::vector<Mesh::Vertex_index> v;
  v.reserve(m.vertices.size());
  for (const cover::Vec3& p : m.vertices) v.push_back(s.add_vertex(K::Point_3(p.x, p.y, p.z)));
  std::vector<Mesh::Vertex_index> f;
  for (size_t i = 0; i < m.face_count(); ++i) {
    f.clear();
    for (uint32_t k : m.face(i)) f.push_back(v[k]);
    s.add_face(f);
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> paths;
  int repeat = 3, threads = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
    } else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else {
      paths.push_back(argv[i]);
    }
  }
  if (paths.empty()) {
    std::fprintf(stderr, "usage: clip_vs_cgal MESH... [--repeat R] [--threads T]\n");
    return 2;
  }
  cover::ThreadLimit limit(threads);
  std::printf("%-14s %7s %-8s %10s %10s %8s %9s %6s %12s\n", "mesh", "faces", "plane", "cover ms",
              "cgal ms", "ratio", "cap ms", "rings", "vol rel diff");
  std::vector<double> ratios;
  for (const std::string& path : paths) {
    const cover::PolygonMesh mesh = cover::read_mesh(path);
    const cover::Bbox b = cover::face_bbox(mesh);
    const cover::Vec3 c = 0.5 * (b.min + b.max);
    const cover::Vec3 oblique{1, 2, 3};
    const cover::Vec3& v = mesh.vertices[mesh.vertices.size() / 2];
    const struct {
      const char* name;
      cover::brep::Plane plane;
    } planes[] = {{"axis", {{1, 0, 0}, c.x}},
                  {"oblique", {oblique, cover::dot(oblique, c)}},
                  {"vertex", {{0, 0, 1}, v.z}}};
    std::string name = path.substr(path.find_last_of('/') + 1);
    name = name.substr(0, name.find('.'));
    for (const auto& [plane_name, plane] : planes) {
      std::vector<double> tc, tg, tcap;
      double cover_volume = 0, cgal_volume = 0;
      int64_t rings = 0;
      for (int r = 0; r < repeat; ++r) {
        auto t0 = Clock::now();
        const cover::brep::ClipResult res = cover::brep::clip(mesh, plane);
        tc.push_back(since(t0));
        tcap.push_back(res.cap_seconds);
        rings = res.above.rings;
        cover_volume = cover::signed_volume(res.below.mesh);
        t0 = Clock::now();
        const Mesh sm = to_surface_mesh(mesh);
        Mesh below = sm, above = sm;
        const cover::Vec3 n = plane.normal;
        PMP::clip(below, K::Plane_3(n.x, n.y, n.z, -plane.offset),
                  CGAL::parameters::clip_volume(true));
        PMP::clip(above, K::Plane_3(-n.x, -n.y, -n.z, plane.offset),
                  CGAL::parameters::clip_volume(true));
        tg.push_back(since(t0));
        cgal_volume = CGAL::to_double(PMP::volume(below));
      }
      const double ratio = median(tg) / median(tc);
      ratios.push_back(ratio);
      std::printf("%-14s %7zu %-8s %10.2f %10.2f %7.1fx %9.2f %6lld %12.1e\n", name.c_str(),
                  mesh.face_count(), plane_name, 1e3 * median(tc), 1e3 * median(tg), ratio,
                  1e3 * median(tcap), static_cast<long long>(rings),
                  std::abs(cover_volume - cgal_volume) / std::abs(cgal_volume));
    }
  }
  std::sort(ratios.begin(), ratios.end());
  std::printf("ratio (CGAL time / Cover time): min %.1fx, median %.1fx, max %.1fx\n",
              ratios.front(), ratios[ratios.size() / 2], ratios.back());
  return 0;
}
