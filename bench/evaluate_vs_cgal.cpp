// `cover evaluate` against CGAL corefinement, in one process on the same inputs:
//   Cover: evaluate(solid) (boolean/evaluate.h) on the concatenated non-evaluated solid, with and
//          without the per-leaf self-intersection check that the CLI runs; all threads.
//   CGAL:  PMP::corefine_and_compute_union / _intersection / _difference (Epick; serial), nested
//          operations folded bottom-up; input copies are made outside the timings.
// Every mesh is transformed once, by Cover, before either side sees it (same doubles). Median of
// 3 runs each; the table prints seconds, the ratio Cover / CGAL, and both volumes, then Cover's
// time per step (EvaluateResult::seconds) of the median unchecked run.
// Usage: evaluate_vs_cgal MESH_FOLDER [CASE...]   (libcgal-demo data/meshes; CASE: 1-based
// indices of the cases to run, all by default)
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "cover/boolean/evaluate.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/transform.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;
using Clock = std::chrono::steady_clock;

std::filesystem::path g_folder;

struct Operand {
  cover::Solid solid;
  Mesh mesh;
};

/// `file` scaled into a cube of side 2·size around `centre`, rotated by `degrees` about `axis`.
Operand operand(const std::string& file, cover::Vec3 centre, double size, double degrees) {
  cover::PolygonMesh m = cover::read_mesh(g_folder / file);
  cover::apply_transform(
      cover::Transform::fit(cover::face_bbox(m), centre, size, {0.3, 1, 0.2}, degrees), m);
  Operand o{cover::make_leaf(m, file), {}};
  std::vector<Mesh::Vertex_index> vs;
  for (const cover::Vec3& p : m.vertices)
    vs.push_back(o.mesh.add_vertex(K::Point_3(p.x, p.y, p.z)));
  for (size_t f = 0; f < m.face_count(); ++f) {
    auto face = m.face(f);
    o.mesh.add_face(vs[face[0]], vs[face[1]], vs[face[2]]);
  }
  return o;
}

enum class Op { kUnion, kIntersection, kDifference };

Mesh corefine(Mesh a, Mesh b, Op op, double& seconds) {
  Mesh out;
  const auto t = Clock::now();
  if (op == Op::kUnion) PMP::corefine_and_compute_union(a, b, out);
  if (op == Op::kIntersection) PMP::corefine_and_compute_intersection(a, b, out);
  if (op == Op::kDifference) PMP::corefine_and_compute_difference(a, b, out);
  seconds += std::chrono::duration<double>(Clock::now() - t).count();
  return out;
}

cover::Solid combine(const cover::Solid& a, const cover::Solid& b, Op op) {
  if (op == Op::kUnion) return cover::unite({a, b});
  if (op == Op::kIntersection) return cover::intersect({a, b});
  return cover::subtract({a, b});
}

double median3(const std::function<double()>& run) {
  double t[3] = {run(), run(), run()};
  std::sort(t, t + 3);
  return t[1];
}

