#pragma once
// HalfedgeMesh: the B-rep kernel (docs/design.md#exactness). An orientable surface stored as
// half-edges (the DLFL of [Akleman2002], with a `face` link per half-edge).
//
// Notation
//   half-edge h     directed edge origin(h) → head(h); its twin is h ^ 1 (edges are the pairs
//                   {2e, 2e+1}), next(h)/prev(h) walk the loop of face(h) counter-clockwise seen
//                   from outside.
//   border h        face(h) == kNone: the edge side has no face yet (an open boundary, or an edge
//                   inserted but not yet used). A border half-edge has next/prev == kNone.
//   deleted         removed vertices, edges and faces are tombstones (kNone links); ids of the
//                   live elements never change.
//
// Mutators are the minimal operators (add_vertex / delete_vertex, insert_edge / delete_edge) and
// Euler operators built on them (make_face, split_edge, split_face, detach_edge,
// split_nonmanifold_vertices). make_face only attaches a face to a closed chain of border
// half-edges and split_face only cuts a face along a new edge, so a mesh built with them is always
// an oriented surface; closedness and fan structure at vertices are what validate() checks.

#include <cstdint>
#include <span>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover::brep {

inline constexpr uint32_t kNone = 0xffffffffu;

class HalfedgeMesh {
 public:
  /// Builds the mesh of a polygon mesh: one vertex per input vertex (same ids, unreferenced ones
  /// stay isolated), one face per input face (same ids), one edge per undirected vertex pair used
  /// by faces with opposite directions. Throws InputError when a directed edge is used twice
  /// (not an oriented manifold) or a face has fewer than 3 vertices.
  static HalfedgeMesh from_polygon_mesh(const PolygonMesh& mesh);

  /// The faces as a polygon mesh over the live vertices (renumbered in id order). Faces whose
  /// loop repeats a vertex (false edges) are written as one index list.
  PolygonMesh to_polygon_mesh() const;

  // --- sizes and accessors -------------------------------------------------------------------
  /// Vertex / half-edge / face slots, deleted ones included.
  uint32_t vertex_slots() const { return static_cast<uint32_t>(position_.size()); }
  uint32_t halfedge_slots() const { return static_cast<uint32_t>(origin_.size()); }
  uint32_t face_slots() const { return static_cast<uint32_t>(face_halfedge_.size()); }

  bool vertex_deleted(uint32_t v) const { return vertex_deleted_[v] != 0; }
  bool edge_deleted(uint32_t h) const { return origin_[h] == kNone; }
  bool face_deleted(uint32_t f) const { return face_halfedge_[f] == kNone; }

  const Vec3& position(uint32_t v) const { return position_[v]; }
  void set_position(uint32_t v, const Vec3& p) { position_[v] = p; }
  /// One outgoing half-edge of v, kNone when v is isolated.
  uint32_t vertex_halfedge(uint32_t v) const { return vertex_halfedge_[v]; }
  uint32_t origin(uint32_t h) const { return origin_[h]; }
  uint32_t head(uint32_t h) const { return origin_[h ^ 1]; }
  static uint32_t twin(uint32_t h) { return h ^ 1; }
  uint32_t next(uint32_t h) const { return next_[h]; }
  uint32_t prev(uint32_t h) const { return prev_[h]; }
  uint32_t face(uint32_t h) const { return face_[h]; }
  bool is_border(uint32_t h) const { return face_[h] == kNone; }
  /// One half-edge of face f's loop.
  uint32_t face_halfedge(uint32_t f) const { return face_halfedge_[f]; }
  /// Number of half-edges in face f's loop.
  uint32_t face_degree(uint32_t f) const;

  // --- minimal operators ---------------------------------------------------------------------
  /// Creates an isolated vertex at p; returns its id.
  uint32_t add_vertex(const Vec3& p);
  /// Deletes an isolated vertex (precondition: vertex_halfedge(v) == kNone).
  void delete_vertex(uint32_t v);
  /// Inserts an edge a–b with no face on either side; returns the half-edge a → b (its twin is
  /// b → a). Precondition: a != b.
  uint32_t insert_edge(uint32_t a, uint32_t b);
  /// Deletes the edge of h. With no face on either side the edge is removed; with two different
  /// faces they merge into face(h) (the inverse of split_face). Precondition: one of these.
  void delete_edge(uint32_t h);

  // --- Euler operators -----------------------------------------------------------------------
  /// Makes a face bounded by `loop`, a closed chain of border half-edges
  /// (head(loop[i]) == origin(loop[i+1]), cyclically); returns the face id.
  uint32_t make_face(std::span<const uint32_t> loop);
  /// Inserts a new vertex at p on the edge of h: h becomes origin(h) → new, a new half-edge
  /// new → head(h) follows it (and symmetrically on the twin side). Returns the new vertex.
  uint32_t split_edge(uint32_t h, const Vec3& p);
  /// Splits face(a) (== face(b), a != b) by a new edge origin(a) – origin(b). The chain from a up
  /// to b, closed by the new half-edge origin(b) → origin(a), becomes a new face; the chain from
  /// b up to a, closed by origin(a) → origin(b), keeps the old face. Returns that last half-edge
  /// (its twin lies in the new face).
  uint32_t split_face(uint32_t a, uint32_t b);
  /// Gives each side of h's edge its own edge: face(twin(h)) moves onto a new edge with a border
  /// twin, and twin(h) becomes a border. Precondition: both sides have faces.
  void detach_edge(uint32_t h);
  /// Duplicates every vertex whose half-edges form more than one fan (cycle of faces around it, or
  /// face chain between border half-edges), so each vertex has one. Returns the number of vertices
  /// added. Paper §6 "touching rings": keeps the capped result a 2-manifold.
  uint32_t split_nonmanifold_vertices();

  /// The border half-edge that follows border half-edge h around the fan of head(h) (kNone when
  /// the fan is a closed cycle, which cannot happen for a border h with a face on its twin).
  uint32_t border_next(uint32_t h) const;

 private:
  void link(uint32_t a, uint32_t b) {
    next_[a] = b;
    prev_[b] = a;
  }
  uint32_t new_edge(uint32_t a, uint32_t b);

  std::vector<Vec3> position_;
  std::vector<uint32_t> vertex_halfedge_;
  std::vector<uint8_t> vertex_deleted_;
  std::vector<uint32_t> origin_, next_, prev_, face_;
  std::vector<uint32_t> face_halfedge_;
};

/// Validity of a HalfedgeMesh (tests, `cover info`).
struct BrepReport {
  bool consistent = false;  ///< every link invariant holds (next/prev/twin/face/vertex pointers)
  bool closed = false;      ///< no border half-edge
  bool manifold = false;    ///< consistent and every vertex has exactly one fan
  int64_t vertices = 0, edges = 0, faces = 0;  ///< live, non-isolated vertices; live edges / faces
  int64_t euler = 0;                           ///< χ = V − E + F
  int64_t components = 0;                      ///< connected components (through edges)
  int64_t boundary_loops = 0;                  ///< cycles of border half-edges under border_next
  int64_t genus = -1;  ///< (2·components − χ − boundary_loops)/2 when manifold, else −1
};

/// Checks the link invariants and computes the topological numbers in O(#half-edges).
BrepReport validate(const HalfedgeMesh& mesh);

}  // namespace cover::brep
