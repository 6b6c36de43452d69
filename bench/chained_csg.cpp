// Chained CSG in the facade: `m = m | sphere_i` in a loop over n = 200, 400, 800 spheres (the
// loop a CAD script writes), against a balanced tree of the same unions (pairwise rounds) and
// against an eager operator that builds every intermediate solid (Model(unite({a.solid(),
// b.solid()})) at each step). docs/benchmarks.md "Chained CSG in the facade". Each variant builds
// its Model and then the solid and its BVH (the first query's work); wall-clock seconds, median
// of 3 interleaved rounds. The spheres (32 segments, 960 triangles each) lie along a helix.
// Usage: chained_csg [--threads N] (default: 2).
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "cover/model/model.h"

namespace {

using Clock = std::chrono::steady_clock;
using cover::Model;

std::vector<Model> spheres(int n) {
  std::vector<Model> out;
  for (int i = 0; i < n; ++i)
    out.push_back(cover::sphere({std::cos(0.3 * i), std::sin(0.3 * i), 0.01 * i}, 0.4));
  return out;
}

Model chained(const std::vector<Model>& parts) {
  Model m;
  for (const Model& p : parts) m = m | p;
  return m;
}

Model eager(const std::vector<Model>& parts) {
  Model m = parts[0];
  for (size_t i = 1; i < parts.size(); ++i) m = Model(cover::unite({m.solid(), parts[i].solid()}));
  return m;
}

Model balanced(std::vector<Model> parts) {
  while (parts.size() > 1) {
    std::vector<Model> next;
    for (size_t i = 0; i + 1 < parts.size(); i += 2) next.push_back(parts[i] | parts[i + 1]);
    if (parts.size() % 2) next.push_back(parts.back());
    parts = std::move(next);
  }
  return parts[0];
}

template <typename F>
double seconds(F&& build) {
  const auto t0 = Clock::now();
  const Model m = build();
  m.bvh();
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 2;
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) threads = std::stoi(argv[++i]);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  std::printf("| spheres | chained (lazy) s | balanced s | chained / balanced | eager chain s |\n");
  std::printf("|---:|---:|---:|---:|---:|\n");
  for (int n : {200, 400, 800}) {
    const std::vector<Model> parts = spheres(n);
    std::vector<double> c, b, e;
    for (int round = 0; round < 3; ++round) {
      c.push_back(seconds([&] { return chained(parts); }));
      b.push_back(seconds([&] { return balanced(parts); }));
      e.push_back(seconds([&] { return eager(parts); }));
    }
    for (auto* v : {&c, &b, &e}) std::sort(v->begin(), v->end());
    std::printf("| %d | %.3f | %.3f | %.2f | %.3f |\n", n, c[1], b[1], c[1] / b[1], e[1]);
  }
  return 0;
}
