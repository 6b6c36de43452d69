#pragma once
// Exact convex decomposition by plane cuts through reflex edges ([Erleben2006 §7
// Fig. 20]; docs/design.md#convex-decomposition). Each cut is the exact plane clip and patch of
// clip.h applied to the piece that holds the edge; a piece without reflex edges is convex.
//
// Conventions
//   reflex edge   an edge u→v of triangle f = (u, v, w) whose other triangle g = (v, u, x) has x
//                 strictly on the outer side of f's plane: orient3d(u, v, w, x) > 0 on the input
//                 doubles. x on the plane (coplanar neighbours) is flat, not reflex.
//   cut plane     a plane through the edge's two input vertices and a third double point (the
//                 exact plane of clip.h's three-point overload, so it contains the edge exactly):
//                 the half-angle plane of the edge's dihedral, or the plane of f or of g. Any
//                 plane through a reflex edge splits its interior angle into two angles ≤ 180°,
//                 so the edge is gone from both halves.
//   provenance    every piece face knows the input triangle it is part of (ClipHalf::face_source;
//                 caps have none). Cuts never create reflex edges (a half-space is convex), so a
//                 piece's reflex edges are exactly its edges between two input triangles that
//                 share an input reflex edge: found combinatorially, without rounded geometry.
//   order         per piece, the `candidates` most reflex edges (largest dihedral angle) are
//                 scored with each of their planes: (input reflex edges the plane crosses, which
//                 the cut splits in two) − (those lying in the plane, which it removes as well);
//                 the lowest score is cut first. docs/design.md gives the measured effect.
//   nearly flat   an exactly reflex edge bent by a rounding-sized angle (the diagonal of a quad
//                 that is planar only up to rounding) cannot be cut reliably: its half-angle
//                 plane is itself decided by rounding. Edges bent by at most
//                 DecomposeOptions::flat_angle are left uncut; the hull then fills their dent
//                 (≈ edge length × face width² × angle / 2).
//   shells       the input is first split into its shells (detail/shells.h): solids apart or
//                touching only along edges or at vertices are cut (and hulled) separately, so
//                no piece spans two of them. A shell of negative volume (a cavity) is cut
//                together with the shells whose bounding boxes meet it; a cut that misses a
//                cavity leaves it with the components of its half whose boxes meet it.
//   fallback     a plane whose clip fails or leaves its edge in a half (rounded points of
//                earlier cuts next to the edge) is discarded and the next candidate tried; a
//                piece that no candidate cuts is finished as it is. Cut pieces form a tree. A
//                finished piece whose hull changes its volume by more than 1e-11 of the input's
//                is redone by CGAL's exact convex_decomposition_3 (Nef polyhedra; a mesh's Nef
//                is built per connected component, combined by symmetric difference, so cavities
//                stay empty): a piece finished without reflex edges first by its exact region
//                (the shell's Nef polyhedron ∩ the piece's widened bounding box ∩ the closed
//                half-space of every cut on its path; the parts the rounded piece winds around),
//                which is convex; then (first for a piece no plane could cut) of the piece
//                itself (its written doubles) when no two of its points coincide, no triangle has
//                zero area and it does not intersect itself; else, for a sliver (volume at most
//                1e-11 of the input's), the piece is dropped; else of its exact region; else of the
//                nearest node up the cut tree (nodes of at most 400 faces, each by its rounded
//                mesh or its exact region, then the shell, node 0) whose parts change it by no
//                more than that (every piece cut from the node is then replaced), at most 20,000
//                triangles; the parts' points are rounded to doubles and hulled. Exact but slow
//                on the shell.
//   rounding     clip.h rounds constructed points to the nearest double, so a finished piece is
//                convex in exact arithmetic but its written points may be very slightly
//                non-convex. Each finished piece is therefore replaced by the exact convex hull
//                of its (double) points (CGAL, exact predicates): convex by construction, equal
//                to the cut piece up to that rounding. Every hull is checked exactly convex
//                (is_convex_exact), and the hulls may change the cut pieces by at most 1e-10 of
//                the input volume in all, and their volumes must sum to the input's as closely
//                (else NotComputable): pieces overlap or leave gaps by no more than that.

#include <cstdint>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover::brep {

struct DecomposeOptions {
  bool face_planes = true;  ///< also score the planes of the edge's two faces (not only the
                            ///< half-angle plane); true: fewer pieces on mechanical parts
  int candidates = 16;      ///< reflex edges scored per cut (the most reflex first); ≥ 1
  /// Reflex edges bent by at most this angle (radians, between the faces' normals) are left
  /// uncut (decompose.h "nearly flat"); 0: cut every reflex edge.
  double flat_angle = 1e-8;
  int64_t max_pieces = 1000000;  ///< NotComputable beyond this many pieces
};

struct DecomposeResult {
  /// The convex pieces: closed, outward triangle meshes (exact convex hulls, see above).
  std::vector<PolygonMesh> pieces;
  int64_t reflex_edges = 0;       ///< reflex edges of the input (after triangulating its faces)
  int64_t nearly_flat_edges = 0;  ///< of those, left uncut by DecomposeOptions::flat_angle
  int64_t cuts = 0;               ///< plane clips made (failed_cuts included)
  int64_t failed_cuts = 0;        ///< clips discarded because they left their edge in a half
  /// Pieces finished with reflex edges that every plane failed to cut (rounding slivers).
  int64_t uncut_pieces = 0;
  /// Cut pieces (or shells) decomposed again by the exact Nef fallback (decompose.h "fallback").
  int64_t fallback_nodes = 0;
  double input_volume = 0;  ///< signed volume of the input
  double volume = 0;        ///< Σ piece volumes
  /// max over shells of Σ |hull volume − cut piece volume| / input volume: what the hulls changed
  double hull_change = 0;
  double cut_seconds = 0;   ///< reflex edges, ordering and clips
  double hull_seconds = 0;  ///< convex hulls of the finished pieces
};

/// Decomposes a closed, outward, consistently oriented 2-manifold polygon mesh without
/// self-intersections into convex pieces whose volumes sum to the input's (up to the rounding
/// of constructed points). Deterministic (pieces in depth-first cut order).
/// \throws InputError for an open mesh (an edge held by different numbers of faces in its two
///   directions), a face that crosses itself, or an inside-out mesh or shell (negative volume);
///   NotComputable when the hulls would change the pieces by more than 1e-10 of the input
///   volume in all (decompose.h "rounding": pieces that neither a plane nor the fallback could
///   make convex), or beyond options.max_pieces.
DecomposeResult decompose(const PolygonMesh& mesh, const DecomposeOptions& options = {});

/// Is every vertex of `piece` on the inner side of, or on, the plane of every triangle of it
/// (exact orient3d on the stored doubles)? Faces with more than three vertices are tested by
/// their fan triangles. The check behind decompose()'s contract, exposed for tests.
bool is_convex_exact(const PolygonMesh& piece);

}  // namespace cover::brep
