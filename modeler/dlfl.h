#pragma once
// DlflMesh: the doubly linked face list of [Akleman2002] for interactive modeling of closed
// orientable 2-manifolds, with the paper's minimal operator set (§3): CREATEVERTEX,
// DELETEVERTEX, INSERTEDGE, DELETEEDGE. Every other modeling operator (modeler/operators.h) is
// built from these four, so a mesh is valid by construction.
//
// Notation
//   half-edge h    directed edge tail(h) → head(h); twin(h) = h ^ 1; edge e is the pair
//                  {2e, 2e+1}. next(h) / prev(h) walk the loop of face(h), counter-clockwise
//                  seen from outside. Every half-edge has a face (the surface is closed).
//   corner         Corner::at(h): the corner at head(h) between h and next(h) in face(h) (the
//                  paper's "two consecutive edges plus the vertex between them").
//   point-sphere   a vertex without edges and its one edgeless face (MVFS); its only corner is
//                  Corner::point_sphere_of(v).
//   rotation(v)    the outgoing half-edges of v in the cyclic order h → next(twin(h)), clockwise
//                  seen from outside. The rotations determine the faces: next(h) =
//                  rotation successor of twin(h).
//   component      a connected part (vertices joined by edges); each has
//                  V − E + F = 2 − 2·genus.
//   deleted        removed vertices, edges and faces are tombstones whose ids are reused by
//                  later creations (last freed, first reused); ids of live elements never change.
//
// Every operator costs O(degree of the faces and vertices it touches).

#include <cstdint>
#include <vector>

#include "cover/solid/polygon_mesh.h"
#include "cover/solid/types.h"

namespace cover::modeler {

using VertexId = uint32_t;    ///< index of a vertex
using HalfedgeId = uint32_t;  ///< index of a half-edge (edge e: 2e and 2e+1)
using EdgeId = uint32_t;      ///< index of an edge
using FaceId = uint32_t;      ///< index of a face

inline constexpr uint32_t kNone = 0xffffffffu;  ///< no element

/// A corner: the corner at the head of a half-edge, or the one corner of a point-sphere.
struct Corner {
  HalfedgeId halfedge = kNone;  ///< the corner at head(halfedge), or kNone for a point-sphere
  VertexId vertex = kNone;      ///< the point-sphere's vertex when halfedge is kNone

  /// The corner at head(h), between h and next(h).
  static Corner at(HalfedgeId h) { return {h, kNone}; }
  /// The one corner of the point-sphere of vertex v.
  static Corner point_sphere_of(VertexId v) { return {kNone, v}; }
  /// True for a point-sphere's corner.
  bool is_point_sphere() const { return halfedge == kNone; }
  friend bool operator==(const Corner&, const Corner&) = default;
};

/// The mesh. Ids index arrays that also hold tombstones: iterate 0 .. *_capacity() and skip the
/// dead ones (vertex_alive and so on).
class DlflMesh {
 public:
  // ---- the minimal operators [Akleman2002 §3] ----

  /// CREATEVERTEX (MVFS): a new point-sphere at p (V+1, F+1, one more component).
  VertexId create_vertex(const Vec3& p);
  /// DELETEVERTEX (KVFS): removes the point-sphere of v (V−1, F−1, one component fewer).
  /// \throws PreconditionError when v is not a live point-sphere.
  void delete_vertex(VertexId v);
  /// INSERTEDGE(c1, c2): a new edge from vertex(c1) to vertex(c2); returns its half-edge from
  /// vertex(c1) to vertex(c2). E+1, and: both corners in one face (the same corner included: a
  /// loop that cuts off a one-sided face) → the face splits (F+1), the loop that holds the
  /// returned half-edge keeps the face's id; corners of two faces of one component → the faces
  /// merge into one (F−1, genus+1: a handle); corners of two components → they join (F−1,
  /// components−1). The merged face keeps the id of face(c1). Point-sphere corners are faces of
  /// their own components (a join). Corners of one vertex give a loop edge.
  /// \throws PreconditionError when a corner is not live.
  HalfedgeId insert_edge(Corner c1, Corner c2);
  /// DELETEEDGE(e), the inverse of insert_edge: two different faces beside e merge (F−1); the
  /// same face on both sides splits in two (F+1), which lowers a genus by one or splits a
  /// component in two; an end left without edges becomes a point-sphere (F+1). Ids follow
  /// insert_edge backwards: face(2e)'s id stays on the side of tail(2e) (the loop through
  /// prev(2e), or tail(2e)'s point-sphere when it is left alone), and the other side takes a
  /// new id (the last freed), so insert_edge then delete_edge restores every id and link.
  /// \throws PreconditionError when e is not live.
  void delete_edge(EdgeId e);

