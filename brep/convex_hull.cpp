// CGAL convex_hull_3 on the doubles (Epick: exact predicates; the hull's points are input points,
// nothing is constructed). The one translation unit of decompose that includes CGAL.
#include "brep/detail/convex_hull.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

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
  PolygonMesh out;
  std::vector<uint32_t> index(hull.number_of_vertices() + hull.number_of_removed_vertices());
  for (Mesh::Vertex_index v : hull.vertices()) {
    index[v] = static_cast<uint32_t>(out.vertices.size());
    const K::Point_3& p = hull.point(v);
    out.vertices.push_back({p.x(), p.y(), p.z()});
  }
  std::vector<uint32_t> loop;
  for (Mesh::Face_index f : hull.faces()) {
    loop.clear();
    for (Mesh::Vertex_index v : CGAL::vertices_around_face(hull.halfedge(f), hull))
      loop.push_back(index[v]);
    out.add_face(loop);
  }
  return out;
}

}  // namespace cover::brep::detail
