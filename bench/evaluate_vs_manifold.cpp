// `cover evaluate` against native Manifold (elalish/manifold, TBB backend), side by side in one
// process, 2 threads each (cover::ThreadLimit; tbb::global_control).
//
// Inputs: every leaf mesh is transformed once (scaled, rotated, moved: the placements of
// bench/evaluate_vs_cgal.cpp and of the 10-leaf scene of bench/render_vs_cgal.cpp) and written as
// an OFF file with round-trip (%.17g) coordinates into a scratch folder, so both sides parse the
// same doubles. Then, per run, each side does what a process evaluating the expression does:
//   Cover:    cover::read_mesh per leaf, make_leaf + the CSG expression (build), evaluate() with
//             the CLI's default options (leaf self-intersection check on: that is the kernel),
//             write_mesh(.off).
//   Manifold: its own OFF parser (std::from_chars; Manifold has no mesh reader without assimp)
//             into MeshGL64 (doubles), Manifold(MeshGL64) per leaf (build), the booleans forced
//             by Status() (kernel), GetMeshGL64() and an OFF writer (std::to_chars, shortest
//             round-trip digits) (write).
// Runs are interleaved (Cover, Manifold, then Manifold, Cover, ...); the table gives medians of
// the whole process and of the kernel, their ratios Cover / Manifold, and both volumes.
// Usage: evaluate_vs_manifold MESH_FOLDER [--runs N] [--scratch DIR] [CASE...]
//        (libcgal-demo data/meshes; CASE: 1-based indices of the cases, all by default)
#include <manifold/manifold.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cover/boolean/evaluate.h"
#include "cover/io/mesh_io.h"
#include "cover/solid/parallel.h"
#include "cover/solid/transform.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct LeafSpec {
  const char* file;
  cover::Vec3 centre;
  double half_size;
  cover::Vec3 axis;
  double degrees;
};

enum class Op { kLeaf, kUnion, kIntersection, kDifference };

/// A CSG expression over the case's leaves. kDifference: first child minus the others.
struct Expr {
  Op op = Op::kLeaf;
  uint32_t leaf = 0;
  std::vector<Expr> kids;
};

Expr leaf(uint32_t i) { return {Op::kLeaf, i, {}}; }
Expr node(Op op, std::vector<Expr> kids) { return {op, 0, std::move(kids)}; }

struct Case {
  std::string name;
  std::vector<LeafSpec> leaves;
  Expr expr;
  std::vector<fs::path> files;  ///< the transformed leaves in the scratch folder
};

/// evaluate_vs_cgal's operand(): scaled into a cube of side 2·size, rotated about (0.3, 1, 0.2).
LeafSpec operand(const char* file, cover::Vec3 centre, double size, double degrees) {
  return {file, centre, size, {0.3, 1, 0.2}, degrees};
}

