// Convex parts of a piece, or of a shell's exact region, by CGAL's Nef polyhedra
// (detail/nef_parts.h): triangles (doubles, exact) make a Nef_polyhedron_3 over Epeck, a region is
// cut from the shell's by Nef intersections (a box, closed half-spaces); convex_decomposition_3
// splits the interior into convex volumes (exact constructions); each marked volume's vertices
// are rounded to the nearest doubles. The one translation unit of decompose that includes Nef_3.
#include "cover/brep/detail/nef_parts.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/generators.h>
#include <CGAL/convex_decomposition_3.h>

#include <exception>
#include <optional>

#include "cover/solid/union_find.h"

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

/// The Nef polyhedron bounded by the closed, outward mesh `solid`, which may have several
/// components (cavities: inward shells inside outer ones); nullopt when a component is no closed
/// 2-manifold. Nef_polyhedron_3's constructor marks the inside of every closed surface whatever
/// its orientation, so one mesh holding a shell and its cavity would come out filled; each
/// component is built alone and they are combined by symmetric difference (a point is inside
/// when an odd number of the nested shells enclose it).
std::optional<Nef> nef_of(const PolygonMesh& solid) {
  const size_t nv = solid.vertices.size();
  UnionFind components(nv);
  for (size_t f = 0; f < solid.face_count(); ++f) {
    const auto v = solid.face(f);
    for (size_t k = 1; k < v.size(); ++k) components.unite(v[0], v[k]);
  }
  std::vector<std::vector<uint32_t>> faces_of(nv);  // per component root: its faces
  for (uint32_t f = 0; f < solid.face_count(); ++f)
    faces_of[components.find(solid.face(f)[0])].push_back(f);
  std::optional<Nef> out;
  for (const std::vector<uint32_t>& faces : faces_of) {
    if (faces.empty()) continue;
    Mesh mesh;
    std::vector<Mesh::Vertex_index> vs(nv, Mesh::null_vertex());
    for (uint32_t f : faces) {
      std::vector<Mesh::Vertex_index> loop;
      for (uint32_t v : solid.face(f)) {
        if (vs[v] == Mesh::null_vertex()) vs[v] = mesh.add_vertex(point(solid.vertices[v]));
        loop.push_back(vs[v]);
      }
      if (mesh.add_face(loop) == Mesh::null_face()) return std::nullopt;
    }
    if (!CGAL::is_closed(mesh)) return std::nullopt;
    Nef component(mesh);
    if (out)
      *out = *out ^ component;
    else
      out.emplace(std::move(component));
  }
  return out;
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
    std::optional<Nef> nef = nef_of(piece);
    if (!nef || !nef->is_simple()) return {};
    return parts_of(*nef);
  } catch (const std::exception&) {
    return {};
  }
}

struct ShellRegions::Impl {
  std::optional<Nef> shell;  ///< nullopt when the shell is no closed 2-manifold
};

ShellRegions::ShellRegions(const PolygonMesh& shell) : impl_(std::make_unique<Impl>()) {
  try {
    impl_->shell = nef_of(shell);
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
