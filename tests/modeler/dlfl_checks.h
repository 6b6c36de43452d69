#pragma once
// Shared checks of the modeler tests: whole-mesh snapshots (every id and link) and the totals
// the operators change (V, E, F, components, genus).

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <vector>

#include "cover/modeler/dlfl.h"
#include "cover/solid/primitives.h"
#include "helpers.h"

namespace cover::modeler::test {

/// V, E, F, the number of components and their total genus.
struct Totals {
  size_t vertices = 0, edges = 0, faces = 0, components = 0;
  int genus = 0;
  friend bool operator==(const Totals&, const Totals&) = default;
};

inline Totals totals(const DlflMesh& mesh) {
  Totals t{mesh.vertex_count(), mesh.edge_count(), mesh.face_count(), 0, 0};
  for (const ComponentInfo& c : components(mesh)) {
    ++t.components;
    t.genus += c.genus;
  }
  return t;
}

inline std::ostream& operator<<(std::ostream& out, const Totals& t) {
  return out << "V " << t.vertices << " E " << t.edges << " F " << t.faces << " components "
             << t.components << " genus " << t.genus;
}

/// Every live id with its links: half-edges (next, head, face), vertices (position, outgoing
/// half-edge, point-sphere face), faces (point-sphere vertex, the loop as a cyclic sequence
/// started at its smallest half-edge), rotations as cyclic sequences.
struct Snapshot {
  std::vector<std::tuple<HalfedgeId, HalfedgeId, VertexId, FaceId>> halfedges;
  std::vector<std::tuple<VertexId, double, double, double, bool>> vertices;
  std::vector<std::tuple<FaceId, VertexId, std::vector<HalfedgeId>>> faces;
  std::vector<std::vector<HalfedgeId>> rotations;
  friend bool operator==(const Snapshot&, const Snapshot&) = default;
};

inline std::vector<HalfedgeId> canonical_cycle(std::vector<HalfedgeId> cycle) {
  if (!cycle.empty())
    std::rotate(cycle.begin(), std::min_element(cycle.begin(), cycle.end()), cycle.end());
  return cycle;
}

inline Snapshot snapshot(const DlflMesh& mesh) {
  Snapshot s;
  for (HalfedgeId h = 0; h < 2 * mesh.edge_capacity(); ++h)
    if (mesh.halfedge_alive(h))
      s.halfedges.emplace_back(h, mesh.next(h), mesh.head(h), mesh.face(h));
  for (VertexId v = 0; v < mesh.vertex_capacity(); ++v) {
    if (!mesh.vertex_alive(v)) continue;
    const Vec3& p = mesh.position(v);
    s.vertices.emplace_back(v, p.x, p.y, p.z, mesh.is_point_sphere(v));
    s.rotations.push_back(canonical_cycle(mesh.rotation(v)));
  }
  for (FaceId f = 0; f < mesh.face_capacity(); ++f)
    if (mesh.face_alive(f))
      s.faces.emplace_back(f, mesh.face_point_sphere(f), canonical_cycle(mesh.face_loop(f)));
  return s;
}

/// The unit cube [0, 1]³ as a DLFL (6 quads).
inline DlflMesh cube(Vec3 min = {0, 0, 0}, Vec3 max = {1, 1, 1}) {
  return from_polygon_mesh(make_box(min, max));
}

}  // namespace cover::modeler::test
