#include "checks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "cgal_oracle.h"
#include "cover/boolean/evaluate.h"
#include "cover/brep/cells.h"
#include "cover/brep/decompose.h"
#include "cover/brep/halfedge.h"
#include "cover/mesh/validate.h"
#include "cover/model/model.h"
#include "cover/solid/errors.h"
#include "cover/solid/measure.h"

namespace cover::stress {
namespace {

std::string fmt(const char* format, double a, double b) {
  char text[200];
  std::snprintf(text, sizeof text, format, a, b);
  return text;
}

/// `mesh` with vertices of equal coordinates merged into the lowest index.
PolygonMesh welded(const PolygonMesh& mesh, bool& had_duplicates) {
  std::vector<uint32_t> order(mesh.vertices.size()), to(mesh.vertices.size());
  for (uint32_t v = 0; v < order.size(); ++v) order[v] = v;
  auto key = [&](uint32_t v) {
    const Vec3& p = mesh.vertices[v];
    return std::array<double, 3>{p.x, p.y, p.z};
  };
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return key(a) != key(b) ? key(a) < key(b) : a < b; });
  had_duplicates = false;
  for (size_t i = 0; i < order.size(); ++i) {
    const bool same = i > 0 && key(order[i]) == key(order[i - 1]);
    to[order[i]] = same ? to[order[i - 1]] : order[i];
    had_duplicates = had_duplicates || same;
  }
  PolygonMesh out;
  out.vertices = mesh.vertices;
  std::vector<uint32_t> loop;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    loop.clear();
    for (uint32_t v : mesh.face(f)) loop.push_back(to[v]);
    out.add_face(loop);
  }
  return out;
}

double box_volume(const Bbox& b) {
  if (b.empty()) return 0;
  const Vec3 e = b.max - b.min;
  return e.x * e.y * e.z;
}

}  // namespace

Outcome check_mesh(const PolygonMesh& mesh) {
  if (mesh.face_count() == 0) return {};
  std::string cover_problem;
  bool structural = false;  // a problem other than self-intersection or degenerate faces
  const MeshReport r = validate_mesh(mesh);
  auto add = [&](const std::string& what, bool is_structural) {
    cover_problem += (cover_problem.empty() ? "" : ", ") + what;
    structural = structural || is_structural;
  };
  if (!r.closed) add("not closed", true);
  if (!r.oriented) add("not oriented", true);
  if (!r.manifold) add("not manifold", true);
  // validate_mesh decides outward on the volume in doubles: a sliver is decided exactly.
  if (r.closed && r.oriented && !r.outward && exact_volume_sign(mesh) <= 0)
    add("not outward", true);
  if (r.self_intersecting.value_or(false)) add("self-intersecting", false);
  if (r.degenerate_faces > 0) add(std::to_string(r.degenerate_faces) + " degenerate faces", false);
  try {
    const brep::BrepReport b = brep::validate(brep::HalfedgeMesh::from_polygon_mesh(mesh));
    if (!b.consistent || !b.closed || !b.manifold)
      add("half-edge mesh not a closed 2-manifold", true);
  } catch (const std::exception& e) {
    add(std::string("half-edge mesh: ") + e.what(), true);
  }
  const std::string cgal = cgal_mesh_problem(mesh);
  if (cover_problem.empty() && cgal.empty()) return {};
  const std::string detail =
      "Cover: " + (cover_problem.empty() ? std::string("valid") : cover_problem) + "; " +
      (cgal.empty() ? std::string("CGAL: valid") : cgal);
  if (structural || !(cgal.empty() || cgal == "CGAL: self-intersecting"))
    return {"invalid", detail};
  // Left: self-intersections (Cover's or CGAL's) and zero-area faces.
  if (!r.self_intersecting.value_or(false) && r.degenerate_faces > 0)
    return {"degenerate", detail + " (CGAL counts a collinear face as a self-intersection)"};
  bool duplicates = false;
  const PolygonMesh w = welded(mesh, duplicates);
  if (duplicates && !self_intersects(w))
    return {"touching", detail + " (only at vertices of equal coordinates)"};
  return {"invalid", detail};
}