/// The run whose total time is the median of 3.
cover::EvaluateResult median_run(const cover::Solid& solid, const cover::EvaluateOptions& o,
                                 double& seconds) {
  std::vector<std::pair<double, cover::EvaluateResult>> runs;
  for (int i = 0; i < 3; ++i) {
    const auto t = Clock::now();
    cover::EvaluateResult r = cover::evaluate(solid, o);
    runs.emplace_back(std::chrono::duration<double>(Clock::now() - t).count(), std::move(r));
  }
  std::sort(runs.begin(), runs.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  seconds = runs[1].first;
  return std::move(runs[1].second);
}

struct Case {
  std::string name;
  cover::Solid solid;
  std::function<Mesh(double&)> cgal;  ///< the corefined result; adds its corefinement time
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: evaluate_vs_cgal MESH_FOLDER\n");
    return 2;
  }
  g_folder = argv[1];
  std::vector<size_t> wanted;
  for (int i = 2; i < argc; ++i) wanted.push_back(std::stoul(argv[i]));
  std::vector<Case> cases;
  {
    const Operand a = operand("bunny00.off", {0, 0, 0}, 1.0, 0);
    const Operand b = operand("elephant.off", {0.35, 0.2, 0.1}, 0.8, 25);
    cases.push_back({"bunny00 − elephant", combine(a.solid, b.solid, Op::kDifference),
                     [a, b](double& s) { return corefine(a.mesh, b.mesh, Op::kDifference, s); }});
  }
  {
    const Operand a = operand("armadillo.off", {0, 0, 0}, 1.0, 10);
    const Operand b = operand("knot1.off", {0.1, -0.2, 0.05}, 1.0, 40);
    cases.push_back({"armadillo ∩ knot1", combine(a.solid, b.solid, Op::kIntersection),
                     [a, b](double& s) { return corefine(a.mesh, b.mesh, Op::kIntersection, s); }});
  }
  {
    const Operand a = operand("cheese.off", {0, 0, 0}, 1.0, 0);
    const Operand b = operand("fandisk.off", {0.3, 0.1, -0.2}, 0.9, 50);
    cases.push_back({"cheese ∪ fandisk", combine(a.solid, b.solid, Op::kUnion),
                     [a, b](double& s) { return corefine(a.mesh, b.mesh, Op::kUnion, s); }});
  }
  {
    const Operand a = operand("bunny00.off", {0, 0, 0}, 1.0, 0);
    const Operand b = operand("knot1.off", {0.2, 0.3, 0}, 0.7, 60);
    const Operand c = operand("elephant.off", {0.9, -0.3, 0.2}, 0.9, 15);
    const Operand d = operand("fandisk.off", {0.8, -0.2, 0.3}, 0.9, 75);
    cases.push_back({"(bunny00 − knot1) ∪ (elephant ∩ fandisk)",
                     cover::unite({combine(a.solid, b.solid, Op::kDifference),
                                   combine(c.solid, d.solid, Op::kIntersection)}),
                     [a, b, c, d](double& s) {
                       const Mesh l = corefine(a.mesh, b.mesh, Op::kDifference, s);
                       const Mesh r = corefine(c.mesh, d.mesh, Op::kIntersection, s);
                       return corefine(l, r, Op::kUnion, s);
                     }});
  }
  std::printf("%-42s %9s %9s %9s %8s %8s %16s %16s\n", "expression", "faces in", "cover s",
              "+check s", "CGAL s", "ratio", "cover volume", "CGAL volume");
  std::vector<std::pair<std::string, cover::EvaluatePhases>> phases;
  for (size_t i = 0; i < cases.size(); ++i) {
    if (!wanted.empty() && std::find(wanted.begin(), wanted.end(), i + 1) == wanted.end()) continue;
    const Case& c = cases[i];
    cover::EvaluateOptions fast;
    fast.check_leaves = false;
    cover::EvaluatePhases last_phases;  // of the last run
    fast.phases = &last_phases;
    double t_cover = 0;
    const cover::EvaluateResult result = median_run(c.solid, fast, t_cover);
    phases.emplace_back(c.name, last_phases);
    const double t_checked = median3([&] {
      const auto t = Clock::now();
      cover::evaluate(c.solid);
      return std::chrono::duration<double>(Clock::now() - t).count();
    });
    Mesh out;
    const double t_cgal = median3([&] {
      double s = 0;
      out = c.cgal(s);
      return s;
    });
    std::printf("%-44s %9zu %9.3f %9.3f %8.3f %8.2f %16.12g %16.12g\n", c.name.c_str(),
                c.solid.face_count(), t_cover, t_checked, t_cgal, t_cover / t_cgal, result.volume,
                CGAL::to_double(PMP::volume(out)));
  }
  std::printf(
      "\nCover seconds per step (median unchecked run)\n%-42s %8s %8s %8s %8s %8s %8s %8s\n",
      "expression", "triang", "pairs", "inters", "split", "ident", "select", "assemb");
  for (const auto& [name, s] : phases)
    std::printf("%-44s %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f\n", name.c_str(), s.triangulate,
                s.pairs, s.intersect, s.split, s.identify, s.select, s.assemble);
  return 0;
}