std::vector<Case> make_cases() {
  std::vector<Case> c;
  c.push_back({"bunny00 − elephant",
               {operand("bunny00.off", {0, 0, 0}, 1.0, 0),
                operand("elephant.off", {0.35, 0.2, 0.1}, 0.8, 25)},
               node(Op::kDifference, {leaf(0), leaf(1)}),
               {}});
  c.push_back({"armadillo ∩ knot1",
               {operand("armadillo.off", {0, 0, 0}, 1.0, 10),
                operand("knot1.off", {0.1, -0.2, 0.05}, 1.0, 40)},
               node(Op::kIntersection, {leaf(0), leaf(1)}),
               {}});
  c.push_back({"cheese ∪ fandisk",
               {operand("cheese.off", {0, 0, 0}, 1.0, 0),
                operand("fandisk.off", {0.3, 0.1, -0.2}, 0.9, 50)},
               node(Op::kUnion, {leaf(0), leaf(1)}),
               {}});
  c.push_back(
      {"(bunny00 − knot1) ∪ (elephant ∩ fandisk)",
       {operand("bunny00.off", {0, 0, 0}, 1.0, 0), operand("knot1.off", {0.2, 0.3, 0}, 0.7, 60),
        operand("elephant.off", {0.9, -0.3, 0.2}, 0.9, 15),
        operand("fandisk.off", {0.8, -0.2, 0.3}, 0.9, 75)},
       node(Op::kUnion, {node(Op::kDifference, {leaf(0), leaf(1)}),
                         node(Op::kIntersection, {leaf(2), leaf(3)})}),
       {}});
  // bench/render_vs_cgal.cpp kLeaves: ((A ∪ B ∪ C) − (D ∪ E)) ∪ ((F ∩ G) − H) ∪ (I − J).
  c.push_back({"10-leaf preview scene",
               {{"bunny00.off", {-0.2, -0.2, 0}, 0.8, {0, 0, 1}, 0},
                {"bunny00.off", {0.2, 0.2, 0.05}, 0.8, {0.2, 1, 0.3}, 70},
                {"refined_elephant.off", {0.1, -0.35, 0.35}, 0.9, {1, 0.2, 0.1}, 30},
                {"armadillo.off", {0.3, -0.4, 0.3}, 0.55, {0.3, 1, 0.2}, 120},
                {"bunny00.off", {0.05, -0.3, 0.5}, 0.5, {1, 1, 0}, 200},
                {"armadillo.off", {0.75, 0.75, 0}, 0.85, {0.1, 0.3, 1}, 20},
                {"bunny00.off", {0.8, 0.8, 0.1}, 0.85, {0.4, 0.1, 1}, 160},
                {"fandisk_large.off", {0.85, 0.55, 0.25}, 0.55, {0.3, 1, 0.2}, 45},
                {"armadillo.off", {-0.75, -0.75, 0}, 0.8, {0.2, 0.2, 1}, 250},
                {"bear.off", {-0.55, -0.95, 0.3}, 0.5, {0, 1, 0.3}, 90}},
               node(Op::kUnion,
                    {node(Op::kDifference, {node(Op::kUnion, {leaf(0), leaf(1), leaf(2)}),
                                            node(Op::kUnion, {leaf(3), leaf(4)})}),
                     node(Op::kDifference, {node(Op::kIntersection, {leaf(5), leaf(6)}), leaf(7)}),
                     node(Op::kDifference, {leaf(8), leaf(9)})}),
               {}});
  return c;
}

/// The leaf placed as specified (same arithmetic as bench/render_vs_cgal.cpp load_leaf).
cover::PolygonMesh placed(const fs::path& folder, const LeafSpec& s) {
  cover::PolygonMesh m = cover::read_mesh(folder / s.file);
  cover::apply_transform(
      cover::Transform::fit(cover::face_bbox(m), s.centre, s.half_size, s.axis, s.degrees), m);
  return m;
}

// ---- Cover ------------------------------------------------------------------------------------

cover::Solid build_cover(const Expr& e, std::vector<cover::Solid>& leaves) {
  if (e.op == Op::kLeaf) return std::move(leaves[e.leaf]);
  std::vector<cover::Solid> parts;
  for (const Expr& k : e.kids) parts.push_back(build_cover(k, leaves));
  if (e.op == Op::kUnion) return cover::unite(std::move(parts));
  if (e.op == Op::kIntersection) return cover::intersect(std::move(parts));
  return cover::subtract(std::move(parts));
}

struct Timed {
  double whole = 0, kernel = 0, volume = 0;
  size_t faces = 0;
  cover::EvaluatePhases phases;  ///< Cover only
};

Timed run_cover(const Case& c, const fs::path& out) {
  Timed r;
  const auto t0 = Clock::now();
  std::vector<cover::Solid> leaves;
  for (size_t i = 0; i < c.files.size(); ++i)
    leaves.push_back(cover::make_leaf(cover::read_mesh(c.files[i]), c.leaves[i].file));
  const cover::Solid solid = build_cover(c.expr, leaves);
  const auto t1 = Clock::now();
  cover::EvaluateOptions options;
  options.phases = &r.phases;
  const cover::EvaluateResult e = cover::evaluate(solid, options);
  r.kernel = since(t1);
  cover::write_mesh(out, e.mesh);
  r.whole = since(t0);
  r.volume = e.volume;
  r.faces = e.mesh.face_count();
  return r;
}

// ---- Manifold ---------------------------------------------------------------------------------