bool volume_matches(double value, double reference, double floor) {
  return std::abs(value - reference) <= 1e-9 * std::max(std::abs(reference), floor);
}

Outcome stage_evaluate(const Solid& solid, std::optional<double> reference, PolygonMesh& mesh) {
  EvaluateResult r = evaluate(solid);
  mesh = std::move(r.mesh);
  Outcome o = check_mesh(mesh);
  if (o.kind != "ok") return {o.kind, o.detail, mesh};
  if (reference && !volume_matches(r.volume, *reference, 1e-3 * box_volume(solid.bbox())))
    return {"volume", fmt("volume %.17g, CGAL corefinement %.17g", r.volume, *reference)};
  return {};
}

Outcome stage_cells(const Solid& solid, const PolygonMesh& mesh, int n) {
  const VoxelBounds b = Model(solid).voxel_bounds(n);
  const brep::CellGrid grid{b.min, b.size, n};
  const brep::CellsResult r = brep::cut_cells(mesh, grid);
  const double volume = signed_volume(mesh);
  const double floor = 1e-3 * box_volume(solid.bbox());
  double sum = 0;
  for (const brep::CellPiece& piece : r.pieces) {
    const std::string cell = "piece (" + std::to_string(piece.cell[0]) + "," +
                             std::to_string(piece.cell[1]) + "," + std::to_string(piece.cell[2]) +
                             ")";
    const Outcome o = check_mesh(piece.mesh);
    if (o.kind != "ok") return {o.kind, cell + ": " + o.detail, piece.mesh};
    const Bbox pb = face_bbox(piece.mesh);
    for (int a = 0; a < 3; ++a)
      if (pb.min[a] < brep::cell_wall(grid, a, piece.cell[a]) ||
          pb.max[a] > brep::cell_wall(grid, a, piece.cell[a] + 1))
        return {"invalid", cell + ": outside its cell on axis " + "xyz"[a], piece.mesh};
    sum += signed_volume(piece.mesh);
  }
  if (!volume_matches(sum, volume, floor))
    return {"volume", fmt("pieces sum to %.17g, evaluate %.17g", sum, volume)};
  const Outcome g = check_mesh(r.glued);
  if (g.kind != "ok") return {g.kind, "glued: " + g.detail, r.glued};
  if (!volume_matches(signed_volume(r.glued), volume, floor))
    return {"volume", fmt("glued %.17g, evaluate %.17g", signed_volume(r.glued), volume)};
  return {};
}

Outcome stage_decompose(const Solid& solid, const PolygonMesh& mesh) {
  const brep::DecomposeResult r = brep::decompose(mesh);
  const double volume = signed_volume(mesh);
  double sum = 0;
  for (size_t i = 0; i < r.pieces.size(); ++i) {
    const std::string piece =
        "piece " + std::to_string(i) + " of " + std::to_string(r.pieces.size());
    const Outcome o = check_mesh(r.pieces[i]);
    if (o.kind != "ok") return {o.kind, piece + ": " + o.detail, r.pieces[i]};
    const std::string convex = cgal_convexity_problem(r.pieces[i]);
    if (!convex.empty()) return {"not-convex", piece + ": " + convex, r.pieces[i]};
    sum += signed_volume(r.pieces[i]);
  }
  if (!volume_matches(sum, volume, 1e-3 * box_volume(solid.bbox())))
    return {"volume", fmt("pieces sum to %.17g, evaluate %.17g", sum, volume)};
  return {};
}

Outcome outcome_of_exception() {
  try {
    throw;
  } catch (const NotComputable& e) {
    return {"refused", e.what()};
  } catch (const InputError& e) {
    return {"bad-input", e.what()};
  } catch (const std::bad_alloc&) {
    return {"memory", "std::bad_alloc"};
  } catch (const InternalError& e) {
    return {"internal", e.what()};
  } catch (const std::exception& e) {
    return {"internal", e.what()};
  } catch (...) {
    return {"internal", "a non-standard exception"};
  }
}

}  // namespace cover::stress