  // ---- counts and liveness ----

  /// Number of live vertices (point-spheres included).
  size_t vertex_count() const { return vertex_count_; }
  /// Number of live edges.
  size_t edge_count() const { return edge_count_; }
  /// Number of live faces (point-spheres' faces included).
  size_t face_count() const { return face_count_; }
  /// One past the largest vertex id ever used.
  size_t vertex_capacity() const { return vertices_.size(); }
  /// One past the largest edge id ever used.
  size_t edge_capacity() const { return halfedges_.size() / 2; }
  /// One past the largest face id ever used.
  size_t face_capacity() const { return faces_.size(); }
  /// True when v is a live vertex id.
  bool vertex_alive(VertexId v) const { return v < vertices_.size() && vertices_[v].alive; }
  /// True when e is a live edge id.
  bool edge_alive(EdgeId e) const { return e < edge_capacity() && halfedges_[2 * e].alive; }
  /// True when h is a half-edge of a live edge.
  bool halfedge_alive(HalfedgeId h) const { return h < halfedges_.size() && halfedges_[h].alive; }
  /// True when f is a live face id.
  bool face_alive(FaceId f) const { return f < faces_.size() && faces_[f].alive; }
  /// True when c names a live corner.
  bool corner_alive(Corner c) const;

  // ---- navigation (\pre: the ids are live) ----

  /// The opposite half-edge of the same edge.
  static HalfedgeId twin(HalfedgeId h) { return h ^ 1u; }
  /// The edge of h.
  static EdgeId edge(HalfedgeId h) { return h / 2; }
  /// The next half-edge in face(h).
  HalfedgeId next(HalfedgeId h) const { return halfedges_[h].next; }
  /// The previous half-edge in face(h).
  HalfedgeId prev(HalfedgeId h) const { return halfedges_[h].prev; }
  /// The vertex h points to.
  VertexId head(HalfedgeId h) const { return halfedges_[h].head; }
  /// The vertex h leaves.
  VertexId tail(HalfedgeId h) const { return halfedges_[h ^ 1u].head; }
  /// The face on h's left (the loop h belongs to).
  FaceId face(HalfedgeId h) const { return halfedges_[h].face; }
  /// An outgoing half-edge of v, or kNone for a point-sphere.
  HalfedgeId vertex_halfedge(VertexId v) const { return vertices_[v].halfedge; }
  /// True when v has no edges (a point-sphere).
  bool is_point_sphere(VertexId v) const { return vertices_[v].halfedge == kNone; }
  /// The edgeless face of point-sphere v (kNone when v has edges).
  FaceId point_sphere_face(VertexId v) const { return vertices_[v].face; }
  /// A half-edge of f's loop, or kNone for a point-sphere's face.
  FaceId face_halfedge(FaceId f) const { return faces_[f].halfedge; }
  /// The vertex of a point-sphere's face, kNone for a face with edges.
  VertexId face_point_sphere(FaceId f) const { return faces_[f].vertex; }
  /// The position of v.
  const Vec3& position(VertexId v) const { return vertices_[v].position; }
  /// Moves v to p (geometry only; the topology is unchanged).
  void set_position(VertexId v, const Vec3& p) { vertices_[v].position = p; }

  // ---- corners, loops and rotations (\pre: the ids are live) ----

  /// The vertex of corner c.
  VertexId corner_vertex(Corner c) const {
    return c.is_point_sphere() ? c.vertex : head(c.halfedge);
  }
  /// The face corner c lies in.
  FaceId corner_face(Corner c) const {
    return c.is_point_sphere() ? vertices_[c.vertex].face : face(c.halfedge);
  }
  /// The half-edges of f's loop in order from face_halfedge(f) (empty for a point-sphere).
  std::vector<HalfedgeId> face_loop(FaceId f) const;
  /// The corners of f in loop order (the point-sphere's corner for an edgeless face).
  std::vector<Corner> face_corners(FaceId f) const;
  /// The vertices of f in loop order: tail of each half-edge of face_loop(f) (the point-sphere's
  /// vertex for an edgeless face). A vertex may occur more than once.
  std::vector<VertexId> face_vertices(FaceId f) const;
  /// Number of half-edges of f (0 for a point-sphere's face).
  size_t face_degree(FaceId f) const;
  /// The outgoing half-edges of v in rotation order from vertex_halfedge(v) (empty for a
  /// point-sphere). A loop edge appears twice (both half-edges leave v).
  std::vector<HalfedgeId> rotation(VertexId v) const;
  /// The corners at v: Corner::at(twin(h)) for h in rotation(v), or the point-sphere's corner.
  std::vector<Corner> vertex_corners(VertexId v) const;

