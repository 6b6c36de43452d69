// Polygonization of field scenes against the peers' routes to a triangle mesh of the same level
// set (one process, one machine, 2 threads where a side is parallel):
//   cover     Model::polygonize (certified marching tetrahedra, polygonize/polygonize.h) of the
//             scene as cover::parse_scene reads it, at --resolution-a / --resolution-b
//   openvdb   f − T by cover::field::evaluate (doubles, rounded to float) at the n³ cell centres
//             of the box's cube into a FloatGrid (x slabs in parallel), tools::volumeToMesh at
//             the threshold, quads split into two triangles along (q0, q2)
//   manifold  (only with COVER_BENCH_MANIFOLD) Manifold::LevelSet of f − T over the field's box
//             with edge length h (default tolerance: linear interpolation), GetMeshGL64
//   cgal      CGAL Surface_mesher: make_surface_mesh (Manifold_tag) of CGAL::Implicit_surface_3
//             (function T − f, bounding sphere around the box centred on the first primitive's
//             centre, default error bound 1e-3 of its radius), Surface_mesh_default_criteria_3
//             (angle 30°, radius bound r, distance bound r); the triangulation is seeded with one
//             surface point per primitive and axis direction (so that every component is found)
//             besides CGAL's own 20 random initial points; facets_in_complex_2_to_triangle_mesh
// Each peer's step (OpenVDB and Manifold: grid spacing h; CGAL: radius bound r) is calibrated so
// that its triangle count is within --match percent of Cover's: a coarse run, the step scaled by
// sqrt(count / target), and a rescale if the first timed run misses.
// Every output is checked the same way after the timings: exactly equal coordinates welded, then
// cover::validate_mesh (closed, manifold, oriented, outward, exact self-intersection test,
// degenerate = zero-area faces), and every vertex v's |f(v) − T| in doubles (field::evaluate of
// solid().fields[0]) with |f(v) − T| / |∇f(v)| (a first-order distance estimate). A peer's mesh
// is reversed when its signed volume is negative (OpenVDB's level-set convention); CGAL's
// components are each oriented by the field's gradient (facets_in_complex_2_to_triangle_mesh
// orients only the component of its top facet outward).
// Timing: wall clock; a side taking < 5 s is run 3 times interleaved with the others (median),
// else once.
// Scenes: (a) the two-point blend of docs (points (±0.35, 0, 0), r_T = 0.5, R = 1, n = 2);
// (b) a blend of P point primitives with centres uniform in [−2, 2]³ (mt19937_64, --seed), the
// same r_T, R, n (field_bench's point blend).
// Usage: polygonize_vs_peers [--resolution-a N] [--resolution-b N] [--primitives P] [--seed S]
//                            [--threads T] [--match PERCENT] [--cgal 0|1] [--scene 1|2|3]
//   (--scene: 1 = (a), 2 = (b), 3 = both; --cgal 0 skips CGAL)
#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/IO/facets_in_complex_2_to_triangle_mesh.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/global_control.h>
#if COVER_BENCH_MANIFOLD
#include <manifold/manifold.h>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "cover/field/field.h"
#include "cover/io/scene.h"
#include "cover/mesh/validate.h"
#include "cover/model/model.h"
#include "cover/solid/measure.h"
#include "cover/solid/parallel.h"
#include "cover/solid/polygon_mesh.h"

namespace {

using bench::Clock;
using bench::since;
using cover::FieldLeaf;
using cover::PolygonMesh;
using cover::Vec3;

const char* kTwoPointBlend =
    R"({"blend": [)"
    R"({"field": {"skeleton": {"point": [-0.35, 0, 0]}, "radius": 0.5, "influence": 1}},)"
    R"( {"field": {"skeleton": {"point": [0.35, 0, 0]}, "radius": 0.5, "influence": 1}}]})";

/// P point primitives with centres uniform in [−2, 2]³, R = 1, r_T = 0.5, n = 2 (field_bench's
/// point_blend), as scene JSON.
std::string point_blend_json(int p, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-2, 2);
  std::string s = R"({"blend": [)";
  char buf[256];
  for (int i = 0; i < p; ++i) {
    const double x = u(rng), y = u(rng), z = u(rng);
    std::snprintf(buf, sizeof buf,
                  R"(%s{"field": {"skeleton": {"point": [%.17g, %.17g, %.17g]}, "radius": 0.5, )"
                  R"("influence": 1}})",
                  i ? ", " : "", x, y, z);
    s += buf;
  }
  return s + "]}";
}

