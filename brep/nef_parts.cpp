// Convex parts of a piece, or of a shell's exact region, by CGAL's Nef polyhedra
// (detail/nef_parts.h): triangles (doubles, exact) make a Nef_polyhedron_3 over Epeck, a region is
// cut from the shell's by Nef intersections (a box, closed half-spaces); convex_decomposition_3
// splits the interior into convex volumes (exact constructions); each marked volume's vertices
// are rounded to the nearest doubles. The one translation unit of decompose that includes Nef_3.
#include "brep/detail/nef_parts.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/generators.h>
#include <CGAL/convex_decomposition_3.h>

#include <exception>
#include <optional>

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

K::Point_3 point(const Vec3& p) { return {p.x, p.y, p.z}; }

/// The Surface_mesh of `piece` (exact points); false when it is no closed 2-manifold.
bool to_mesh(const PolygonMesh& piece, Mesh& mesh) {
  std::vector<Mesh::Vertex_index> vs;
  for (const Vec3& p : piece.vertices) vs.push_back(mesh.add_vertex(point(p)));
  for (size_t f = 0; f < piece.face_count(); ++f) {
    std::vector<Mesh::Vertex_index> loop;
    for (uint32_t v : piece.face(f)) loop.push_back(vs[v]);
    if (mesh.add_face(loop) == Mesh::null_face()) return false;
  }
  return CGAL::is_closed(mesh);
}

/// The convex parts of `nef` (exact points), rounded.
std::vector<std::vector<Vec3>> parts_of(Nef& nef) {
  std::vector<std::vector<Vec3>> out;
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
  return out;
}

}  // namespace

std::vector<std::vector<Vec3>> nef_convex_parts(const PolygonMesh& piece) {
  try {
    Mesh mesh;
    if (!to_mesh(piece, mesh)) return {};
    Nef nef(mesh);
    if (!nef.is_simple()) return {};
    return parts_of(nef);
  } catch (const std::exception&) {
    return {};
  }
}

struct ShellRegions::Impl {
  std::optional<Nef> shell;  ///< nullopt when the shell is no closed 2-manifold
};

ShellRegions::ShellRegions(const PolygonMesh& shell) : impl_(std::make_unique<Impl>()) {
  try {
    Mesh mesh;
    if (to_mesh(shell, mesh)) impl_->shell.emplace(mesh);
  } catch (const std::exception&) {
  }
}

ShellRegions::~ShellRegions() = default;

std::optional<std::vector<std::vector<Vec3>>> ShellRegions::convex_parts(
    std::span<const HalfSpace> cuts, const Bbox& near) const {
  if (!impl_->shell) return std::nullopt;
  try {
    Mesh box;
    CGAL::make_hexahedron(
        point({near.min.x, near.min.y, near.min.z}), point({near.max.x, near.min.y, near.min.z}),
        point({near.max.x, near.max.y, near.min.z}), point({near.min.x, near.max.y, near.min.z}),
        point({near.min.x, near.max.y, near.max.z}), point({near.min.x, near.min.y, near.max.z}),
        point({near.max.x, near.min.y, near.max.z}), point({near.max.x, near.max.y, near.max.z}),
        box);
    // The shell within the box, then each half-space (Nef's own plane intersection: the region's
    // components may touch at points or edges, which Nef represents and PMP::clip does not).
    Nef region = *impl_->shell * Nef(box);
    for (const HalfSpace& h : cuts) {
      if (region.is_empty()) break;
      // A closed half-space of Nef is the negative side of its plane, opposite the normal
      // (q − p) × (r − p) of the plane through p, q, r.
      K::Plane_3 plane(point(h.plane[0]), point(h.plane[1]), point(h.plane[2]));
      if (h.above) plane = plane.opposite();
      region = region.intersection(plane, Nef::CLOSED_HALFSPACE);
    }
    if (region.is_empty()) return std::vector<std::vector<Vec3>>{};
    region.regularization();
    return parts_of(region);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace cover::brep::detail
