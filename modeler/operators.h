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
  PipeOptions(int segments_ = 1, int twist_ = 0) : segments(segments_), twist(twist_) {}
  int segments = 1;  ///< edges along the pipe between the two faces; segments − 1 inner rings
  int twist = 0;     ///< corner offset added to the closest correspondence (turns the pipe)
  /// A curved pipe (TopMod's Hermite handle): the centre runs on a cubic Hermite curve from f1's
  /// centroid through `path` to f2's, leaving f1 along its normal and entering f2 against its
  /// normal, and the rings blend the two faces' shapes across the curve
  /// (modeler/detail/pipe_path.h). False with an empty path: straight rails.
  bool curved = false;
  double weight1 = 1, weight2 = 1;  ///< end tangents, in lengths of the first / last chord
  std::vector<Vec3> path;           ///< points the centre passes through (implies curved)
};

/// CREATEPIPE: a pipe from face f1 to face f2 of equal degree n (both removed). Corner i of f1
/// (loop order) is joined to corner σ(i) = s + twist − i (mod n) of f2 (f2 walked backwards:
/// the faces look at each other), s minimising Σ |p(corner i) − p(corner σ(i))|². segments = 1:
/// n insert_edge calls; the first merges f1 and f2 (one component: genus+1, a handle; two
/// components: they join), the others split off the n quads of the pipe. segments > 1:
/// subdivide_edge cuts each of those edges into `segments` pieces (inner ring vertices on the
/// straight segments between corresponding corners) and insert_edge closes each ring. Changes:
/// V + n(segments−1), E + n(2·segments−1), F + n·segments − 2.
/// Curved: σ minimises the same sum over the corners' offsets from the centroids, taken in one
/// frame (the frame carried along the curve), and the inner ring vertices lie on the curve's
/// rings instead of the straight segments.
/// \throws PreconditionError when a face is not live; InputError when f1 == f2, a face is a
/// point-sphere's, the degrees differ, segments < 1, or segments > 1 with faces under 3 sides;
/// curved: a weight not positive and finite, a face without a normal, or a cusp on the curve.
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

/// Catmull–Clark refinement (one level, closed meshes) built from the minimal operators, the
/// DLFL view of [Akleman2002 §5] vertex insertion: subdivide_edge(·, 1) on every edge (the edge
/// points), then per face a point-sphere joined by insert_edge to one edge point of the face and
/// then to each of its other edge points (the face point; each join after the first splits off
/// one quad). Positions are subdivision/'s Catmull–Clark masks (docs/design.md "Subdivision")
/// evaluated in its operand order over the corner order of to_polygon_mesh(mesh), so
/// to_polygon_mesh of the result equals subdivide(to_polygon_mesh(mesh), {kCatmullClark, 1})
/// bit for bit up to the numbering of vertices and faces. Old vertices, edges and faces become
/// V + E + F vertices, 2E + H edges and H quads (H: face-vertex entries); genus and components
/// are unchanged. Vertex ids of the input are kept (they hold the vertex points).
/// \throws InputError when the mesh has a point-sphere or a loop edge.
void catmull_clark_by_operators(DlflMesh& mesh);

/// Face inset: extrude_face(f, 0), then the n new vertices (f's loop) moved toward f's
/// centroid by `fraction` of the way; f becomes the smaller copy inside a ring of n quads.
/// V+n, E+2n, F+n; genus and components unchanged. Returns f.
/// \throws as extrude_face; InputError when fraction is not in (0, 1).
FaceId inset_face(DlflMesh& mesh, FaceId f, double fraction);

/// Edge chamfer (TopMod's "cut edges"): edge e becomes a face. The four edges beside e in its
/// two faces get cut points at fraction t from u = tail(2e) and v = head(2e) (subdivide_edge),
/// each face is cut between its two cut points (insert_edge) and e is deleted, which merges the
/// two strips into the new face. An end of valence 3 is dissolved (its far face is cut between
/// its two cut points and remove_edge takes its two short edges), as on a cube, so the new face
/// is a quad; an end of higher valence stays a corner of it. Changes: V+4, E+5, F+1, then per
/// dissolved end V−1, E−1; genus and components unchanged. Returns the new face.
/// \throws PreconditionError when e is not live; InputError when t is not in (0, 1/2), e is a
/// loop, has one face on both sides, borders a face of fewer than 3 sides, or ends at a
/// vertex of valence under 3.
FaceId chamfer_edge(DlflMesh& mesh, EdgeId e, double t);