/// One run of a route: its triangles and its wall time.
struct Run {
  PolygonMesh mesh;
  double seconds = 0;
  double tolerance = 0;  // Cover's certified tolerance (0 for the peers)
};

/// A side of the comparison: its name, its step parameter and the route at a given step.
struct Side {
  std::string name;
  std::string param_name;
  double param = 0;
  std::function<Run(double)> route;
  bool calibrate = true;  // a peer: its step is chosen to match Cover's triangle count
  std::vector<double> times;
  Run first;  // the mesh checked below (the routes are deterministic)
  size_t tries = 0;
};

/// Merges vertices at exactly equal coordinates; returns how many were merged away.
size_t weld(PolygonMesh& mesh) {
  const size_t n = mesh.vertices.size();
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  auto key = [&](uint32_t i) {
    const Vec3& v = mesh.vertices[i];
    return std::array<double, 3>{v.x, v.y, v.z};
  };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const auto ka = key(a), kb = key(b);
    return ka != kb ? ka < kb : a < b;
  });
  std::vector<uint32_t> remap(n);
  std::vector<Vec3> out;
  out.reserve(n);
  for (size_t k = 0; k < n; ++k) {
    if (k == 0 || key(order[k]) != key(order[k - 1])) out.push_back(mesh.vertices[order[k]]);
    remap[order[k]] = static_cast<uint32_t>(out.size() - 1);
  }
  const size_t merged = n - out.size();
  for (uint32_t& v : mesh.face_vertices) v = remap[v];
  mesh.vertices = std::move(out);
  return merged;
}

void reverse_face(PolygonMesh& mesh, size_t f) {
  std::reverse(mesh.face_vertices.begin() + mesh.face_start[f],
               mesh.face_vertices.begin() + mesh.face_start[f + 1]);
}

/// Reverses every face when the signed volume is negative; true when it did.
bool outward_by_volume(PolygonMesh& mesh) {
  if (cover::signed_volume(mesh) >= 0) return false;
  for (size_t f = 0; f < mesh.face_count(); ++f) reverse_face(mesh, f);
  return true;
}

