// The DLFL's validity check and its components (notation in dlfl.h).

#include <string>

#include "cover/modeler/dlfl.h"
#include "cover/solid/errors.h"
#include "cover/solid/union_find.h"

namespace cover::modeler {

namespace {

[[noreturn]] void fail(const std::string& what) { throw InternalError("dlfl: " + what); }

std::string name(const char* kind, uint32_t id) {
  return std::string(kind) + " " + std::to_string(id);
}

}  // namespace

std::vector<uint32_t> vertex_components(const DlflMesh& mesh) {
  const size_t n = mesh.vertex_capacity();
  UnionFind sets(n);
  for (EdgeId e = 0; e < mesh.edge_capacity(); ++e)
    if (mesh.edge_alive(e)) sets.unite(mesh.tail(2 * e), mesh.head(2 * e));
  std::vector<uint32_t> root_index(n, kNone), component(n, kNone);
  uint32_t count = 0;
  for (VertexId v = 0; v < n; ++v) {
    if (!mesh.vertex_alive(v)) continue;
    uint32_t& index = root_index[sets.find(v)];
    if (index == kNone) index = count++;
    component[v] = index;
  }
  return component;
}

std::vector<ComponentInfo> components(const DlflMesh& mesh) {
  const std::vector<uint32_t> component = vertex_components(mesh);
  std::vector<ComponentInfo> info;
  auto at = [&](VertexId v) -> ComponentInfo& {
    if (component[v] >= info.size()) info.resize(component[v] + 1);
    return info[component[v]];
  };
  for (VertexId v = 0; v < mesh.vertex_capacity(); ++v)
    if (mesh.vertex_alive(v)) ++at(v).vertices;
  for (EdgeId e = 0; e < mesh.edge_capacity(); ++e)
    if (mesh.edge_alive(e)) ++at(mesh.head(2 * e)).edges;
  for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
    if (!mesh.face_alive(f)) continue;
    const HalfedgeId h = mesh.face_halfedge(f);
    ++at(h == kNone ? mesh.face_point_sphere(f) : mesh.head(h)).faces;
  }
  for (ComponentInfo& c : info) {
    const auto euler = static_cast<long long>(c.vertices) - static_cast<long long>(c.edges) +
                       static_cast<long long>(c.faces);
    c.genus = static_cast<int>((2 - euler) / 2);
  }
  return info;
}

void check_valid(const DlflMesh& mesh) {
  size_t vertices = 0, halfedges = 0, faces = 0;
  // Half-edges: live links, inverse next/prev, heads meet tails, faces agree along next.
  for (HalfedgeId h = 0; h < 2 * mesh.edge_capacity(); ++h) {
    if (!mesh.halfedge_alive(h)) continue;
    ++halfedges;
    const HalfedgeId n = mesh.next(h);
    if (!mesh.halfedge_alive(n) || !mesh.halfedge_alive(mesh.prev(h)))
      fail(name("half-edge", h) + ": next or prev is not live");
    if (mesh.prev(n) != h) fail(name("half-edge", h) + ": prev(next(h)) != h");
    if (!mesh.vertex_alive(mesh.head(h))) fail(name("half-edge", h) + ": head is not live");
    if (mesh.tail(n) != mesh.head(h)) fail(name("half-edge", h) + ": tail(next(h)) != head(h)");
    if (!mesh.face_alive(mesh.face(h))) fail(name("half-edge", h) + ": face is not live");
    if (mesh.face(n) != mesh.face(h)) fail(name("half-edge", h) + ": face(next(h)) != face(h)");
  }
  // Faces: each loop holds exactly the half-edges labelled with its face (the loop lengths add
  // up to all half-edges, so no orbit is left without its own face).
  size_t loop_total = 0;
  for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
    if (!mesh.face_alive(f)) continue;
    ++faces;
    const HalfedgeId h = mesh.face_halfedge(f);
    if (h == kNone) {
      const VertexId v = mesh.face_point_sphere(f);
      if (!mesh.vertex_alive(v) || !mesh.is_point_sphere(v) || mesh.point_sphere_face(v) != f)
        fail(name("face", f) + ": edgeless face without its point-sphere");
      continue;
    }
    if (!mesh.halfedge_alive(h) || mesh.face(h) != f)
      fail(name("face", f) + ": its half-edge is not in it");
    HalfedgeId g = h;
    do {
      if (++loop_total > halfedges) fail(name("face", f) + ": loops overlap");
      g = mesh.next(g);
    } while (g != h);
  }
  if (loop_total != halfedges) fail("some half-edges are in no face's loop");
  // Vertices: each rotation holds exactly the outgoing half-edges (a manifold vertex); the
  // rotation successors, kept apart, trace the stored faces.
  std::vector<HalfedgeId> rotation_next(2 * mesh.edge_capacity(), kNone);
  size_t rotation_total = 0;
  for (VertexId v = 0; v < mesh.vertex_capacity(); ++v) {
    if (!mesh.vertex_alive(v)) continue;
    ++vertices;
    if (mesh.is_point_sphere(v)) {
      const FaceId f = mesh.point_sphere_face(v);
      if (!mesh.face_alive(f) || mesh.face_point_sphere(f) != v)
        fail(name("vertex", v) + ": point-sphere without its face");
      continue;
    }
    const HalfedgeId h = mesh.vertex_halfedge(v);
    if (!mesh.halfedge_alive(h) || mesh.tail(h) != v)
      fail(name("vertex", v) + ": its half-edge does not leave it");
    HalfedgeId g = h;
    do {
      if (mesh.tail(g) != v) fail(name("vertex", v) + ": rotation leaves the vertex");
      if (++rotation_total > halfedges) fail(name("vertex", v) + ": rotations overlap");
      const HalfedgeId following = mesh.next(DlflMesh::twin(g));
      rotation_next[g] = following;
      g = following;
    } while (g != h);
  }
  if (rotation_total != halfedges) fail("a vertex's half-edges form more than one rotation");
  for (HalfedgeId h = 0; h < rotation_next.size(); ++h)
    if (mesh.halfedge_alive(h) && rotation_next[DlflMesh::twin(h)] != mesh.next(h))
      fail(name("half-edge", h) + ": the face traced from the rotations differs");
  if (vertices != mesh.vertex_count() || halfedges != 2 * mesh.edge_count() ||
      faces != mesh.face_count())
    fail("the stored counts differ from the live elements");
  for (const ComponentInfo& c : components(mesh)) {
    const auto euler = static_cast<long long>(c.vertices) - static_cast<long long>(c.edges) +
                       static_cast<long long>(c.faces);
    if (euler > 2 || euler % 2 != 0)
      fail("a component has Euler characteristic " + std::to_string(euler));
  }
}

}  // namespace cover::modeler
