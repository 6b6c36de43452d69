#pragma once
// Topological and geometric validation of one leaf mesh (what `cover info` reports per leaf).
// Edges are undirected vertex-index pairs of the faces' loops; a repeated consecutive index is not
// an edge. False edges (a pair used once in each direction inside the SAME face, [Segura2004 §3
// Fig. 1]) are not edges of the surface: they are never a side of an edge below. Conventions:
//   boundary edge      used by exactly one face side
//   non-manifold edge  used by more than two face sides
//   manifold           no non-manifold edge and no pinched vertex (a vertex whose faces form more
//                      than one fan, e.g. two cones meeting at their apex)
//   oriented           every edge with two sides is traversed once in each direction
//   outward            closed, oriented, and the signed covering volume is > 0
//   components         connected components of faces through shared edges (faces whose indices
//                      are all equal have no edge and are ignored)
//   genus              (2·components − χ)/2, only for closed, manifold, oriented meshes (else -1).
//                      χ = V − E + F reads each face as a disk bounded by its loop and glued to
//                      itself along its false edges: V counts vertices on an edge, F faces with an
//                      edge, E the surface edges plus one per false pair; so a face with L loops
//                      joined by L−1 false edges counts as a disk with L−1 holes (χ = 2 − L).
//   degenerate face    all its vertices on one line (exact), including faces with fewer than three
//                      distinct vertices

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover {

struct ValidateOptions {
  bool check_self_intersection = true;  ///< run the (exact, CGAL) self-intersection test
  /// Count components, vertex fans (manifold, genus) and degenerate faces. Off: only the edge
  /// table's figures (closed, oriented, edges, boundary_edges, nonmanifold_edges) and volume are
  /// filled (manifold false, genus −1, components and degenerate_faces 0): what a loaded leaf
  /// needs (io/scene.cpp), about half the time.
  bool full_report = true;
};

struct MeshReport {
  bool closed = false;
  bool manifold = false;
  bool oriented = false;
  bool outward = false;
  int64_t edges = 0;  ///< distinct surface edges (boundary_edges is a part of them)
  int64_t boundary_edges = 0;
  int64_t nonmanifold_edges = 0;
  int64_t components = 0;
  int64_t genus = -1;  ///< -1 when not closed/manifold/oriented
  int64_t degenerate_faces = 0;
  double volume = 0;  ///< signed covering volume, signed_volume() of measure.h
  /// Faces meet beyond their shared vertices (self_intersects()), other than where distinct
  /// vertices at equal coordinates touch: false for a mesh whose faces meet only there. Empty
  /// when not checked.
  std::optional<bool> self_intersecting;
  /// Distinct vertices at equal coordinates where faces meet and nothing else: the mesh touches
  /// itself (a pinched vertex or edge of a regularized result, as two boxes sharing an edge)
  /// without crossing; exact (self_intersects() on the mesh with those vertices identified).
  /// Empty when not checked.
  std::optional<bool> self_touching;
};

/// Validates one mesh in O(n log d) for n face indices and largest vertex degree d (plus
/// self_intersects() when asked). Precondition: all indices < vertices.size().
MeshReport validate_mesh(const PolygonMesh& mesh, const ValidateOptions& options = {});

/// Exact self-intersection test (CGAL Epick predicates on the input doubles). Each face is tiled
/// exactly by triangulate_face (mesh/triangulate.h: false edges join no region, holes stay
/// empty); a face whose boundary crosses itself or winds more than once counts as
/// self-intersecting. Tiles of the same face are never tested against each other;
/// collinear tiles are ignored. Tiles sharing vertex indices intersect only when they meet beyond
/// the shared vertices (CGAL::Polygon_mesh_processing::self_intersections' rules); distinct indices
/// at equal coordinates are a contact, hence an intersection.
bool self_intersects(const PolygonMesh& mesh);

/// Whether two triangles (vertex indices into v, of different faces, neither collinear) meet
/// beyond their shared vertices, by self_intersects()' rules (exact).
bool tiles_meet(const std::array<uint32_t, 3>& a, const std::array<uint32_t, 3>& b,
                std::span<const Vec3> v);

/// The same with each triangle's normal_axis given: callers testing many pairs compute it once
/// per triangle. The answer does not depend on the axes (they only choose the projections the
/// filters try first; every projection is sound).
bool tiles_meet(const std::array<uint32_t, 3>& a, const std::array<uint32_t, 3>& b,
                std::span<const Vec3> v, int axis_a, int axis_b);

/// The axis (0, 1, 2) of the largest component of the normal (b − a) × (c − a), in doubles: the
/// projection along it flattens the triangle least.
int normal_axis(const Vec3& a, const Vec3& b, const Vec3& c);

/// Vertices whose fan is a flat star: flag s is set when the triangles with corner s (by index,
/// all of one `group`, e.g. one leaf) form one cycle around s, each sharing the edge after s
/// with the next, and in the projection along some axis every one of them turns the same way
/// around s (strict orient2d) and the cycle winds around s exactly once. Their projections
/// then tile a neighbourhood of s without overlap, so any two of them meet only at s or along
/// a shared edge: by self_intersects()' rules, pairs that share a flagged vertex never meet.
/// (A check of a mesh's pairs spends most of its time on such neighbours; a fan costs about
/// two strict orient2d per triangle, its pairs about six each.) Sound, not complete: a fan it
/// cannot certify is left unflagged. Triangles are never collinear; `group` may be empty (one
/// group). Parallel over vertices.
std::vector<uint8_t> star_vertices(std::span<const std::array<uint32_t, 3>> tris,
                                   std::span<const uint32_t> group, std::span<const Vec3> v);

/// The pairs (f, g), f ≤ g, of faces that meet by self_intersects()' rules, sorted; (f, f) for a
/// face whose boundary crosses itself or winds more than once. With `suspect` (one flag per
/// face) only pairs with at least one suspect face are tested: a caller that knows which faces
/// may have moved (e.g. those with rounded vertices) skips the pairs of unchanged faces.
/// Sequential; meant for the few faces near rounded points, or for tests.
/// `group` (one id per face, optional): faces with the same nonzero id are known not to overlap
/// one another (e.g. the faces of one valid cap triangulation) and are not tested as a pair.
std::vector<std::pair<uint32_t, uint32_t>> intersecting_face_pairs(
    const PolygonMesh& mesh, std::span<const uint8_t> suspect = {},
    std::span<const uint32_t> group = {});

}  // namespace cover