/// Orients each connected component (faces through shared vertices) so that most of its area
/// faces down the field's gradient (outward: f decreases out of the solid); returns how many
/// components it reversed.
size_t orient_components_by_gradient(PolygonMesh& mesh, const FieldLeaf& f) {
  const size_t nf = mesh.face_count();
  std::vector<uint32_t> parent(mesh.vertices.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (size_t fi = 0; fi < nf; ++fi) {
    const auto loop = mesh.face(fi);
    for (size_t k = 1; k < loop.size(); ++k) parent[find(loop[k])] = find(loop[0]);
  }
  std::vector<double> vote(mesh.vertices.size(), 0);
  for (size_t fi = 0; fi < nf; ++fi) {
    const auto t = mesh.face(fi);
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Vec3 u{b.x - a.x, b.y - a.y, b.z - a.z}, w{c.x - a.x, c.y - a.y, c.z - a.z};
    const Vec3 n{u.y * w.z - u.z * w.y, u.z * w.x - u.x * w.z, u.x * w.y - u.y * w.x};
    const Vec3 m{(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
    const Vec3 g = cover::field::evaluate(f, m).gradient;
    vote[find(t[0])] -= n.x * g.x + n.y * g.y + n.z * g.z;
  }
  size_t flipped = 0;
  for (size_t v = 0; v < vote.size(); ++v)
    flipped += find(static_cast<uint32_t>(v)) == v && vote[v] < 0;
  for (size_t fi = 0; fi < nf; ++fi)
    if (vote[find(mesh.face(fi)[0])] < 0) reverse_face(mesh, fi);
  return flipped;
}

struct VertexError {
  double max_abs = 0;   // max |f(v) − T|
  double max_dist = 0;  // max |f(v) − T| / |∇f(v)|
};

VertexError vertex_error(const PolygonMesh& mesh, const FieldLeaf& f, double T) {
  const size_t n = mesh.vertices.size(), grain = 4096;
  const size_t chunks = (n + grain - 1) / grain;
  std::vector<VertexError> part(chunks);
  cover::parallel_for(n, grain, [&](size_t b, size_t e) {
    VertexError& r = part[b / grain];
    for (size_t i = b; i < e; ++i) {
      const cover::field::FieldValue fv = cover::field::evaluate(f, mesh.vertices[i]);
      const double d = std::abs(fv.value - T);
      const double g = std::sqrt(fv.gradient.x * fv.gradient.x + fv.gradient.y * fv.gradient.y +
                                 fv.gradient.z * fv.gradient.z);
      r.max_abs = std::max(r.max_abs, d);
      r.max_dist = std::max(r.max_dist, g > 0 ? d / g : INFINITY);
    }
  });
  VertexError out;
  for (const VertexError& r : part) {
    out.max_abs = std::max(out.max_abs, r.max_abs);
    out.max_dist = std::max(out.max_dist, r.max_dist);
  }
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// --- CGAL Surface_mesher ----------------------------------------------------------------------
using Tr = CGAL::Surface_mesh_default_triangulation_3;
using C2t3 = CGAL::Complex_2_in_triangulation_3<Tr>;
using GT = Tr::Geom_traits;
using Point_3 = GT::Point_3;

/// T − f (negative inside, as Implicit_surface_3 wants).
struct CgalFunction {
  const FieldLeaf* f;
  double T;
  GT::FT operator()(const Point_3& p) const {
    return T - cover::field::evaluate(*f, Vec3{p.x(), p.y(), p.z()}).value;
  }
};
using CgalSurface = CGAL::Implicit_surface_3<GT, CgalFunction>;

/// A surface point between an inside point a and an outside point b (60 bisections).
Vec3 bisect(const FieldLeaf& f, double T, Vec3 a, Vec3 b) {
  for (int k = 0; k < 60; ++k) {
    const Vec3 m{(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
    (cover::field::evaluate(f, m).value > T ? a : b) = m;
  }
  return {(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
}

Run cgal_route(const FieldLeaf& f, double T, const cover::Bbox& box, double r) {
  Run run;
  const auto t0 = Clock::now();
  Tr tr;
  C2t3 c2t3(tr);
  // Seeds: from each primitive's centre along ±x, ±y, ±z to its influence radius.
  for (const cover::FieldPrimitive& prim : f.primitives) {
    const Vec3 c = prim.points[0];
    if (cover::field::evaluate(f, c).value <= T) continue;
    for (int axis = 0; axis < 3; ++axis)
      for (double s : {-1.0, 1.0}) {
        Vec3 e = c;
        (axis == 0 ? e.x : axis == 1 ? e.y : e.z) += s * prim.influence;
        if (cover::field::evaluate(f, e).value > T) continue;
        const Vec3 p = bisect(f, T, c, e);
        tr.insert(Point_3(p.x, p.y, p.z));
      }
  }
  const Vec3 c = f.primitives[0].points[0];  // inside: f ≥ 1 > T there
  double r2 = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 q{k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y,
                 k & 4 ? box.max.z : box.min.z};
    r2 = std::max(
        r2, (q.x - c.x) * (q.x - c.x) + (q.y - c.y) * (q.y - c.y) + (q.z - c.z) * (q.z - c.z));
  }
  const CgalSurface surface(CgalFunction{&f, T}, GT::Sphere_3(Point_3(c.x, c.y, c.z), r2 * 1.01));
  const CGAL::Surface_mesh_default_criteria_3<Tr> criteria(30., r, r);
  CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_tag());
  CGAL::Surface_mesh<Point_3> sm;
  CGAL::facets_in_complex_2_to_triangle_mesh(c2t3, sm);
  PolygonMesh& mesh = run.mesh;
  mesh.vertices.reserve(sm.number_of_vertices());
  for (auto v : sm.vertices()) {
    const Point_3& p = sm.point(v);
    mesh.vertices.push_back({p.x(), p.y(), p.z()});
  }
  for (auto fh : sm.faces()) {
    std::array<uint32_t, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(fh), sm))
      t[k++] = static_cast<uint32_t>(v);
    mesh.add_face({t[0], t[1], t[2]});
  }
  run.seconds = since(t0);
  return run;
}

// --- OpenVDB: dense sampling + volumeToMesh -------------------------------------------------
Run openvdb_route(const FieldLeaf& f, double T, const cover::Bbox& box, double h_wanted) {
  Run run;
  const auto t0 = Clock::now();
  const double side =
      std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z});
  const int n = static_cast<int>(std::ceil(side / h_wanted));
  const double h = side / n;
  const float Tf = static_cast<float>(T);
  auto fgrid = openvdb::FloatGrid::create(Tf);
  fgrid->setTransform(openvdb::math::Transform::createLinearTransform(h));
  std::vector<openvdb::FloatGrid::Ptr> slabs(n);
  cover::parallel_for(static_cast<size_t>(n), 1, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) {
      slabs[i] = openvdb::FloatGrid::create(Tf);
      auto acc = slabs[i]->getAccessor();
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          const Vec3 p{box.min.x + (i + 0.5) * h, box.min.y + (j + 0.5) * h,
                       box.min.z + (k + 0.5) * h};
          const float v = static_cast<float>(cover::field::evaluate(f, p).value) - Tf;
          if (v != -Tf) acc.setValue(openvdb::Coord(static_cast<int>(i), j, k), -v);
        }
    }
  });
  for (auto& s : slabs) fgrid->tree().merge(s->tree());
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*fgrid, points, tris, quads, 0.0);
  PolygonMesh& mesh = run.mesh;
  mesh.vertices.reserve(points.size());
  for (const auto& p : points)
    mesh.vertices.push_back(
        {box.min.x + p.x() + 0.5 * h, box.min.y + p.y() + 0.5 * h, box.min.z + p.z() + 0.5 * h});
  for (const auto& t : tris) mesh.add_face({t[0], t[1], t[2]});
  for (const auto& q : quads) {
    mesh.add_face({q[0], q[1], q[2]});
    mesh.add_face({q[0], q[2], q[3]});
  }
  run.seconds = since(t0);
  return run;
}