 private:
  struct Vertex {
    Vec3 position;
    HalfedgeId halfedge = kNone;  ///< outgoing, or kNone for a point-sphere
    FaceId face = kNone;          ///< the point-sphere's face, else kNone
    bool alive = true;
  };
  struct Halfedge {
    HalfedgeId next = kNone;
    HalfedgeId prev = kNone;
    VertexId head = kNone;
    FaceId face = kNone;
    bool alive = true;
  };
  struct Face {
    HalfedgeId halfedge = kNone;  ///< a half-edge of the loop, or kNone for a point-sphere
    VertexId vertex = kNone;      ///< the point-sphere's vertex, else kNone
    bool alive = true;
  };

  VertexId new_vertex(const Vec3& p);
  EdgeId new_edge();
  FaceId new_face();
  void free_face(FaceId f);
  void link(HalfedgeId a, HalfedgeId b);
  void set_loop_face(HalfedgeId start, FaceId f);
  void make_point_sphere(VertexId v, FaceId f);
  void repoint_vertex(VertexId v, HalfedgeId a, HalfedgeId b, HalfedgeId na, HalfedgeId nb,
                      HalfedgeId pa, HalfedgeId pb);
  bool loop_is_consistent(HalfedgeId start) const;

  std::vector<Vertex> vertices_;
  std::vector<Halfedge> halfedges_;
  std::vector<Face> faces_;
  std::vector<VertexId> free_vertices_;
  std::vector<EdgeId> free_edges_;
  std::vector<FaceId> free_faces_;
  size_t vertex_count_ = 0;
  size_t edge_count_ = 0;
  size_t face_count_ = 0;

  friend DlflMesh from_polygon_mesh(const PolygonMesh& mesh);
};

/// Facts of one connected component.
struct ComponentInfo {
  size_t vertices = 0;  ///< V
  size_t edges = 0;     ///< E
  size_t faces = 0;     ///< F
  int genus = 0;        ///< g from V − E + F = 2 − 2g
};

/// The connected components (vertices joined by edges), ordered by their smallest vertex id.
std::vector<ComponentInfo> components(const DlflMesh& mesh);

/// The component index (into components(mesh)) of every vertex id; kNone for dead ids.
std::vector<uint32_t> vertex_components(const DlflMesh& mesh);

/// Checks every invariant: live links point to live elements; prev(next(h)) = h; tail(next(h))
/// = head(h); each face's loop holds exactly the half-edges labelled with it; each vertex's
/// rotation holds exactly its outgoing half-edges (a manifold vertex); the faces traced from
/// the rotations (next(h) = rotation successor of twin(h)) equal the stored loops; point-spheres
/// own one edgeless face; the counts match; V − E + F is even and ≤ 2 in every component.
/// \throws InternalError naming the first broken invariant.
void check_valid(const DlflMesh& mesh);

/// The DLFL of a closed polygon mesh: vertex i and face f keep their ids, face f's loop starts at
/// the half-edge face_vertices(f)[0] → [1]; edges are numbered in order of first use. Vertices
/// that no face uses become point-spheres. A face may repeat a vertex or use both directions of
/// a vertex pair (false edges): a DLFL face may touch itself.
/// \throws InputError when a face has no vertices or an index out of range, a face repeats a
/// vertex consecutively, a directed vertex pair is used twice (inconsistent orientation or an
/// edge of more than two faces), a pair is used in one direction only (a boundary: the DLFL
/// represents closed surfaces; close or cap the mesh first), or a vertex's faces form more than
/// one fan (a non-manifold vertex).
DlflMesh from_polygon_mesh(const PolygonMesh& mesh);

/// The faces with edges as a polygon mesh: the live vertices renumbered in id order (a
/// point-sphere's vertex is kept, and its edgeless face is not written); the faces in id order,
/// each as face_vertices(f). A face of fewer than 3 vertices (left by loops or parallel edges)
/// is written as it is.
PolygonMesh to_polygon_mesh(const DlflMesh& mesh);

}  // namespace cover::modeler
