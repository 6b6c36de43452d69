// `cover evaluate --cells N` against plain `cover evaluate` (docs/benchmarks.md): for each scene
// and N = 2, 4, 8, the median wall time of Model::evaluate() and of Model::evaluate_cells(N)
// (the same evaluation, then the cut into N³ cells and the gluing), interleaved A/B runs, and
// the faces the caps add. The cells' cube is the evaluated result's box made cubic with 1 %
// margin per side (`--bounds`), so that every N really cuts the solid (the default cube of
// `voxelize` leaves one empty cell of margin per side). Usage: cells_bench [RUNS] (default 5);
// prints a Markdown table.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cover/model/model.h"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

struct Scene {
  std::string name;
  cover::Model model;
};

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  std::vector<Scene> scenes;
  scenes.push_back(
      {"box − sphere(64) ∪ cylinder(48)",
       (cover::box({-1, -1, -1}, {1, 1, 1}) - cover::sphere({0.4, 0.3, 0.2}, 1.1, 64)) |
           cover::cylinder({-1.5, 0, 0}, {1.5, 0.1, 0.2}, 0.4, 48)});
  scenes.push_back({"sphere(256) ∩ box", cover::sphere({0, 0, 0}, 1, 256) &
                                             cover::box({-0.9, -0.8, -0.7}, {0.9, 0.8, 0.7})});
  std::printf(
      "| scene | evaluated faces | N | pieces | cap faces | glued faces | evaluate s | "
      "evaluate --cells s | of which cut s | glue s | repair s | collapsed | contacts left |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Scene& s : scenes) {
    for (int n : {2, 4, 8}) {
      const cover::Bbox box = cover::face_bbox(s.model.evaluate().mesh);
      const double ext =
          std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z});
      const cover::VoxelBounds cube{box.min - cover::Vec3{0.01 * ext, 0.01 * ext, 0.01 * ext},
                                    1.02 * ext};
      std::vector<double> plain, cells, cut, glue, repair;
      cover::CellsEvaluation last;
      size_t faces = 0;
      for (int r = 0; r < runs; ++r) {
        auto t = std::chrono::steady_clock::now();
        faces = s.model.evaluate().mesh.face_count();
        plain.push_back(seconds_since(t));
        t = std::chrono::steady_clock::now();
        last = s.model.evaluate_cells(n, cube);
        cells.push_back(seconds_since(t));
        cut.push_back(last.cells.cut_seconds);
        glue.push_back(last.cells.glue_seconds);
        repair.push_back(last.cells.repair_seconds);
      }
      std::printf(
          "| %s | %zu | %d | %zu | %lld | %zu | %.3f | %.3f | %.3f | %.3f | %.3f | %lld | %lld |\n",
          s.name.c_str(), faces, n, last.cells.pieces.size(),
          static_cast<long long>(last.cells.cap_faces), last.cells.glued.face_count(),
          median(plain), median(cells), median(cut), median(glue), median(repair),
          static_cast<long long>(last.cells.collapsed_edges),
          static_cast<long long>(last.cells.rounding_contacts));
      std::fflush(stdout);
    }
  }
  return 0;
}
