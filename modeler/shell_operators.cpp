// Operators that shape solids: face inset, edge chamfer, bevel, and the crust / wireframe of TopMod
// (dlflaux/DLFLCrust: createCrust, cmMakeHole, makeWireframe), each built from the minimal
// DLFL operators through extrude_face, subdivide_edge, remove_edge and create_pipe (notation
// in dlfl.h).
//
// Notation
//   copy c(h)     the half-edge of the inner copy that runs between the copies of tail(h) and
//                 head(h) in the same direction; the copy has the reversed rotation at every
//                 vertex, so its faces are the input's faces reversed (inward normals): the face
//                 of c(twin(h)) is the copy of face(h).
//   corner at(h)  inserting at Corner::at(h) puts the new outgoing half-edge right after
//                 twin(h) in rotation(head(h)) (before next(h)).

#include <algorithm>
#include <cmath>
#include <string>

#include "cover/modeler/operators.h"
#include "cover/solid/errors.h"

namespace cover::modeler {

namespace {

Vec3 lerp(const Vec3& p, const Vec3& q, double t) { return p + t * (q - p); }

/// The unit Newell normal of face f (zero for a degenerate face).
Vec3 face_normal(const DlflMesh& mesh, FaceId f) {
  const std::vector<VertexId> loop = mesh.face_vertices(f);
  Vec3 normal{0, 0, 0};
  for (size_t i = 0; i < loop.size(); ++i)
    normal = normal + cross(mesh.position(loop[i]), mesh.position(loop[(i + 1) % loop.size()]));
  const double length = std::sqrt(dot(normal, normal));
  return length > 0 ? (1 / length) * normal : normal;
}

/// The point `thickness` inside the surface at v: along minus the mean of the unit normals of
/// v's faces, at the mean of thickness / cos(angle to each normal) (TopMod's uniform crust).
Vec3 inner_point(const DlflMesh& mesh, VertexId v, const std::vector<Vec3>& normals,
                 double thickness) {
  Vec3 sum{0, 0, 0};
  const std::vector<Corner> corners = mesh.vertex_corners(v);
  for (Corner c : corners) sum = sum + normals[mesh.corner_face(c)];
  const double length = std::sqrt(dot(sum, sum));
  if (!(length > 0)) throw InputError("crust: vertex " + std::to_string(v) + " has no mean normal");
  const Vec3 direction = (1 / length) * sum;
  double distance = 0;
  for (Corner c : corners) {
    const double cosine = dot(direction, normals[mesh.corner_face(c)]);
    if (!(cosine > 0))
      throw InputError("crust: the faces at vertex " + std::to_string(v) +
                       " turn by 90 degrees or more from their mean normal");
    distance += thickness / cosine;
  }
  return mesh.position(v) - (distance / double(corners.size())) * direction;
}

/// Appends the reversed copy of every live element with edges, at the positions `at` (by
/// vertex id): create_vertex per vertex, then insert_edge per edge at the corners that give the
/// reversed rotations (the first edge of each copy vertex joins its point-sphere). Returns
/// c(h) for every half-edge id h (kNone for dead ones).
std::vector<HalfedgeId> append_reversed_copy(DlflMesh& mesh, const std::vector<Vec3>& at) {
  const size_t vertices = mesh.vertex_capacity(), edges = mesh.edge_capacity();
  std::vector<VertexId> copy_vertex(vertices, kNone);
  std::vector<std::vector<HalfedgeId>> rotations(vertices);
  for (VertexId v = 0; v < vertices; ++v) {
    if (!mesh.vertex_alive(v) || mesh.is_point_sphere(v)) continue;
    rotations[v] = mesh.rotation(v);
    copy_vertex[v] = mesh.create_vertex(at[v]);
  }
  std::vector<HalfedgeId> copy(2 * edges, kNone);
  // The corner of copy vertex v where the copy of outgoing h goes: after the nearest present
  // copy that follows h in rotation(v) (the copy's rotation runs backwards).
  const auto corner_for = [&](HalfedgeId h) {
    const VertexId v = mesh.tail(h);
    const std::vector<HalfedgeId>& r = rotations[v];
    const size_t i = static_cast<size_t>(std::find(r.begin(), r.end(), h) - r.begin());
    for (size_t k = 1; k < r.size(); ++k) {
      const HalfedgeId after = r[(i + k) % r.size()];
      if (copy[after] != kNone) return Corner::at(DlflMesh::twin(copy[after]));
    }
    return Corner::point_sphere_of(copy_vertex[v]);
  };
  for (EdgeId e = 0; e < edges; ++e) {
    if (!mesh.edge_alive(e)) continue;
    const HalfedgeId c = mesh.insert_edge(corner_for(2 * e), corner_for(2 * e + 1));
    copy[2 * e] = c;
    copy[2 * e + 1] = DlflMesh::twin(c);
  }
  return copy;
}

}  // namespace

FaceId inset_face(DlflMesh& mesh, FaceId f, double fraction) {
  if (!(fraction > 0 && fraction < 1))
    throw InputError(parameter("fraction") + ": " + std::to_string(fraction) + " is not in (0, 1)");
  extrude_face(mesh, f, 0.0);
  const std::vector<VertexId> ring = mesh.face_vertices(f);
  Vec3 centroid{0, 0, 0};
  for (VertexId v : ring) centroid = centroid + mesh.position(v);
  centroid = (1.0 / double(ring.size())) * centroid;
  for (VertexId v : ring) mesh.set_position(v, lerp(mesh.position(v), centroid, fraction));
  return f;
}

FaceId chamfer_edge(DlflMesh& mesh, EdgeId e, double t) {
  if (!mesh.edge_alive(e))
    throw PreconditionError("chamfer_edge: edge " + std::to_string(e) + " is not live");
  if (!(t > 0 && t < 0.5))
    throw InputError(parameter("t") + ": " + std::to_string(t) + " is not in (0, 1/2)");
  const HalfedgeId h = 2 * e, o = 2 * e + 1;
  const VertexId u = mesh.tail(h), v = mesh.head(h);
  if (u == v || mesh.face(h) == mesh.face(o) || mesh.face_degree(mesh.face(h)) < 3 ||
      mesh.face_degree(mesh.face(o)) < 3 || mesh.rotation(u).size() < 3 ||
      mesh.rotation(v).size() < 3)
    throw InputError("chamfer_edge: edge " + std::to_string(e) +
                     " is a loop, has one face on both sides, borders a face of two sides or" +
                     " ends at a vertex of valence under 3");
  // The cut points: on the edges beside e in both faces, at fraction t from u and from v.
  const auto cut = [&](HalfedgeId from_end) {
    const Vec3 p = mesh.position(mesh.tail(from_end)), q = mesh.position(mesh.head(from_end));
    mesh.set_position(subdivide_edge(mesh, from_end, 1)[0], lerp(p, q, t));
  };
  cut(DlflMesh::twin(mesh.prev(h)));  // on f1 at u
  cut(mesh.next(h));                  // on f1 at v
  cut(mesh.next(o));                  // on f2 at u
  cut(DlflMesh::twin(mesh.prev(o)));  // on f2 at v
  // Cut a strip u, v off each face; deleting e merges the strips into the new face.
  const HalfedgeId strip =
      mesh.insert_edge(Corner::at(mesh.next(h)), Corner::at(mesh.prev(mesh.prev(h))));
  mesh.insert_edge(Corner::at(mesh.next(o)), Corner::at(mesh.prev(mesh.prev(o))));
  mesh.delete_edge(e);
  const FaceId chamfer = mesh.face(strip);
  // An end left with two edges (valence 3 before) is dissolved: its far face is cut between
  // the two cut points and the two short edges go.
  for (VertexId end : {u, v}) {
    const std::vector<HalfedgeId> spokes = mesh.rotation(end);
    if (spokes.size() != 2) continue;
    HalfedgeId into = DlflMesh::twin(spokes[0]);
    if (mesh.face(into) == chamfer) into = DlflMesh::twin(spokes[1]);
    mesh.insert_edge(Corner::at(mesh.prev(into)), Corner::at(mesh.next(into)));
    remove_edge(mesh, DlflMesh::edge(spokes[0]));
    remove_edge(mesh, DlflMesh::edge(spokes[1]));
  }
  return mesh.face(strip);
}

void bevel(DlflMesh& mesh, double fraction) {
  if (!(fraction > 0 && fraction < 1))
    throw InputError(parameter("fraction") + ": " + std::to_string(fraction) + " is not in (0, 1)");
  std::vector<FaceId> faces;
  std::vector<EdgeId> edges;
  std::vector<VertexId> vertices;
  for (FaceId f = 0; f < mesh.face_capacity(); ++f) {
    if (!mesh.face_alive(f)) continue;
    if (mesh.face_halfedge(f) == kNone)
      throw InputError("bevel: vertex " + std::to_string(mesh.face_point_sphere(f)) +
                       " is a point-sphere");
    faces.push_back(f);
  }
  for (EdgeId e = 0; e < mesh.edge_capacity(); ++e) {
    if (!mesh.edge_alive(e)) continue;
    if (mesh.head(2 * e) == mesh.tail(2 * e))
      throw InputError("bevel: edge " + std::to_string(e) + " is a loop");
    edges.push_back(e);
  }
  for (VertexId v = 0; v < mesh.vertex_capacity(); ++v)
    if (mesh.vertex_alive(v)) vertices.push_back(v);
  for (FaceId f : faces) inset_face(mesh, f, fraction);
  // Edge u → v between the ring quads (u, v, i1v, i1u) and (v, u, i2u, i2v): deleting it
  // merges them; cutting i1u–i2u and i2v–i1v leaves the edge's quad between two triangles.
  for (EdgeId e : edges) {
    const HalfedgeId h = 2 * e, o = 2 * e + 1;
    const HalfedgeId at_i1u = mesh.prev(mesh.prev(h)), at_i2u = mesh.next(o);
    const HalfedgeId at_i2v = mesh.prev(mesh.prev(o)), at_i1v = mesh.next(h);
    mesh.delete_edge(e);
    mesh.insert_edge(Corner::at(at_i1u), Corner::at(at_i2u));
    mesh.insert_edge(Corner::at(at_i2v), Corner::at(at_i1v));
  }
  // Each old vertex is left in a fan of those triangles; removing its edges merges them.
  for (VertexId v : vertices)
    for (HalfedgeId h : mesh.rotation(v)) remove_edge(mesh, DlflMesh::edge(h));
}

void crust(DlflMesh& mesh, const std::vector<FaceId>& punched, const CrustOptions& options) {
  if (!(options.thickness > 0))
    throw InputError(parameter("thickness") + ": " + std::to_string(options.thickness) +
                     " is not positive");
  if (!(options.inset > 0 && options.inset < 1))
    throw InputError(parameter("inset") + ": " + std::to_string(options.inset) +
                     " is not in (0, 1)");
  std::vector<uint8_t> chosen(mesh.face_capacity(), 0);
  for (FaceId f : punched) {
    if (!mesh.face_alive(f))
      throw PreconditionError("crust: face " + std::to_string(f) + " is not live");
    if (mesh.face_halfedge(f) == kNone)
      throw InputError("crust: face " + std::to_string(f) + " is a point-sphere's face");
    if (chosen[f]) throw InputError("crust: face " + std::to_string(f) + " is punched twice");
    chosen[f] = 1;
  }
  for (EdgeId e = 0; e < mesh.edge_capacity(); ++e)
    if (mesh.edge_alive(e) && mesh.head(2 * e) == mesh.tail(2 * e))
      throw InputError("crust: edge " + std::to_string(e) + " is a loop");
  std::vector<Vec3> normals(mesh.face_capacity(), Vec3{0, 0, 0});
  for (FaceId f = 0; f < mesh.face_capacity(); ++f)
    if (mesh.face_alive(f) && mesh.face_halfedge(f) != kNone) normals[f] = face_normal(mesh, f);
  std::vector<Vec3> inner(mesh.vertex_capacity());
  for (VertexId v = 0; v < mesh.vertex_capacity(); ++v)
    if (mesh.vertex_alive(v) && !mesh.is_point_sphere(v))
      inner[v] = inner_point(mesh, v, normals, options.thickness);
  std::vector<FaceId> inner_faces(punched.size(), kNone);
  {
    std::vector<HalfedgeId> first;
    for (FaceId f : punched) first.push_back(DlflMesh::twin(mesh.face_halfedge(f)));
    const std::vector<HalfedgeId> copy = append_reversed_copy(mesh, inner);
    for (size_t i = 0; i < punched.size(); ++i) inner_faces[i] = mesh.face(copy[first[i]]);
  }
  for (size_t i = 0; i < punched.size(); ++i) {
    inset_face(mesh, punched[i], options.inset);
    inset_face(mesh, inner_faces[i], options.inset);
    create_pipe(mesh, punched[i], inner_faces[i]);
  }
}

void wireframe(DlflMesh& mesh, const CrustOptions& options) {
  std::vector<FaceId> faces;
  for (FaceId f = 0; f < mesh.face_capacity(); ++f)
    if (mesh.face_alive(f) && mesh.face_halfedge(f) != kNone) faces.push_back(f);
  crust(mesh, faces, options);
}

}  // namespace cover::modeler
