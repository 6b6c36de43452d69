// Catmull–Clark refinement built from the minimal DLFL operators (notation in dlfl.h), with the
// masks of subdivision/ (docs/design.md "Subdivision") evaluated in the same operand order.
//
// Notation
//   corner order   the order in which to_polygon_mesh writes face-vertex entries: faces by id,
//                  each loop from face_halfedge(f); the "first" half-edge of an edge or of a
//                  edge is the one met first in this order, as subdivision/ numbers edges;
//                  the "last" half-edge of a vertex is its last outgoing one in this order.
//   ring(v)        v's outgoing half-edges from its last one, h → twin(prev(h)) (the reverse
//                  of DlflMesh::rotation); a vertex point sums the faces of ring(v) from the
//                  last one backwards and the neighbours from the one after it backwards, as
//                  subdivision/ does (CGAL's order, detail/stencils.h).

#include <string>

#include "cover/modeler/operators.h"
#include "cover/solid/errors.h"

namespace cover::modeler {

namespace {

/// A point whose operations are subdivision/'s (division, not multiplication by a reciprocal).
struct P3 {
  double x, y, z;
};
P3 operator+(const P3& a, const P3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
P3 operator*(const P3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
P3 operator*(double s, const P3& a) { return {s * a.x, s * a.y, s * a.z}; }
P3 operator/(const P3& a, double s) { return {a.x / s, a.y / s, a.z / s}; }

/// The Catmull–Clark points of the input mesh, by vertex, edge and face id.
struct Points {
  std::vector<P3> vertex, edge, face;
};

Points catmull_clark_points(const DlflMesh& mesh) {
  const auto pos = [&](VertexId v) {
    const Vec3& p = mesh.position(v);
    return P3{p.x, p.y, p.z};
  };
  Points out;
  out.face.resize(mesh.face_capacity());
  out.edge.resize(mesh.edge_capacity());
  out.vertex.resize(mesh.vertex_capacity());
  std::vector<HalfedgeId> last_out(mesh.vertex_capacity(), kNone);
  std::vector<HalfedgeId> edge_first(mesh.edge_capacity(), kNone);
  for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
    if (!mesh.face_alive(f)) continue;
    const std::vector<HalfedgeId> loop = mesh.face_loop(f);
    P3 s{0.0, 0.0, 0.0};
    for (HalfedgeId h : loop) {
      s = s + pos(mesh.tail(h));
      last_out[mesh.tail(h)] = h;
      if (edge_first[DlflMesh::edge(h)] == kNone) edge_first[DlflMesh::edge(h)] = h;
    }
    out.face[f] = s / static_cast<double>(loop.size());
  }
  for (EdgeId e = 0; e < mesh.edge_capacity(); ++e) {
    if (!mesh.edge_alive(e)) continue;
    const HalfedgeId h = edge_first[e];
    out.edge[e] = (pos(mesh.head(h)) + pos(mesh.tail(h)) + out.face[mesh.face(h)] +
                   out.face[mesh.face(DlflMesh::twin(h))]) /
                  4.0;
  }
  for (VertexId v = 0; v < mesh.vertex_capacity(); ++v) {
    if (!mesh.vertex_alive(v) || mesh.is_point_sphere(v)) continue;
    const P3 s = pos(v);
    std::vector<HalfedgeId> ring;
    HalfedgeId h = last_out[v];
    do {
      ring.push_back(h);
      h = DlflMesh::twin(mesh.prev(h));
    } while (h != last_out[v]);
    const size_t n = ring.size();
    P3 r{0.0, 0.0, 0.0}, q{0.0, 0.0, 0.0};
    for (size_t j = 0; j < n; ++j) {
      r = r + (s + pos(mesh.head(ring[(n + 1 - j) % n]))) / 2.0;
      q = q + out.face[mesh.face(ring[(n - j) % n])];
    }
    const auto tn = static_cast<double>(n);
    r = r / tn;
    q = q / tn;
    out.vertex[v] = (q + 2.0 * r + s * (static_cast<double>(n) - 3.0)) / tn;
  }
  return out;
}

}  // namespace

void catmull_clark_by_operators(DlflMesh& mesh) {
  for (FaceId f = 0; f < mesh.face_capacity(); ++f)
    if (mesh.face_alive(f) && mesh.face_halfedge(f) == kNone)
      throw InputError("catmull_clark_by_operators: vertex " +
                       std::to_string(mesh.face_point_sphere(f)) + " is a point-sphere");
  for (EdgeId e = 0; e < mesh.edge_capacity(); ++e)
    if (mesh.edge_alive(e) && mesh.head(2 * e) == mesh.tail(2 * e))
      throw InputError("catmull_clark_by_operators: edge " + std::to_string(e) + " is a loop");
  const Points points = catmull_clark_points(mesh);
  const auto to_vec = [](const P3& p) { return Vec3{p.x, p.y, p.z}; };
  std::vector<FaceId> faces;
  for (FaceId f = 0; f < mesh.face_capacity(); ++f)
    if (mesh.face_alive(f)) faces.push_back(f);
  std::vector<EdgeId> edges;
  for (EdgeId e = 0; e < mesh.edge_capacity(); ++e)
    if (mesh.edge_alive(e)) edges.push_back(e);
  std::vector<VertexId> old_vertices;
  for (VertexId v = 0; v < mesh.vertex_capacity(); ++v)
    if (mesh.vertex_alive(v)) old_vertices.push_back(v);
  // Edge points: subdivide_edge keeps the face ids; mark the new vertices.
  std::vector<uint8_t> is_edge_point;
  for (EdgeId e : edges) {
    const VertexId w = subdivide_edge(mesh, 2 * e, 1)[0];
    mesh.set_position(w, to_vec(points.edge[e]));
    if (is_edge_point.size() <= w) is_edge_point.resize(w + 1, 0);
    is_edge_point[w] = 1;
  }
  const auto edge_point = [&](VertexId v) { return v < is_edge_point.size() && is_edge_point[v]; };
  // Face points: a point-sphere joined to one edge point of the face, then to every other one
  // (each join splits off one quad; the corner after the first spoke stays in the rest).
  for (FaceId f : faces) {
    std::vector<HalfedgeId> spokes_to;
    for (HalfedgeId h : mesh.face_loop(f))
      if (edge_point(mesh.head(h))) spokes_to.push_back(h);
    const VertexId c = mesh.create_vertex(to_vec(points.face[f]));
    const Corner at_center =
        Corner::at(mesh.insert_edge(Corner::at(spokes_to[0]), Corner::point_sphere_of(c)));
    for (size_t i = 1; i < spokes_to.size(); ++i)
      mesh.insert_edge(Corner::at(spokes_to[i]), at_center);
  }
  for (VertexId v : old_vertices) mesh.set_position(v, to_vec(points.vertex[v]));
}

}  // namespace cover::modeler
