#pragma once
// Checks of brep::cut_cells shared by the cells tests and the evaluate tests: every piece a
// closed, outward 2-manifold without self-intersections (kernel validity + CGAL's exact test,
// check_half), the pieces' volumes summing to the mesh's, and the glued pieces the same solid as
// the mesh (volume to 1e-12 relative, valid, same genus).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "brep_checks.h"
#include "cover/brep/cells.h"
#include "cover/solid/measure.h"

namespace cover::test {

/// CGAL's verdict on `mesh` as written (an independent oracle of Cover's own checks): a polygon
/// mesh (each edge used once each way), closed, outward (Polygon_mesh_processing::
/// is_outward_oriented) and, its faces triangulated by CGAL, free of self-intersections
/// (does_self_intersect, exact predicates on the doubles). "" when valid, else what failed.
inline std::string cgal_verdict(const PolygonMesh& mesh) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  namespace PMP = CGAL::Polygon_mesh_processing;
  if (mesh.face_count() == 0) return "";
  std::vector<K::Point_3> points;
  for (const Vec3& p : mesh.vertices) points.emplace_back(p.x, p.y, p.z);
  std::vector<std::vector<size_t>> faces;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto loop = mesh.face(f);
    faces.emplace_back(loop.begin(), loop.end());
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(faces)) return "not a polygon mesh";
  CGAL::Surface_mesh<K::Point_3> sm;
  PMP::polygon_soup_to_polygon_mesh(points, faces, sm);
  if (!CGAL::is_closed(sm)) return "open";
  if (!PMP::triangulate_faces(sm)) return "faces CGAL cannot triangulate";
  if (PMP::does_self_intersect(sm)) return "self-intersecting";
  if (!PMP::is_outward_oriented(sm)) return "inside out";
  return "";
}

/// The cube around `mesh`'s box, enlarged by `margin` of its largest extent on every side.
inline brep::CellGrid cells_around(const PolygonMesh& mesh, int n, double margin = 0.01) {
  const Bbox b = face_bbox(mesh);
  const double ext = std::max({b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z});
  return {b.min - Vec3{margin * ext, margin * ext, margin * ext}, (1 + 2 * margin) * ext, n};
}

/// What expect_valid_cells tolerates, printing a note instead of failing.
struct CellsTolerance {
  /// A mesh that intersects itself (outside cut_cells' precondition) is not cut.
  bool self_intersecting_input = false;
};

/// Cuts `mesh` (closed, outward, valid) into the cells of `grid` and checks pieces and glue; the
/// cube is expected to contain `mesh`. Returns the result for further checks.
inline brep::CellsResult expect_valid_cells(const PolygonMesh& mesh, const brep::CellGrid& grid,
                                            const std::string& what,
                                            const CellsTolerance& tolerate = {}) {
  const std::string label = what + " n=" + std::to_string(grid.n);
  const HalfCheck input = check_half(mesh, {}, -1);
  if (tolerate.self_intersecting_input && input.self_intersecting) {
    std::printf("note: %s: the mesh intersects itself; not cut into cells\n", label.c_str());
    return {};
  }
  brep::CellsResult r = brep::cut_cells(mesh, grid);
  EXPECT_EQ(r.rounding_contacts, 0) << label;
  if (r.forced_ears > 0 || r.collapsed_edges > 0)
    std::printf("note: %s: %lld forced ears, %lld rounding-scale edges collapsed\n", label.c_str(),
                static_cast<long long>(r.forced_ears), static_cast<long long>(r.collapsed_edges));
  const double volume = signed_volume(mesh);
  double sum = 0;
  for (const brep::CellPiece& piece : r.pieces) {
    const std::string cell = label + " cell " + std::to_string(piece.cell[0]) + "," +
                             std::to_string(piece.cell[1]) + "," + std::to_string(piece.cell[2]);
    const HalfCheck c = check_half(piece.mesh, {}, -1);
    EXPECT_TRUE(c.report.consistent && c.report.closed && c.report.manifold) << cell;
    EXPECT_FALSE(c.self_intersecting) << cell;
    EXPECT_GT(piece.volume, 0) << cell;
    EXPECT_EQ(piece.faces.size(), piece.mesh.face_count()) << cell;
    const Bbox b = face_bbox(piece.mesh);
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(b.min[a], brep::cell_wall(grid, a, piece.cell[a])) << cell;
      EXPECT_LE(b.max[a], brep::cell_wall(grid, a, piece.cell[a] + 1)) << cell;
    }
    sum += piece.volume;
  }
  EXPECT_NEAR(sum, volume, 1e-11 * std::abs(volume)) << label;
  if (mesh.face_count() == 0) {
    EXPECT_TRUE(r.pieces.empty()) << label;
    return r;
  }
  const HalfCheck glued = check_half(r.glued, {}, -1);
  EXPECT_TRUE(glued.report.consistent && glued.report.closed && glued.report.manifold) << label;
  EXPECT_FALSE(glued.self_intersecting) << label;
  EXPECT_EQ(glued.report.genus, input.report.genus) << label;
  EXPECT_EQ(glued.report.components, input.report.components) << label;
  EXPECT_NEAR(glued.volume, volume, 1e-12 * std::abs(volume)) << label;
  EXPECT_NEAR(surface_area(r.glued), surface_area(mesh), 1e-12 * surface_area(mesh)) << label;
  return r;
}

}  // namespace cover::test
