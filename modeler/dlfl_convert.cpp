// Conversion between PolygonMesh and DlflMesh (notation in dlfl.h).

#include <string>
#include <unordered_map>

#include "cover/modeler/dlfl.h"
#include "cover/solid/errors.h"

namespace cover::modeler {

namespace {

std::string pair_text(uint32_t u, uint32_t w) {
  return "(" + std::to_string(u) + ", " + std::to_string(w) + ")";
}

}  // namespace

DlflMesh from_polygon_mesh(const PolygonMesh& mesh) {
  DlflMesh m;
  const size_t n = mesh.vertices.size();
  for (const Vec3& p : mesh.vertices) m.vertices_.push_back(DlflMesh::Vertex{p});
  m.vertex_count_ = n;
  // Directed vertex pair → its half-edge; the first use of {u, w} makes edge e, whose 2e runs
  // in the direction of that use.
  std::unordered_map<uint64_t, HalfedgeId> directed;
  auto key = [](uint64_t u, uint64_t w) { return (u << 32) | w; };
  std::vector<HalfedgeId> loop;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    const auto face = mesh.face(f);
    const std::string where = "face " + std::to_string(f) + ": ";
    if (face.empty()) throw InputError(where + "no vertices");
    loop.clear();
    for (size_t i = 0; i < face.size(); ++i) {
      const uint32_t u = face[i], w = face[(i + 1) % face.size()];
      if (u >= n || w >= n) throw InputError(where + "vertex index out of range");
      if (u == w) throw InputError(where + "vertex " + std::to_string(u) + " repeated in a row");
      if (directed.contains(key(u, w)))
        throw InputError(where + "edge " + pair_text(u, w) +
                         " used twice in this direction (faces oriented inconsistently, or an "
                         "edge of more than two faces)");
      HalfedgeId h;
      if (auto it = directed.find(key(w, u)); it != directed.end()) {
        h = DlflMesh::twin(it->second);
      } else {
        h = 2 * static_cast<HalfedgeId>(m.halfedges_.size() / 2);
        m.halfedges_.resize(m.halfedges_.size() + 2);
        m.halfedges_[h + 1].head = u;
      }
      directed.emplace(key(u, w), h);
      m.halfedges_[h].head = w;
      m.halfedges_[h].face = static_cast<FaceId>(f);
      m.vertices_[u].halfedge = h;
      loop.push_back(h);
    }
    for (size_t i = 0; i < loop.size(); ++i) m.link(loop[i], loop[(i + 1) % loop.size()]);
    m.faces_.push_back(DlflMesh::Face{loop[0]});
  }
  m.face_count_ = mesh.face_count();
  m.edge_count_ = m.halfedges_.size() / 2;
  for (HalfedgeId h = 0; h < m.halfedges_.size(); ++h)
    if (m.halfedges_[h].face == kNone)
      throw InputError("edge " + pair_text(m.tail(h), m.head(h)) +
                       " has a face on one side only: the mesh has a boundary (the DLFL "
                       "represents closed surfaces)");
  // Manifold vertices: one rotation through all outgoing half-edges.
  std::vector<uint32_t> outgoing(n, 0);
  for (HalfedgeId h = 0; h < m.halfedges_.size(); ++h) ++outgoing[m.tail(h)];
  for (VertexId v = 0; v < n; ++v) {
    if (outgoing[v] == 0) {
      m.make_point_sphere(v, m.new_face());
      continue;
    }
    if (m.rotation(v).size() != outgoing[v])
      throw InputError("vertex " + std::to_string(v) +
                       ": its faces form more than one fan (a non-manifold vertex)");
  }
  return m;
}

PolygonMesh to_polygon_mesh(const DlflMesh& mesh) {
  PolygonMesh out;
  std::vector<uint32_t> index(mesh.vertex_capacity(), kNone);
  for (VertexId v = 0; v < mesh.vertex_capacity(); ++v) {
    if (!mesh.vertex_alive(v)) continue;
    index[v] = static_cast<uint32_t>(out.vertices.size());
    out.vertices.push_back(mesh.position(v));
  }
  std::vector<uint32_t> loop;
  for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
    if (!mesh.face_alive(f) || mesh.face_halfedge(f) == kNone) continue;
    loop.clear();
    for (VertexId v : mesh.face_vertices(f)) loop.push_back(index[v]);
    out.add_face(loop);
  }
  return out;
}

}  // namespace cover::modeler