/// A triangle OFF file into MeshGL64 (polygons fan-triangulated); throws on malformed input.
manifold::MeshGL64 read_off(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const char* p = text.data();
  const char* end = p + text.size();
  auto skip = [&] {
    while (p < end && (*p == ' ' || *p == '\n' || *p == '\r' || *p == '\t' || *p == '#')) {
      if (*p == '#')
        while (p < end && *p != '\n') ++p;
      else
        ++p;
    }
  };
  auto number = [&](auto& x) {
    skip();
    const auto [q, ec] = std::from_chars(p, end, x);
    if (ec != std::errc()) throw std::runtime_error(path.string() + ": bad number");
    p = q;
  };
  skip();
  if (end - p < 3 || std::strncmp(p, "OFF", 3) != 0)
    throw std::runtime_error(path.string() + ": not OFF");
  p += 3;
  size_t nv, nf, ne;
  number(nv), number(nf), number(ne);
  manifold::MeshGL64 m;
  m.numProp = 3;
  m.vertProperties.resize(3 * nv);
  for (double& x : m.vertProperties) number(x);
  m.triVerts.reserve(3 * nf);
  for (size_t f = 0; f < nf; ++f) {
    size_t k;
    uint64_t v0, prev, v;
    number(k), number(v0), number(prev);
    for (size_t i = 2; i < k; ++i) {
      number(v);
      m.triVerts.insert(m.triVerts.end(), {v0, prev, v});
      prev = v;
    }
  }
  return m;
}

void write_off(const fs::path& path, const manifold::MeshGL64& m) {
  std::string s = "OFF\n" + std::to_string(m.NumVert()) + " " + std::to_string(m.NumTri()) + " 0\n";
  char buf[32];
  for (size_t v = 0; v < m.NumVert(); ++v)
    for (int a = 0; a < 3; ++a) {
      s.append(buf, std::to_chars(buf, buf + sizeof buf, m.vertProperties[v * m.numProp + a]).ptr);
      s += a == 2 ? '\n' : ' ';
    }
  for (size_t t = 0; t < m.NumTri(); ++t) {
    s += "3";
    for (int a = 0; a < 3; ++a) {
      s += ' ';
      s.append(buf, std::to_chars(buf, buf + sizeof buf, m.triVerts[3 * t + a]).ptr);
    }
    s += '\n';
  }
  std::ofstream(path, std::ios::binary).write(s.data(), static_cast<std::streamsize>(s.size()));
}

manifold::Manifold build_manifold(const Expr& e, const std::vector<manifold::Manifold>& leaves) {
  if (e.op == Op::kLeaf) return leaves[e.leaf];
  std::vector<manifold::Manifold> parts;
  for (const Expr& k : e.kids) parts.push_back(build_manifold(k, leaves));
  const manifold::OpType op = e.op == Op::kUnion          ? manifold::OpType::Add
                              : e.op == Op::kIntersection ? manifold::OpType::Intersect
                                                          : manifold::OpType::Subtract;
  return manifold::Manifold::BatchBoolean(parts, op);
}

