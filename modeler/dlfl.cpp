// DlflMesh: the minimal operators and the loop and rotation queries (notation in dlfl.h).
//
// INSERTEDGE as a splice of the next permutation. Corner c = (in, out): in = c.halfedge arrives
// at the corner's vertex, out = next(in) leaves it. The new edge a: v1 → v2, b = twin(a):
//   at c1: in1 → a, b → out1        (a point-sphere corner: b → a)
//   at c2: in2 → b, a → out2        (a point-sphere corner: a → b)
// One face: the loop splits into (a, out2 … in1) and (b, out1 … in2); two faces: one loop
// (a, out2 … in2, b, out1 … in1). The same corner twice (a loop edge) keeps a in the face and
// cuts off b alone: in → a → out, b → b. DELETEEDGE undoes the splice: prev(a) → next(b),
// prev(b) → next(a), with the cases where a or b follows the other (an end of valence 1) or
// itself (a one-sided loop face).

#include "cover/modeler/dlfl.h"

#include <array>

#include "cover/solid/errors.h"

namespace cover::modeler {

VertexId DlflMesh::new_vertex(const Vec3& p) {
  VertexId v;
  if (!free_vertices_.empty()) {
    v = free_vertices_.back();
    free_vertices_.pop_back();
    vertices_[v] = Vertex{p};
  } else {
    v = static_cast<VertexId>(vertices_.size());
    vertices_.push_back(Vertex{p});
  }
  ++vertex_count_;
  return v;
}

EdgeId DlflMesh::new_edge() {
  EdgeId e;
  if (!free_edges_.empty()) {
    e = free_edges_.back();
    free_edges_.pop_back();
    halfedges_[2 * e] = Halfedge{};
    halfedges_[2 * e + 1] = Halfedge{};
  } else {
    e = static_cast<EdgeId>(halfedges_.size() / 2);
    halfedges_.resize(halfedges_.size() + 2);
  }
  ++edge_count_;
  return e;
}

FaceId DlflMesh::new_face() {
  FaceId f;
  if (!free_faces_.empty()) {
    f = free_faces_.back();
    free_faces_.pop_back();
    faces_[f] = Face{};
  } else {
    f = static_cast<FaceId>(faces_.size());
    faces_.push_back(Face{});
  }
  ++face_count_;
  return f;
}

void DlflMesh::free_face(FaceId f) {
  faces_[f] = Face{kNone, kNone, false};
  free_faces_.push_back(f);
  --face_count_;
}

void DlflMesh::link(HalfedgeId a, HalfedgeId b) {
  halfedges_[a].next = b;
  halfedges_[b].prev = a;
}

void DlflMesh::set_loop_face(HalfedgeId start, FaceId f) {
  HalfedgeId h = start;
  do {
    halfedges_[h].face = f;
    h = halfedges_[h].next;
  } while (h != start);
  faces_[f].halfedge = start;
  faces_[f].vertex = kNone;
}

void DlflMesh::make_point_sphere(VertexId v, FaceId f) {
  vertices_[v].halfedge = kNone;
  vertices_[v].face = f;
  faces_[f].halfedge = kNone;
  faces_[f].vertex = v;
}

bool DlflMesh::corner_alive(Corner c) const {
  if (c.is_point_sphere()) return vertex_alive(c.vertex) && is_point_sphere(c.vertex);
  return halfedge_alive(c.halfedge);
}

bool DlflMesh::loop_is_consistent(HalfedgeId start) const {
  size_t steps = 0;
  HalfedgeId h = start;
  do {
    HalfedgeId n = next(h);
    if (!halfedge_alive(n) || prev(n) != h || face(n) != face(start) || tail(n) != head(h))
      return false;
    if (++steps > halfedges_.size()) return false;
    h = n;
  } while (h != start);
  return true;
}

VertexId DlflMesh::create_vertex(const Vec3& p) {
  VertexId v = new_vertex(p);
  FaceId f = new_face();
  make_point_sphere(v, f);
  return v;
}

void DlflMesh::delete_vertex(VertexId v) {
  if (!vertex_alive(v) || !is_point_sphere(v))
    throw PreconditionError("delete_vertex: vertex " + std::to_string(v) +
                            " is not a live point-sphere");
  free_face(vertices_[v].face);
  vertices_[v] = Vertex{{}, kNone, kNone, false};
  free_vertices_.push_back(v);
  --vertex_count_;
}

HalfedgeId DlflMesh::insert_edge(Corner c1, Corner c2) {
  if (!corner_alive(c1) || !corner_alive(c2))
    throw PreconditionError("insert_edge: a corner is not live");
  const VertexId v1 = corner_vertex(c1), v2 = corner_vertex(c2);
  const FaceId f1 = corner_face(c1), f2 = corner_face(c2);
  const HalfedgeId out1 = c1.is_point_sphere() ? kNone : next(c1.halfedge);
  const HalfedgeId out2 = c2.is_point_sphere() ? kNone : next(c2.halfedge);
  const EdgeId e = new_edge();
  const HalfedgeId a = 2 * e, b = a + 1;
  halfedges_[a].head = v2;
  halfedges_[b].head = v1;
  if (c1 == c2) {
    if (c1.is_point_sphere()) {
      link(a, a);
    } else {
      link(c1.halfedge, a);
      link(a, out1);
    }
    link(b, b);
  } else {
    if (c1.is_point_sphere()) {
      link(b, a);
    } else {
      link(c1.halfedge, a);
      link(b, out1);
    }
    if (c2.is_point_sphere()) {
      link(a, b);
    } else {
      link(c2.halfedge, b);
      link(a, out2);
    }
  }
  if (c2.is_point_sphere()) {
    vertices_[v2].halfedge = b;
    vertices_[v2].face = kNone;
  }
  if (c1.is_point_sphere()) {
    vertices_[v1].halfedge = a;
    vertices_[v1].face = kNone;
  }
  if (f1 == f2) {
    set_loop_face(a, f1);
    set_loop_face(b, new_face());
  } else {
    free_face(f2);
    set_loop_face(a, f1);
  }
  COVER_ASSERT(loop_is_consistent(a) && loop_is_consistent(b));
  return a;
}

void DlflMesh::repoint_vertex(VertexId v, HalfedgeId a, HalfedgeId b, HalfedgeId na, HalfedgeId nb,
                              HalfedgeId pa, HalfedgeId pb) {
  HalfedgeId& out = vertices_[v].halfedge;
  if (out != a && out != b) return;
  // The rotation neighbours of a and b at their tails: if none of them is another edge's
  // half-edge, v has no other edge.
  out = kNone;
  for (HalfedgeId h : std::array{nb, na, twin(pa), twin(pb)}) {
    if (h != a && h != b && tail(h) == v) {
      out = h;
      return;
    }
  }
}

void DlflMesh::delete_edge(EdgeId e) {
  if (!edge_alive(e))
    throw PreconditionError("delete_edge: edge " + std::to_string(e) + " is not live");
  const HalfedgeId a = 2 * e, b = a + 1;
  const VertexId v1 = head(b), v2 = head(a);
  const FaceId fa = face(a), fb = face(b);
  const HalfedgeId na = next(a), pa = prev(a), nb = next(b), pb = prev(b);
  repoint_vertex(v1, a, b, na, nb, pa, pb);
  repoint_vertex(v2, a, b, na, nb, pa, pb);
  if (na == a && nb == b) {
    free_face(fb);
    make_point_sphere(v1, fa);
  } else if (na == a) {
    link(pb, nb);
    free_face(fa);
    faces_[fb].halfedge = nb;
  } else if (nb == b) {
    link(pa, na);
    free_face(fb);
    faces_[fa].halfedge = na;
  } else if (na == b && nb == a) {
    make_point_sphere(v1, fa);
    make_point_sphere(v2, new_face());
  } else if (na == b) {
    link(pa, nb);
    faces_[fa].halfedge = nb;
    make_point_sphere(v2, new_face());
  } else if (nb == a) {
    link(pb, na);
    set_loop_face(na, new_face());
    make_point_sphere(v1, fa);
  } else {
    link(pa, nb);
    link(pb, na);
    if (fa != fb) {
      free_face(fb);
      set_loop_face(nb, fa);
    } else {
      set_loop_face(nb, fa);
      set_loop_face(na, new_face());
    }
  }
  COVER_ASSERT(vertices_[v1].halfedge != kNone || vertices_[v1].face != kNone);
  COVER_ASSERT(vertices_[v2].halfedge != kNone || vertices_[v2].face != kNone);
  halfedges_[a] = Halfedge{kNone, kNone, kNone, kNone, false};
  halfedges_[b] = Halfedge{kNone, kNone, kNone, kNone, false};
  free_edges_.push_back(e);
  --edge_count_;
  COVER_ASSERT(vertices_[v1].halfedge == kNone || loop_is_consistent(vertices_[v1].halfedge));
  COVER_ASSERT(vertices_[v2].halfedge == kNone || loop_is_consistent(vertices_[v2].halfedge));
}

std::vector<HalfedgeId> DlflMesh::face_loop(FaceId f) const {
  std::vector<HalfedgeId> loop;
  const HalfedgeId start = faces_[f].halfedge;
  if (start == kNone) return loop;
  HalfedgeId h = start;
  do {
    loop.push_back(h);
    h = next(h);
  } while (h != start);
  return loop;
}

std::vector<Corner> DlflMesh::face_corners(FaceId f) const {
  if (faces_[f].halfedge == kNone) return {Corner::point_sphere_of(faces_[f].vertex)};
  std::vector<Corner> corners;
  for (HalfedgeId h : face_loop(f)) corners.push_back(Corner::at(h));
  return corners;
}

std::vector<VertexId> DlflMesh::face_vertices(FaceId f) const {
  if (faces_[f].halfedge == kNone) return {faces_[f].vertex};
  std::vector<VertexId> vertices;
  for (HalfedgeId h : face_loop(f)) vertices.push_back(tail(h));
  return vertices;
}

size_t DlflMesh::face_degree(FaceId f) const {
  const HalfedgeId start = faces_[f].halfedge;
  if (start == kNone) return 0;
  size_t n = 0;
  HalfedgeId h = start;
  do {
    ++n;
    h = next(h);
  } while (h != start);
  return n;
}

std::vector<HalfedgeId> DlflMesh::rotation(VertexId v) const {
  std::vector<HalfedgeId> out;
  const HalfedgeId start = vertices_[v].halfedge;
  if (start == kNone) return out;
  HalfedgeId h = start;
  do {
    out.push_back(h);
    h = next(twin(h));
  } while (h != start);
  return out;
}

std::vector<Corner> DlflMesh::vertex_corners(VertexId v) const {
  if (is_point_sphere(v)) return {Corner::point_sphere_of(v)};
  std::vector<Corner> corners;
  for (HalfedgeId h : rotation(v)) corners.push_back(Corner::at(twin(h)));
  return corners;
}

}  // namespace cover::modeler