/// Vertex-and-edge bevel (the Doo–Sabin pattern as one step): every face is inset by
/// `fraction` (inset_face), then each old edge is deleted (its two ring quads merge) and its
/// ends are cut across (two insert_edge: the edge's quad between two triangles), and each old
/// vertex is removed with its edges (remove_edge; its triangles merge into its face). Each
/// corner of face f at v ends at v + fraction·(centroid(f) − v). V, E, F become H, 2H and
/// F + E + V (H: face-vertex entries, = 2E); genus and components unchanged.
/// \throws InputError when fraction is not in (0, 1), the mesh has a point-sphere or a loop
/// edge, or a face is degenerate.
void bevel(DlflMesh& mesh, double fraction);

/// Options of crust and wireframe.
struct CrustOptions {
  double thickness = 0.1;  ///< distance of the inner surface below the outer one
  double inset = 0.2;      ///< inset_face fraction of each punched face (and its inner copy)
};

/// A rind (TopMod's createCrust + cmMakeHole): a reversed copy of the mesh (create_vertex per
/// vertex, insert_edge per edge at the corners of the reversed rotations) placed
/// options.thickness inside (each vertex moved against the mean unit normal of its faces, by
/// the mean of thickness / cos over them: a uniform thickness on flat sides), then each punched
/// face and its inner copy are inset (inset_face, so neighbouring holes keep a frame between
/// them) and joined by create_pipe: each punched face becomes a tunnel through the rind into
/// its hollow. For a connected closed mesh (V, E, F, genus g) and k ≥ 1 punched faces of total
/// degree N: V' = 2V + 2N, E' = 2E + 5N, F' = 2F + 3N − 2k, one component of genus 2g + k − 1
/// (with k = 0: the two shells, genus g each).
/// \throws PreconditionError when a punched face is not live; InputError when one is a
/// point-sphere's face or listed twice, the mesh has a loop edge, thickness ≤ 0, inset is not in
/// (0, 1), or a vertex's faces turn 90° or more from their mean normal.
void crust(DlflMesh& mesh, const std::vector<FaceId>& punched, const CrustOptions& options = {});

/// Wireframe (TopMod's makeWireframe): crust with every face punched, so every face becomes a
/// hole framed by beams along its edges. For a connected closed genus-0 mesh the result is one
/// component of genus F − 1 = E − V + 1 (the cycle rank of the edge graph), V' = 2V + 2H,
/// E' = 2E + 5H, F' = 3H (H: face-vertex entries).
/// \throws as crust.
void wireframe(DlflMesh& mesh, const CrustOptions& options = {});

/// Options of extrude_face_doo_sabin.
struct DooSabinExtrudeOptions {
  double twist = 0;  ///< in [0, 1]: corner i starts from (1 − twist)·p_i + twist·p_{i+1}
  double scale = 1;  ///< the new face scaled about its centroid (> 0)
};

/// Doo–Sabin extrusion (TopMod's extrudeFaceDS): extrude_face(f, 0), then new corner i at the
/// Doo–Sabin corner mask Σ a_k q_{i+k}, a_0 = 1/4 + 5/(4n), a_k = (3 + 2cos(2πk/n))/(4n), over
/// the corners q moved `distance` along f's unit normal (and twisted), scaled about their
/// centroid. V+n, E+2n, F+n; genus and components unchanged. Returns f (the new top face).
/// \throws as extrude_face; InputError when scale ≤ 0 or twist is not in [0, 1].
FaceId extrude_face_doo_sabin(DlflMesh& mesh, FaceId f, double distance,
                              const DooSabinExtrudeOptions& options = {});

/// Dome extrusion (TopMod's extrudeFaceDome): five Doo–Sabin extrusions of heights (0.3, 0.18,
/// 0.1, 0.05, 0.025)·length and scales (1.7, 1.6, 1.4, 1.2, 1.1)·scale, then stellate_face of
/// height 0.01·length. V+5n+1, E+11n, F+6n−1. Returns the apex.
/// \throws as extrude_face_doo_sabin.
VertexId extrude_face_dome(DlflMesh& mesh, FaceId f, double length, double scale = 1);

/// Dodecahedral extrusion (TopMod's extrudeFaceDodeca): three layers of height distance / 3,
/// each scaled by ∛scale about its centroid: a straight extrusion (corners c_i); a dual ring of
/// new vertices m_i over the edge midpoints, each joined to both ends of its edge and to the
/// next m (insert_edge), after which the old top edges are deleted; a straight extrusion of the
/// m-face, after which the m-face's old edges are deleted. The 2n sides are pentagons (a
/// pentagon grows a cap of 10 pentagons, as in TopMod). V+3n, E+5n, F+2n; genus and components
/// unchanged. Returns the new top face.
/// \throws PreconditionError when f is not live; InputError when scale ≤ 0, f has fewer than 3
/// sides, or a layer's face is degenerate.
FaceId extrude_face_dodecahedral(DlflMesh& mesh, FaceId f, double distance, double scale = 1);

}  // namespace cover::modeler
