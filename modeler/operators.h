#pragma once
// User-level modeling operators of [Akleman2002 §4] (names after TopMod), each built only from
// the minimal operators of DlflMesh (create_vertex, delete_vertex, insert_edge, delete_edge), so
// every result is a valid DLFL by construction. Notation as in modeler/dlfl.h; positions of new
// vertices are the operators' only geometry.

#include <vector>

#include "cover/modeler/dlfl.h"

namespace cover::modeler {

/// REMOVEEDGE: delete_edge(e), then delete_vertex on each end left as a point-sphere (E−1; the
/// face, genus and component changes of delete_edge; V−1, F−1 per end removed).
/// \throws PreconditionError when e is not live.
void remove_edge(DlflMesh& mesh, EdgeId e);

/// SUBDIVIDEEDGE: k new vertices evenly spaced on the edge of h (V+k, E+k; faces, their ids and
/// the topology unchanged; the edge of h is replaced by k+1 edges). Built as create_vertex and
/// insert_edge along face(twin(h)) then delete_edge of the old edge. Returns the new vertices in
/// order from tail(h) to head(h).
/// \throws PreconditionError when h is not live; InputError when k < 0.
std::vector<VertexId> subdivide_edge(DlflMesh& mesh, HalfedgeId h, int k);

/// Options of create_pipe.
struct PipeOptions {
  int segments = 1;  ///< edges along the pipe between the two faces; segments − 1 inner rings
  int twist = 0;     ///< corner offset added to the closest correspondence (turns the pipe)
};

/// CREATEPIPE: a pipe from face f1 to face f2 of equal degree n (both removed). Corner i of f1
/// (loop order) is joined to corner σ(i) = s + twist − i (mod n) of f2 (f2 walked backwards:
/// the faces look at each other), s minimising Σ |p(corner i) − p(corner σ(i))|². segments = 1:
/// n insert_edge calls; the first merges f1 and f2 (one component: genus+1, a handle; two
/// components: they join), the others split off the n quads of the pipe. segments > 1:
/// subdivide_edge cuts each of those edges into `segments` pieces (inner ring vertices on the
/// straight segments between corresponding corners) and insert_edge closes each ring. Changes:
/// V + n(segments−1), E + n(2·segments−1), F + n·segments − 2.
/// \throws PreconditionError when a face is not live; InputError when f1 == f2, a face is a
/// point-sphere's, the degrees differ, segments < 1, or segments > 1 with faces under 3 sides.
void create_pipe(DlflMesh& mesh, FaceId f1, FaceId f2, const PipeOptions& options = {});

/// Straight face extrusion: n new vertices at f's corners moved by distance along f's unit
/// (Newell) normal, each joined to its corner (insert_edge of a point-sphere: a dangling edge
/// in f), then joined to its neighbour across f (n splits). V+n, E+2n, F+n; the genus and
/// components are unchanged. Returns f, which is now the moved top face; the n side quads are
/// new faces.
/// \throws PreconditionError when f is not live; InputError when f is a point-sphere's face or
/// its normal is zero (a degenerate face).
FaceId extrude_face(DlflMesh& mesh, FaceId f, double distance);

/// Stellate extrusion (TopMod's "stellate"): a cone over f. A new vertex at f's centroid moved
/// by height along f's unit (Newell) normal, joined to every corner of f (the first join merges
/// its point-sphere into f, the others split off one triangle each). V+1, E+n, F+n−1; the genus
/// and components are unchanged. Returns the apex.
/// \throws PreconditionError when f is not live; InputError when f is a point-sphere's face or
/// its normal is zero (a degenerate face).
VertexId stellate_face(DlflMesh& mesh, FaceId f, double height);

/// Vertex truncation (a conical cut; TopMod's "truncate vertex"): each edge at v gets a new
/// vertex at fraction t from v (subdivide_edge), each face at v is cut between the two new
/// vertices beside v (insert_edge), and v is removed with its short edges (remove_edge), leaving
/// one new face whose corners are the new vertices. For v of valence d: V + d − 1, E + d, F + 1;
/// the genus and components are unchanged. Returns the new face.
/// \throws PreconditionError when v is not live; InputError when v is a point-sphere, has a loop
/// edge, or t is not in (0, 1).
FaceId truncate_vertex(DlflMesh& mesh, VertexId v, double t);

}  // namespace cover::modeler
