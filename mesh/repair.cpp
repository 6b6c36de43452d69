#include "cover/mesh/repair.h"

#include <unordered_map>
#include <vector>

#include "cover/solid/predicates.h"
#include "cover/solid/vec3_hash.h"

namespace cover {

size_t weld_duplicate_vertices(PolygonMesh& mesh) {
  std::unordered_map<Vec3, uint32_t, detail::Vec3Hash> first;
  first.reserve(mesh.vertices.size());
  std::vector<uint32_t> to(mesh.vertices.size());
  size_t merged = 0;
  for (uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    const auto [it, added] = first.try_emplace(mesh.vertices[v], v);  // == treats −0 as +0
    to[v] = it->second;
    merged += added ? 0 : 1;
  }
  if (merged > 0)
    for (uint32_t& v : mesh.face_vertices) v = to[v];
  return merged;
}

size_t drop_zero_area_faces(PolygonMesh& mesh) {
  PolygonMesh kept;
  size_t dropped = 0;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    if (all_collinear(mesh.vertices, mesh.face(f))) {
      ++dropped;
      continue;
    }
    kept.add_face(mesh.face(f));
  }
  if (dropped > 0) {
    mesh.face_start = std::move(kept.face_start);
    mesh.face_vertices = std::move(kept.face_vertices);
  }
  return dropped;
}

RepairReport repair_report(const PolygonMesh& mesh, const MeshReport& report) {
  RepairReport out;
  out.boundary_edges = report.boundary_edges;
  out.edges = report.edges;
  if (report.boundary_edges == 0) return out;
  PolygonMesh repaired = mesh;
  out.welded_vertices = static_cast<int64_t>(weld_duplicate_vertices(repaired));
  out.zero_area_faces = static_cast<int64_t>(drop_zero_area_faces(repaired));
  ValidateOptions quick;
  quick.check_self_intersection = false;
  const MeshReport after = validate_mesh(repaired, quick);
  out.boundary_edges = after.boundary_edges;
  out.edges = after.edges;
  return out;
}

}  // namespace cover