Timed run_manifold(const Case& c, const fs::path& out) {
  Timed r;
  const auto t0 = Clock::now();
  std::vector<manifold::Manifold> leaves;
  for (const fs::path& f : c.files) {
    leaves.emplace_back(read_off(f));
    if (leaves.back().Status() != manifold::Manifold::Error::NoError)
      throw std::runtime_error(f.string() + ": Manifold refuses the leaf");
  }
  const auto t1 = Clock::now();
  const manifold::Manifold result = build_manifold(c.expr, leaves);
  if (result.Status() != manifold::Manifold::Error::NoError)
    throw std::runtime_error(c.name + ": Manifold failed");
  r.kernel = since(t1);
  write_off(out, result.GetMeshGL64());
  r.whole = since(t0);
  r.volume = result.Volume();
  r.faces = result.NumTri();
  return r;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const char* usage =
      "usage: evaluate_vs_manifold MESH_FOLDER [--runs N] [--scratch DIR] [CASE...]\n"
      "  MESH_FOLDER  libcgal-demo data/meshes; CASE: 1-based case numbers (all by default)\n";
  if (argc < 2 || argv[1][0] == '-') {
    const bool help =
        argc >= 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h");
    std::fputs(usage, help ? stdout : stderr);
    return help ? 0 : 2;
  }
  const fs::path folder = argv[1];
  if (!fs::exists(folder / "bunny00.off")) {
    std::fprintf(stderr,
                 "evaluate_vs_manifold: %s has no bunny00.off (want libcgal-demo's data/meshes)\n",
                 folder.c_str());
    return 2;
  }
  fs::path scratch = fs::temp_directory_path() / "evaluate_vs_manifold";
  int runs = 3;
  std::vector<size_t> wanted;
  // A malformed number is a usage error (exit 2), not an uncaught std::invalid_argument.
  auto number = [&](const std::string& text) -> long {
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || v < 1) {
      std::fprintf(stderr, "evaluate_vs_manifold: '%s' is not a positive number\n%s", text.c_str(),
                   usage);
      std::exit(2);
    }
    return v;
  };
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc)
      runs = static_cast<int>(number(argv[++i]));
    else if (a == "--scratch" && i + 1 < argc)
      scratch = argv[++i];
    else
      wanted.push_back(static_cast<size_t>(number(a)));
  }
  fs::create_directories(scratch);
  cover::ThreadLimit limit(2);
  tbb::global_control tbb_limit(tbb::global_control::max_allowed_parallelism, 2);

  std::vector<Case> cases = make_cases();
  std::vector<size_t> chosen;
  for (size_t i = 0; i < cases.size(); ++i)
    if (wanted.empty() || std::find(wanted.begin(), wanted.end(), i + 1) != wanted.end())
      chosen.push_back(i);
  std::vector<size_t> triangles(cases.size(), 0);
  for (size_t i : chosen)
    for (size_t l = 0; l < cases[i].leaves.size(); ++l) {
      const cover::PolygonMesh m = placed(folder, cases[i].leaves[l]);
      for (size_t f = 0; f < m.face_count(); ++f) triangles[i] += m.face(f).size() - 2;
      cases[i].files.push_back(
          scratch / ("case" + std::to_string(i + 1) + "_leaf" + std::to_string(l) + ".off"));
      cover::write_mesh(cases[i].files.back(), m);  // OFF round trips are exact
    }

  std::vector<std::vector<Timed>> cov(cases.size()), man(cases.size());
  for (int run = 0; run < runs; ++run)
    for (size_t i : chosen) {
      const fs::path co = scratch / ("cover" + std::to_string(i + 1) + ".off");
      const fs::path mo = scratch / ("manifold" + std::to_string(i + 1) + ".off");
      if (run % 2 == 0) {
        cov[i].push_back(run_cover(cases[i], co));
        man[i].push_back(run_manifold(cases[i], mo));
      } else {
        man[i].push_back(run_manifold(cases[i], mo));
        cov[i].push_back(run_cover(cases[i], co));
      }
    }

  std::printf("%-42s %8s | %8s %8s %6s | %8s %8s %6s | %16s %16s %9s\n", "expression", "tris in",
              "Cover s", "Manif s", "ratio", "Cover k", "Manif k", "ratio", "Cover volume",
              "Manifold volume", "rel diff");
  for (size_t i : chosen) {
    auto med = [](const std::vector<Timed>& v, double Timed::*f) {
      std::vector<double> x;
      for (const Timed& t : v) x.push_back(t.*f);
      return median(x);
    };
    const double cw = med(cov[i], &Timed::whole), mw = med(man[i], &Timed::whole);
    const double ck = med(cov[i], &Timed::kernel), mk = med(man[i], &Timed::kernel);
    const double cv = cov[i][0].volume, mv = man[i][0].volume;
    std::printf("%-44s %8zu | %8.3f %8.3f %6.2f | %8.3f %8.3f %6.2f | %16.12g %16.12g %9.2e\n",
                cases[i].name.c_str(), triangles[i], cw, mw, cw / mw, ck, mk, ck / mk, cv, mv,
                std::abs(cv - mv) / std::max(std::abs(cv), 1e-300));
  }
  // check+pairs: the leaf self-intersection test and the candidate pairs share one grid pass.
  std::printf(
      "\nCover seconds per step (run with the median kernel time)\n%-42s %7s %7s %7s "
      "%7s %7s %7s %7s %7s\n",
      "expression", "triang", "chk+prs", "inters", "split", "ident", "select", "assemb", "repair");
  for (size_t i : chosen) {
    std::vector<Timed> v = cov[i];
    std::sort(v.begin(), v.end(),
              [](const Timed& a, const Timed& b) { return a.kernel < b.kernel; });
    const cover::EvaluatePhases& s = v[v.size() / 2].phases;
    std::printf("%-44s %7.3f %7.3f %7.3f %7.3f %7.3f %7.3f %7.3f %7.3f\n", cases[i].name.c_str(),
                s.triangulate, s.check + s.pairs, s.intersect, s.split, s.identify, s.select,
                s.assemble, s.repair);
  }
  return 0;
}
