#include "cgal_oracle.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include "cover/mesh/triangulate.h"

namespace cover::stress {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;

/// The triangles of `mesh` (every face tiled by triangulate_face); false when a face's boundary
/// crosses itself.
bool triangles(const PolygonMesh& mesh, std::vector<std::array<uint32_t, 3>>& out) {
  const std::span<const Vec3> points(mesh.vertices.data(), mesh.vertices.size());
  for (size_t f = 0; f < mesh.face_count(); ++f)
    if (triangulate_face(points, mesh.face(f), out) == FaceTiling::kCrossing) return false;
  return true;
}

/// `mesh` as a CGAL Surface_mesh with the same vertex indices and faces, then triangulated by
/// CGAL (PMP::triangulate_faces: vertices in the middle of a straight side stay corners of
/// non-degenerate triangles); an empty string, or the reason why it cannot be built: the faces
/// are not a 2-manifold polygon mesh (is_polygon_soup_a_polygon_mesh), or a face has no
/// triangulation.
template <class K>
std::string to_surface_mesh(const PolygonMesh& mesh, CGAL::Surface_mesh<typename K::Point_3>& out) {
  std::vector<std::vector<std::size_t>> faces;
  faces.reserve(mesh.face_count());
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    faces.emplace_back(loop.begin(), loop.end());
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces)) return "not a 2-manifold polygon mesh";
  std::vector<typename K::Point_3> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) points.emplace_back(p.x, p.y, p.z);
  PMP::polygon_soup_to_polygon_mesh(points, faces, out);
  if (!CGAL::is_closed(out)) return "not closed";
  if (!PMP::triangulate_faces(out)) return "a face has no triangulation";
  return {};
}

using ExactMesh = CGAL::Surface_mesh<Epeck::Point_3>;

/// The corefined result of tree node `node`; throws std::runtime_error naming what CGAL refused.
ExactMesh corefine_node(const Solid& solid, uint32_t node) {
  const CsgNode& n = solid.tree.nodes.at(node);
  if (n.op == CsgOp::kLeaf) {
    ExactMesh m;
    const std::string why = to_surface_mesh<Epeck>(leaf_mesh(solid, n.leaf), m);
    if (!why.empty()) throw std::runtime_error("leaf " + std::to_string(n.leaf) + ": " + why);
    return m;
  }
  if (n.op == CsgOp::kComplement) throw std::runtime_error("a complement (unbounded)");
  ExactMesh acc = corefine_node(solid, n.children.at(0));
  for (size_t k = 1; k < n.children.size(); ++k) {
    ExactMesh other = corefine_node(solid, n.children[k]), out;
    bool ok = false;
    if (n.op == CsgOp::kUnion) ok = PMP::corefine_and_compute_union(acc, other, out);
    if (n.op == CsgOp::kIntersection) ok = PMP::corefine_and_compute_intersection(acc, other, out);
    if (n.op == CsgOp::kDifference) ok = PMP::corefine_and_compute_difference(acc, other, out);
    if (!ok)
      throw std::runtime_error("corefinement refused the operation at node " +
                               std::to_string(node));
    acc = std::move(out);
  }
  return acc;
}

}  // namespace

std::optional<double> corefined_volume(const Solid& solid, std::string& why) {
  try {
    if (solid.tree.nodes.empty()) return 0.0;
    const ExactMesh result = corefine_node(solid, solid.tree.root);
    return CGAL::to_double(PMP::volume(result));
  } catch (const std::exception& e) {
    why = e.what();
    return std::nullopt;
  }
}

std::string cgal_mesh_problem(const PolygonMesh& mesh) {
  if (mesh.face_count() == 0) return {};
  using Mesh = CGAL::Surface_mesh<Epick::Point_3>;
  Mesh m;
  const std::string why = to_surface_mesh<Epick>(mesh, m);
  if (!why.empty()) return "CGAL: " + why;
  if (PMP::does_self_intersect(m)) return "CGAL: self-intersecting";
  // Closed and free of self-intersections: the orientation of every component against its
  // nesting (exact predicates) decides outward; a flat piece cannot get here.
  if (!PMP::does_bound_a_volume(m)) return "CGAL: does not bound a volume (orientation)";
  return {};
}

int exact_volume_sign(const PolygonMesh& mesh) {
  using Q = CGAL::Exact_rational;
  const auto& v = mesh.vertices;
  Q sum = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    const Vec3& a = v[loop[0]];
    for (size_t k = 1; k + 1 < loop.size(); ++k) {
      const Vec3& b = v[loop[k]];
      const Vec3& c = v[loop[k + 1]];
      sum += Q(a.x) * (Q(b.y) * Q(c.z) - Q(b.z) * Q(c.y)) -
             Q(a.y) * (Q(b.x) * Q(c.z) - Q(b.z) * Q(c.x)) +
             Q(a.z) * (Q(b.x) * Q(c.y) - Q(b.y) * Q(c.x));
    }
  }
  return CGAL::sign(sum);
}

std::string cgal_convexity_problem(const PolygonMesh& piece) {
  std::vector<std::array<uint32_t, 3>> tris;
  if (!triangles(piece, tris)) return "a face crosses itself";
  const auto& v = piece.vertices;
  std::vector<Epick::Point_3> p;
  p.reserve(v.size());
  for (const Vec3& q : v) p.emplace_back(q.x, q.y, q.z);
  size_t outside = 0;
  double worst = 0;
  for (const auto& t : tris) {
    const Vec3 n = cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]]);
    const double len = std::sqrt(dot(n, n));
    for (size_t i = 0; i < p.size(); ++i) {
      if (CGAL::orientation(p[t[0]], p[t[1]], p[t[2]], p[i]) != CGAL::POSITIVE) continue;
      ++outside;
      if (len > 0) worst = std::max(worst, dot(n, v[i] - v[t[0]]) / len);
    }
  }
  if (outside == 0) return {};
  char text[160];
  std::snprintf(text, sizeof text,
                "not convex: %zu vertex-plane pairs outside, largest distance %.3g", outside,
                worst);
  return text;
}

}  // namespace cover::stress