#if COVER_BENCH_MANIFOLD
// --- Manifold: LevelSet ---------------------------------------------------------------------
Run manifold_route(const FieldLeaf& f, double T, const cover::Bbox& box, double h) {
  Run run;
  const auto t0 = Clock::now();
  const manifold::Box mbox({box.min.x, box.min.y, box.min.z}, {box.max.x, box.max.y, box.max.z});
  const manifold::Manifold solid = manifold::Manifold::LevelSet(
      [&f, T](manifold::vec3 p) {
        return cover::field::evaluate(f, Vec3{p.x, p.y, p.z}).value - T;
      },
      mbox, h);
  const manifold::MeshGL64 gl = solid.GetMeshGL64();
  PolygonMesh& mesh = run.mesh;
  mesh.vertices.reserve(gl.NumVert());
  for (size_t v = 0; v < gl.NumVert(); ++v) {
    const double* p = gl.vertProperties.data() + v * gl.numProp;
    mesh.vertices.push_back({p[0], p[1], p[2]});
  }
  for (size_t t = 0; t < gl.NumTri(); ++t)
    mesh.add_face({static_cast<uint32_t>(gl.triVerts[3 * t]),
                   static_cast<uint32_t>(gl.triVerts[3 * t + 1]),
                   static_cast<uint32_t>(gl.triVerts[3 * t + 2])});
  run.seconds = since(t0);
  if (solid.Status() != manifold::Manifold::Error::NoError)
    std::printf("  manifold: status %d\n", static_cast<int>(solid.Status()));
  return run;
}
#endif

