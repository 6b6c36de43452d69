// triangulate_face (triangulate.h): the fan test and the constrained Delaunay triangulation in
// the face's projection (CGAL Epick, constraints that would cross are refused, not constructed).
#include "cover/mesh/triangulate.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace cover {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = K::Point_2;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<
    K, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;

Point2 project(const Vec3& p, int k) { return {p[(k + 1) % 3], p[(k + 2) % 3]}; }

/// Newell normal of the loop (doubles). When it vanishes (lobes of opposite orientation cancel,
/// as in a bow tie, or the loop is collinear), the normal of the first corner (loop[0], loop[i],
/// loop[i+1]) that is not, so that the projection still shows a crossing.
/// Both are computed on the coordinates scaled by a power of two (exact) to magnitude at most 1,
/// so that a tiny face (side 1e-200 near the origin) gets a normal, not an underflowed 0.
Vec3 projection_normal(std::span<const Vec3> points, std::span<const uint32_t> loop) {
  double m = 0;
  for (uint32_t v : loop)
    m = std::max({m, std::abs(points[v].x), std::abs(points[v].y), std::abs(points[v].z)});
  const int e = m > 0 && std::isfinite(m) ? -std::ilogb(m) : 0;
  auto at = [&](size_t i) {
    const Vec3& p = points[loop[i % loop.size()]];
    return Vec3{std::ldexp(p.x, e), std::ldexp(p.y, e), std::ldexp(p.z, e)};
  };
  Vec3 normal{};
  for (size_t i = 0; i < loop.size(); ++i) {
    const Vec3 a = at(i), b = at(i + 1);
    normal = normal +
             Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  for (size_t i = 1; normal == Vec3{} && i + 1 < loop.size(); ++i)
    normal = normal_direction(at(0), at(i), at(i + 1));
  return normal;
}

/// True when the projected loop turns the same way, never straight, at every vertex and repeats
/// no index (so its fan is its covering).
bool turns_one_way(std::span<const Vec3> points, std::span<const uint32_t> loop, int k) {
  const size_t n = loop.size();
  CGAL::Orientation first = CGAL::COLLINEAR;
  for (size_t i = 0; i < n; ++i) {
    if (loop[i] == loop[(i + 1) % n]) return false;
    const auto o =
        CGAL::orientation(project(points[loop[i]], k), project(points[loop[(i + 1) % n]], k),
                          project(points[loop[(i + 2) % n]], k));
    if (o == CGAL::COLLINEAR || (first != CGAL::COLLINEAR && o != first)) return false;
    first = o;
  }
  std::vector<uint32_t> sorted(loop.begin(), loop.end());
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
}

/// For a loop that turns one way: the number of times it winds, i.e. its lexicographic local
/// minima in the projection (the edge direction turns monotonically, passing "upwards" once per
/// turn; consecutive projected points differ, as no turn is straight).
size_t windings(std::span<const Vec3> points, std::span<const uint32_t> loop, int k) {
  const size_t n = loop.size();
  auto below = [&](uint32_t a, uint32_t b) {
    return project(points[a], k) < project(points[b], k);
  };
  size_t minima = 0;
  for (size_t i = 0; i < n; ++i)
    if (below(loop[i], loop[(i + 1) % n]) && below(loop[i], loop[(i + n - 1) % n])) ++minima;
  return minima;
}

}  // namespace

FaceTiling triangulate_face(std::span<const Vec3> points, std::span<const uint32_t> loop,
                            std::vector<std::array<uint32_t, 3>>& out) {
  auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    auto p = [&](uint32_t v) { return K::Point_3(points[v].x, points[v].y, points[v].z); };
    if (!CGAL::collinear(p(a), p(b), p(c))) out.push_back({a, b, c});
  };
  const size_t n = loop.size();
  if (n < 3) return FaceTiling::kSimple;
  if (n == 3) {
    add(loop[0], loop[1], loop[2]);
    return FaceTiling::kSimple;
  }
  const Vec3 normal = projection_normal(points, loop);
  const int k = dominant_axis(normal);
  if (turns_one_way(points, loop, k)) {
    for (size_t i = 1; i + 1 < n; ++i) add(loop[0], loop[i], loop[i + 1]);
    return windings(points, loop, k) == 1 ? FaceTiling::kSimple : FaceTiling::kWinding;
  }
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> vh(n);
  for (size_t i = 0; i < n; ++i) {
    vh[i] = cdt.insert(project(points[loop[i]], k));
    vh[i]->info() = loop[i];
  }
  // Times the loop runs along each undirected edge: a false edge (twice) separates nothing.
  std::map<std::pair<Cdt::Vertex_handle, Cdt::Vertex_handle>, int> count;
  try {
    for (size_t i = 0; i < n; ++i) {
      Cdt::Vertex_handle a = vh[i], b = vh[(i + 1) % n];
      if (a == b) continue;
      cdt.insert_constraint(a, b);
      ++count[std::minmax(a, b)];
    }
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    return FaceTiling::kCrossing;
  }
  // Parity of the loop edges crossed from the infinite faces (flood fill).
  std::map<Cdt::Face_handle, int> inside;
  std::vector<Cdt::Face_handle> stack;
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
    if (cdt.is_infinite(f)) {
      inside[f] = 0;
      stack.push_back(f);
    }
  while (!stack.empty()) {
    Cdt::Face_handle f = stack.back();
    stack.pop_back();
    for (int i = 0; i < 3; ++i) {
      Cdt::Face_handle g = f->neighbor(i);
      if (inside.count(g)) continue;
      auto it = count.find(std::minmax(f->vertex(Cdt::cw(i)), f->vertex(Cdt::ccw(i))));
      inside[g] = inside[f] ^ (it != count.end() ? it->second & 1 : 0);
      stack.push_back(g);
    }
  }
  const bool flip = normal[k] < 0;  // CDT faces are counter-clockwise in the projection
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!inside[f]) continue;
    const uint32_t a = f->vertex(0)->info(), b = f->vertex(1)->info(), c = f->vertex(2)->info();
    if (flip) {
      add(a, c, b);
    } else {
      add(a, b, c);
    }
  }
  return FaceTiling::kSimple;
}

}  // namespace cover
