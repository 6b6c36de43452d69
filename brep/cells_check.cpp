// The exact check of cell pieces as written (brep/detail/cells_check.h).
#include "cover/brep/detail/cells_check.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <cstdint>

#include "cover/brep/cells.h"
#include "cover/mesh/triangulate.h"
#include "cover/mesh/validate.h"
#include "cover/solid/predicates.h"

namespace cover::brep::detail {
namespace {

bool on_one_coordinate(const PolygonMesh& mesh, std::span<const uint32_t> loop) {
  for (int a = 0; a < 3; ++a) {
    const double c = mesh.vertices[loop[0]][a];
    bool same = true;
    for (uint32_t v : loop) same = same && mesh.vertices[v][a] == c;
    if (same) return true;
  }
  return false;
}

/// Sign of the volume of the closed mesh: the sum of the fan triangles' det[a, b, c] / 6, in
/// doubles with an error bound, exact (rationals) when the bound does not separate it from 0.
int volume_sign(const PolygonMesh& mesh) {
  double sum = 0, magnitude = 0;
  size_t terms = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    const Vec3& a = mesh.vertices[loop[0]];
    for (size_t i = 1; i + 1 < loop.size(); ++i) {
      const Vec3& b = mesh.vertices[loop[i]];
      const Vec3& c = mesh.vertices[loop[i + 1]];
      sum += dot(a, cross(b, c));
      magnitude += std::abs(a.x) * (std::abs(b.y * c.z) + std::abs(b.z * c.y)) +
                   std::abs(a.y) * (std::abs(b.z * c.x) + std::abs(b.x * c.z)) +
                   std::abs(a.z) * (std::abs(b.x * c.y) + std::abs(b.y * c.x));
      ++terms;
    }
  }
  // Each term is within 4u of its magnitude, the running sum adds u per addition (u = 2^-53);
  // the factor 2 covers the rounding of the bound itself.
  const double bound = 2 * (8 + static_cast<double>(terms)) * 0x1p-53 * magnitude;
  if (std::abs(sum) > bound) return sum > 0 ? 1 : -1;
  CGAL::Exact_rational exact = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    const Vec3& a = mesh.vertices[loop[0]];
    for (size_t i = 1; i + 1 < loop.size(); ++i) {
      const Vec3& b = mesh.vertices[loop[i]];
      const Vec3& c = mesh.vertices[loop[i + 1]];
      using Q = CGAL::Exact_rational;
      exact += Q(a.x) * (Q(b.y) * Q(c.z) - Q(b.z) * Q(c.y)) +
               Q(a.y) * (Q(b.z) * Q(c.x) - Q(b.x) * Q(c.z)) +
               Q(a.z) * (Q(b.x) * Q(c.y) - Q(b.y) * Q(c.x));
    }
  }
  return CGAL::sign(exact);
}

/// The triangles of face `loop`: triangulate_face's tiles when they cover it (n − 2 of them);
/// for a quad whose tiling drops a collinear triangle (a sliver of rounded points), the other
/// diagonal if neither of its triangles is collinear. False when neither works.
bool face_triangles(const PolygonMesh& mesh, std::span<const uint32_t> loop,
                    std::vector<std::array<uint32_t, 3>>& tris) {
  tris.clear();
  if (loop.size() == 3) {
    tris.push_back({loop[0], loop[1], loop[2]});
    return true;
  }
  if (triangulate_face(mesh.vertices, loop, tris) == FaceTiling::kSimple &&
      tris.size() + 2 == loop.size())
    return true;
  if (loop.size() != 4) return false;
  for (int d = 0; d < 2; ++d) {
    const uint32_t a = loop[d], b = loop[d + 1], c = loop[d + 2], e = loop[(d + 3) % 4];
    const std::array<uint32_t, 3> t0{a, b, c}, t1{a, c, e};
    if (!all_collinear(mesh.vertices, t0) && !all_collinear(mesh.vertices, t1)) {
      tris = {t0, t1};
      return true;
    }
  }
  return false;
}

/// CGAL's exact self-intersection test (Polygon_mesh_processing::does_self_intersect, Epick
/// predicates on the doubles) of the faces' tiles; false also when a face cannot be tiled.
bool cgal_self_intersects(const PolygonMesh& mesh) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  namespace PMP = CGAL::Polygon_mesh_processing;
  std::vector<K::Point_3> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) points.emplace_back(p.x, p.y, p.z);
  std::vector<std::array<size_t, 3>> tris;
  std::vector<std::array<uint32_t, 3>> tiles;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    if (!face_triangles(mesh, loop, tiles)) return true;
    for (const auto& t : tiles) tris.push_back({t[0], t[1], t[2]});
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(tris)) return true;
  CGAL::Surface_mesh<K::Point_3> sm;
  PMP::polygon_soup_to_polygon_mesh(points, tris, sm);
  return PMP::does_self_intersect(sm);
}

}  // namespace

template <class Kind>
void triangulate_nonplanar(PolygonMesh& mesh, std::vector<Kind>& kinds) {
  bool any = false;
  for (size_t f = 0; f < mesh.face_count() && !any; ++f)
    any = mesh.face(f).size() > 3 && !on_one_coordinate(mesh, mesh.face(f));
  if (!any) return;
  PolygonMesh out;
  out.vertices = mesh.vertices;
  std::vector<Kind> out_kinds;
  std::vector<std::array<uint32_t, 3>> tris;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    tris.clear();
    if (loop.size() > 3 && !on_one_coordinate(mesh, loop) && face_triangles(mesh, loop, tris)) {
      for (const auto& t : tris) {
        out.add_face({t[0], t[1], t[2]});
        if (!kinds.empty()) out_kinds.push_back(kinds[f]);
      }
    } else {
      out.add_face(loop);
      if (!kinds.empty()) out_kinds.push_back(kinds[f]);
    }
  }
  mesh = std::move(out);
  if (!kinds.empty()) kinds = std::move(out_kinds);
}

template void triangulate_nonplanar<CellFace>(PolygonMesh&, std::vector<CellFace>&);
template void triangulate_nonplanar<uint8_t>(PolygonMesh&, std::vector<uint8_t>&);

std::string invalid_reason(const PolygonMesh& mesh, bool contacts_allowed) {
  if (mesh.face_count() == 0) return "";
  ValidateOptions options;
  options.check_self_intersection = false;
  const MeshReport r = validate_mesh(mesh, options);
  if (!r.closed) return "not closed";
  if (!r.oriented || r.nonmanifold_edges > 0) return "not an oriented 2-manifold";
  if (!r.manifold) return "a vertex whose faces form more than one fan";
  if (r.degenerate_faces > 0) return "a face with all its vertices on one line";
  if (!contacts_allowed && cgal_self_intersects(mesh)) return "it intersects or touches itself";
  if (volume_sign(mesh) <= 0) return "inside out (volume not positive)";
  return "";
}

}  // namespace cover::brep::detail