void run_scene(const std::string& title, const std::string& json, int resolution, bool with_cgal,
               double match) {
  const cover::LoadedInput loaded = cover::parse_scene(json, "scene.json");
  const cover::Model model(loaded.solid);
  const FieldLeaf& f = model.solid().fields[0];
  const cover::Bbox box = model.solid().leaves[0].bbox;
  const double T = cover::field::threshold(f);
  std::printf("\n=== %s: %zu primitives, T = %.17g, box [%g %g %g]-[%g %g %g]\n", title.c_str(),
              f.primitives.size(), T, box.min.x, box.min.y, box.min.z, box.max.x, box.max.y,
              box.max.z);

  std::vector<Side> sides;
  double cover_h = 0;
  {
    Side s;
    s.name = "cover polygonize";
    s.param_name = "resolution";
    s.param = resolution;
    s.calibrate = false;
    const cover::Solid solid = loaded.solid;
    s.route = [solid](double res) {
      Run run;
      cover::Solid copy = solid;
      const auto t0 = Clock::now();
      const cover::Model m(std::move(copy));
      cover::PolygonizeOptions o;
      o.resolution = static_cast<int>(res);
      cover::PolygonizeResult r = m.polygonize(o);
      run.seconds = since(t0);
      run.mesh = std::move(r.mesh);
      run.tolerance = r.tolerance;
      return run;
    };
    sides.push_back(std::move(s));
  }
  // Cover first: its triangle count is the target; its cell size seeds the peers' first steps.
  {
    cover::PolygonizeOptions o;
    o.resolution = resolution;
    cover_h = model.polygonize(o).cell_size;  // warm-up, not timed
  }
  {
    Side s;
    s.name = "openvdb volumeToMesh";
    s.param_name = "h";
    s.param = 4 * cover_h;
    s.route = [&f, T, box](double h) { return openvdb_route(f, T, box, h); };
    sides.push_back(std::move(s));
  }
#if COVER_BENCH_MANIFOLD
  {
    Side s;
    s.name = "manifold LevelSet";
    s.param_name = "edge";
    s.param = 4 * cover_h;
    s.route = [&f, T, box](double h) { return manifold_route(f, T, box, h); };
    sides.push_back(std::move(s));
  }
#endif
  if (with_cgal) {
    Side s;
    s.name = "cgal make_surface_mesh";
    s.param_name = "radius";
    s.param = 4 * cover_h;
    s.route = [&f, T, box](double r) { return cgal_route(f, T, box, r); };
    sides.push_back(std::move(s));
  }

  Side& cv = sides[0];
  // Round 0: Cover, then each peer calibrated (a coarse run, then its step scaled by
  // sqrt(count / target); rescaled and rerun when the count misses by more than `match`).
  Run c0 = cv.route(cv.param);
  cv.times.push_back(c0.seconds);
  cv.first = std::move(c0);
  const double target = static_cast<double>(cv.first.mesh.face_count());
  std::printf("cover: %zu triangles at resolution %d (cell %.9g) in %.3f s\n",
              cv.first.mesh.face_count(), resolution, cover_h, cv.times[0]);
  for (size_t i = 1; i < sides.size(); ++i) {
    Side& s = sides[i];
    const Run coarse = s.route(s.param);
    std::printf("  %s calibration: %s %.6g -> %zu triangles in %.3f s\n", s.name.c_str(),
                s.param_name.c_str(), s.param, coarse.mesh.face_count(), coarse.seconds);
    s.param *= std::sqrt(static_cast<double>(coarse.mesh.face_count()) / target);
    for (int attempt = 0; attempt < 3; ++attempt) {
      Run r = s.route(s.param);
      ++s.tries;
      const double ratio = static_cast<double>(r.mesh.face_count()) / target;
      std::printf("  %s: %s %.6g -> %zu triangles (%.2f x cover) in %.3f s\n", s.name.c_str(),
                  s.param_name.c_str(), s.param, r.mesh.face_count(), ratio, r.seconds);
      if (std::abs(ratio - 1) <= match || attempt == 2) {
        s.times.push_back(r.seconds);
        s.first = std::move(r);
        break;
      }
      s.param *= std::sqrt(ratio);
    }
  }
  // Rounds 1, 2: every side under 5 s again, interleaved.
  for (int round = 1; round < 3; ++round)
    for (Side& s : sides)
      if (s.times[0] < 5) s.times.push_back(s.route(s.param).seconds);

  // Checks and table.
  std::printf(
      "\n| %s | tool | step | time s (runs) | triangles | / cover | welded | zero-area | closed | "
      "manifold | oriented | outward | self-int. | components | max abs(f-T) | max abs(f-T)/|grad "
      "f| "
      "| certified tolerance |\n",
      title.c_str());
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (size_t i = 0; i < sides.size(); ++i) {
    Side& s = sides[i];
    PolygonMesh mesh = s.first.mesh;
    const size_t welded = weld(mesh);
    std::string note;
    if (s.name.rfind("cgal", 0) == 0) {
      const size_t flipped = orient_components_by_gradient(mesh, f);
      if (flipped) note = " (" + std::to_string(flipped) + " components reversed)";
    } else if (i > 0 && outward_by_volume(mesh)) {
      note = " (reversed)";
    }
    const auto tv = Clock::now();
    const cover::MeshReport rep = cover::validate_mesh(mesh);
    const double tvs = since(tv);
    const VertexError err = vertex_error(mesh, f, T);
    std::string runs;
    char buf[64];
    for (double t : s.times) {
      std::snprintf(buf, sizeof buf, "%s%.3f", runs.empty() ? "" : " ", t);
      runs += buf;
    }
    char step[64];
    if (i == 0)
      std::snprintf(step, sizeof step, "res %d (h %.6g)", resolution, cover_h);
    else
      std::snprintf(step, sizeof step, "%s %.5g", s.param_name.c_str(), s.param);
    char tol[64] = "-";
    if (i == 0) std::snprintf(tol, sizeof tol, "%.3g", s.first.tolerance);
    std::printf(
        "| %s | %s%s | %s | %.3f (%s) | %zu | %.2f | %zu | %lld | %s | %s | %s | %s | %s | %lld | "
        "%.3g | %.3g | %s |\n",
        title.c_str(), s.name.c_str(), note.c_str(), step, median(s.times), runs.c_str(),
        mesh.face_count(), static_cast<double>(mesh.face_count()) / target, welded,
        static_cast<long long>(rep.degenerate_faces), rep.closed ? "yes" : "NO",
        rep.manifold ? "yes" : "NO", rep.oriented ? "yes" : "NO", rep.outward ? "yes" : "NO",
        !rep.self_intersecting   ? "unchecked"
        : *rep.self_intersecting ? "YES"
                                 : "no",
        static_cast<long long>(rep.components), err.max_abs, err.max_dist, tol);
    std::fflush(stdout);
    std::fprintf(stderr,
                 "  (%s: validate_mesh %.2f s; boundary edges %lld, non-manifold edges %lld, "
                 "genus %lld, volume %.6f)\n",
                 s.name.c_str(), tvs, static_cast<long long>(rep.boundary_edges),
                 static_cast<long long>(rep.nonmanifold_edges), static_cast<long long>(rep.genus),
                 rep.volume);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int res_a = static_cast<int>(bench::arg(argc, argv, "--resolution-a", 128));
  const int res_b = static_cast<int>(bench::arg(argc, argv, "--resolution-b", 64));
  const int prims = static_cast<int>(bench::arg(argc, argv, "--primitives", 50));
  const uint64_t seed = static_cast<uint64_t>(bench::arg(argc, argv, "--seed", 7));
  const int threads = static_cast<int>(bench::arg(argc, argv, "--threads", 2));
  const double match = bench::arg(argc, argv, "--match", 20) / 100.0;
  const bool with_cgal = bench::arg(argc, argv, "--cgal", 1) != 0;
  const long scenes = bench::arg(argc, argv, "--scene", 3);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  openvdb::initialize();
  std::printf("threads %d (cover, openvdb, manifold; cgal's Surface_mesher is sequential)\n",
              threads);
#if !COVER_BENCH_MANIFOLD
  std::printf("manifold: not built (configure with -DCOVER_MANIFOLD_DIR)\n");
#endif
  if (scenes & 1) run_scene("a", kTwoPointBlend, res_a, with_cgal, match);
  if (scenes & 2) run_scene("b", point_blend_json(prims, seed), res_b, with_cgal, match);
  return 0;
}
