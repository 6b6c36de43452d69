// CGAL convex_hull_3 on the doubles (Epick: exact predicates; the hull's points are input points,
// nothing is constructed). The one translation unit of decompose that includes CGAL.
#include "cover/brep/detail/convex_hull.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <vector>

namespace cover::brep::detail {

PolygonMesh convex_hull(std::span<const Vec3> points) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Mesh = CGAL::Surface_mesh<K::Point_3>;
  std::vector<K::Point_3> in;
  in.reserve(points.size());
  for (const Vec3& p : points) in.emplace_back(p.x, p.y, p.z);
  Mesh hull;
  CGAL::convex_hull_3(in.begin(), in.end(), hull);
  // The output in a canonical order (vertices sorted by coordinates, each triangle from its
  // smallest vertex, triangles sorted): the mesh's own order follows handle addresses, which
  // differ between runs and threads.
  const uint32_t n =
      static_cast<uint32_t>(hull.number_of_vertices() + hull.number_of_removed_vertices());
  std::vector<Mesh::Vertex_index> live(hull.vertices().begin(), hull.vertices().end());
  auto at = [&](Mesh::Vertex_index v) {
    const K::Point_3& p = hull.point(v);
    return std::array<double, 3>{p.x(), p.y(), p.z()};
  };
  std::sort(live.begin(), live.end(),
            [&](Mesh::Vertex_index a, Mesh::Vertex_index b) { return at(a) < at(b); });
  std::vector<uint32_t> index(n);
  PolygonMesh out;
  for (Mesh::Vertex_index v : live) {
    index[v] = static_cast<uint32_t>(out.vertices.size());
    const auto p = at(v);
    out.vertices.push_back({p[0], p[1], p[2]});
  }
  std::vector<std::array<uint32_t, 3>> tris;
  for (Mesh::Face_index f : hull.faces()) {
    std::array<uint32_t, 3> t{};
    int k = 0;
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(hull.halfedge(f), hull))
      if (k < 3) t[k++] = index[v];
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    tris.push_back(t);
  }
  std::sort(tris.begin(), tris.end());
  for (const auto& t : tris) out.add_face({t[0], t[1], t[2]});
  return out;
}

}  // namespace cover::brep::detail
