// Open meshes by the generalized winding number (covering/gwn.h), issue 23 item 5:
//   classify() of 1,000,000 uniform points in the box against open meshes of about 10k, 100k and
//   1M triangles (holes punched: every 50th face dropped) — bunny00 (libcgal-demo) and the bumpy
//   sphere of bench_models.h — against the same closed mesh (the exact path, grid on), and
//   against a brute-force C++ solid-angle sum over every triangle (on a subset, scaled to 1M);
//   Model::voxelize at 256³ of the open 100k-triangle mesh.
// Usage: open_classify [BUNNY.off] [--threads N] (default: 2). Wall-clock seconds, median of 5
// interleaved rounds; the open mesh is also classified with the grid off (the per-point path,
// checked to give the same classes).
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench_models.h"
#include "cover/covering/classify.h"
#include "cover/covering/gwn.h"
#include "cover/io/scene.h"
#include "cover/model/model.h"

namespace {

using Clock = std::chrono::steady_clock;

template <typename F>
double median_seconds(F&& f, int runs = 3) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = Clock::now();
    f();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

/// Every 50th face dropped: about 2% of the surface missing, in holes all over it.
cover::PolygonMesh punched(const cover::PolygonMesh& m) {
  cover::PolygonMesh out;
  out.vertices = m.vertices;
  for (size_t f = 0; f < m.face_count(); ++f)
    if (f % 50 != 17) out.add_face(m.face(f));
  return out;
}

cover::Model leaf(cover::PolygonMesh m, const std::string& name) {
  std::vector<std::string> warnings;
  return cover::Model(cover::prepare_leaf(std::move(m), name, name, {}, warnings));
}

void row(const std::string& name, const cover::PolygonMesh& closed_mesh) {
  const cover::Model closed = leaf(closed_mesh, name);
  const cover::Model open = leaf(punched(closed_mesh), name + " (holes)");
  const std::vector<cover::Vec3> pts = bench::random_points(closed.solid(), 1'000'000, 7);
  closed.bvh();
  open.bvh();
  open.gwn();
  // Interleaved rounds: closed, open (grid cells settled by the cones' bound), and open with
  // the grid off (every point through the closure: the per-point path); medians of 5.
  cover::ClassifyOptions per_point;
  per_point.grid_min_points = SIZE_MAX;
  std::vector<double> tc, to, tp;
  std::vector<cover::PointClass> co, cp;
  for (int round = 0; round < 5; ++round) {
    tc.push_back(median_seconds([&] { (void)closed.classify(pts); }, 1));
    to.push_back(median_seconds([&] { co = open.classify(pts); }, 1));
    tp.push_back(median_seconds([&] { cp = open.classify(pts, per_point); }, 1));
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  const double t_closed = median(tc), t_open = median(to), t_point = median(tp);
  if (co != cp) std::printf("MISMATCH between the grid and the per-point path\n");
  // Brute force: every triangle for every point (the tree's triangles, direct sum), on a subset
  // of about 1e8 triangle visits, one thread, scaled to 1M points.
  const cover::GwnTree& tree = open.gwn()->trees[0];
  const size_t subset = std::max<size_t>(20, std::min<size_t>(20000, 1e8 / tree.tris.size()));
  size_t agree = 0;
  const double t_brute = median_seconds(
      [&] {
        agree = 0;
        for (size_t i = 0; i < subset; ++i)
          agree += (std::abs(cover::generalized_winding_direct(tree, pts[i]).w) > 0.5) ==
                   (co[i] == cover::PointClass::kInside);
      },
      1);
  std::printf(
      "| %s | %zu | %zu | %.3f | %.3f | %.1fx | %.3f | %.1fx | %.0f (%zu pts, 1 thread, scaled) | "
      "%zu/%zu |\n",
      name.c_str(), tree.tris.size(), open.gwn()->closures[0].cone.tris.size(), t_closed, t_open,
      t_open / t_closed, t_point, t_point / t_closed, t_brute * 1e6 / subset, subset, agree,
      subset);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string bunny;
  int threads = 2;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--threads") && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else
      bunny = argv[i];
  }
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
  std::printf("threads %d; seconds, median of 5 interleaved rounds (brute force: one run)\n\n",
              threads);
  std::printf(
      "| mesh | open triangles | cap triangles | closed classify 1M | open classify 1M | "
      "open / closed | open, grid off | grid off / closed | brute force 1M (s) | "
      "brute agrees |\n|---|---|---|---|---|---|---|---|---|---|\n");
  std::fflush(stdout);
  if (!bunny.empty()) {
    const cover::Solid s = cover::load_input(bunny).solid;
    row("bunny00", cover::leaf_mesh(s, 0));
  }
  for (int64_t n : {10'000, 100'000, 1'000'000})
    row("bumpy sphere " + std::to_string(n / 1000) + "k",
        bench::bumpy_sphere(bench::segments_for(n)));
  // Voxelize 256³ of the open 100k mesh.
  const cover::Model open = leaf(punched(bench::bumpy_sphere(bench::segments_for(100'000))), "v");
  const cover::Model closed = leaf(bench::bumpy_sphere(bench::segments_for(100'000)), "c");
  cover::VoxelizeOptions vo;
  vo.resolution = 256;
  open.gwn();
  closed.bvh();
  const double t_vc = median_seconds([&] { (void)closed.voxelize(vo); }, 1);
  const double t_vo = median_seconds([&] { (void)open.voxelize(vo); }, 1);
  std::printf("\nvoxelize 256^3, bumpy sphere 100k: closed %.3f s, open (holes) %.3f s (%.1fx)\n",
              t_vc, t_vo, t_vo / t_vc);
}
