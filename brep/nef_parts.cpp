// Convex parts of a piece by CGAL's Nef polyhedra (detail/nef_parts.h): the piece's triangles
// (doubles, exact) make a Nef_polyhedron_3 over Epeck; convex_decomposition_3 splits its
// interior into convex volumes (exact constructions); each marked volume's vertices are rounded
// to the nearest doubles. The one translation unit of decompose that includes Nef_3.
#include "brep/detail/nef_parts.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_decomposition_3.h>

#include <exception>

namespace cover::brep::detail {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using Nef = CGAL::Nef_polyhedron_3<K>;
using Polyhedron = CGAL::Polyhedron_3<K>;

double nearest(const K::FT& x) {
  CGAL::exact(x);  // tightens the interval to the exact value's neighbours
  return CGAL::to_double(x);
}

}  // namespace

std::vector<std::vector<Vec3>> nef_convex_parts(const PolygonMesh& piece) {
  std::vector<std::vector<Vec3>> out;
  try {
    Mesh mesh;
    std::vector<Mesh::Vertex_index> vs;
    for (const Vec3& p : piece.vertices) vs.push_back(mesh.add_vertex(K::Point_3(p.x, p.y, p.z)));
    for (size_t f = 0; f < piece.face_count(); ++f) {
      std::vector<Mesh::Vertex_index> loop;
      for (uint32_t v : piece.face(f)) loop.push_back(vs[v]);
      if (mesh.add_face(loop) == Mesh::null_face()) return {};
    }
    if (!CGAL::is_closed(mesh)) return {};
    Nef nef(mesh);
    if (!nef.is_simple()) return {};
    CGAL::convex_decomposition_3(nef);
    for (auto ci = ++nef.volumes_begin(); ci != nef.volumes_end(); ++ci) {
      if (!ci->mark()) continue;
      Polyhedron p;
      nef.convert_inner_shell_to_polyhedron(ci->shells_begin(), p);
      std::vector<Vec3> points;
      for (auto v = p.vertices_begin(); v != p.vertices_end(); ++v)
        points.push_back({nearest(v->point().x()), nearest(v->point().y()), nearest(v->point().z())});
      out.push_back(std::move(points));
    }
  } catch (const std::exception&) {
    return {};
  }
  return out;
}

}  // namespace cover::brep::detail
