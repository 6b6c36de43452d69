#pragma once
// Uniform subdivision of polygon meshes: Catmull–Clark, Loop, Doo–Sabin and √3 (Kobbelt), with
// the masks and border rules of CGAL 5.5's Subdivision_method_3 (docs/design.md "Subdivision").
// Every level builds the refined vertex and face arrays directly from a half-edge view of the
// previous level; each phase is a parallel loop writing fixed slots, so the output does not
// depend on the thread count.

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "cover/solid/polygon_mesh.h"

namespace cover {

/// A subdivision scheme (docs/design.md "Subdivision" gives the masks).
enum class Scheme {
  kCatmullClark,  ///< primal quad scheme, any polygons in, quads out
  kLoop,          ///< primal triangle scheme (1-to-4), triangles in and out
  kDooSabin,      ///< dual corner-cutting scheme, any polygons in
  kSqrt3,         ///< Kobbelt's √3 scheme (1-to-3 and edge flips), triangles in and out
};

/// The scheme's name in the CLI (`--scheme`), scenes ("scheme") and Python (`scheme=`):
/// "catmull-clark", "loop", "doo-sabin" or "sqrt3".
std::string_view to_string(Scheme scheme);

/// The scheme that to_string() names `name` (exact spelling), or nullopt.
std::optional<Scheme> scheme_from_string(std::string_view name);

/// How subdivide() refines a mesh.
struct SubdivideOptions {
  Scheme scheme = Scheme::kCatmullClark;  ///< default: Catmull–Clark
  int levels = 1;                         ///< default 1; 0 returns the input unchanged
  /// Default false: stencils are evaluated in doubles in a fixed order (the order CGAL's masks
  /// use). true: every new point is the correctly rounded value of its stencil evaluated exactly
  /// (rationals) over the previous level's double positions; weights that involve cos(2π/n) are
  /// the doubles of the documented formulas.
  bool exact_rounding = false;
};

/// The largest refined mesh subdivide() builds: at most 2^30 vertices and 2^30 face-vertex
/// entries per level (bounds computed from the input's counts before anything is allocated).
inline constexpr uint64_t kMaxSubdivisionEntries = uint64_t{1} << 30;

/// `levels` rounds of `scheme` on `mesh` (CCW faces, outward normals preserved).
/// Output order per level (V, E, F, H: vertices, edges, faces, corners of the previous level;
/// edges numbered in order of first appearance when walking faces corner by corner):
///   Catmull–Clark  vertices [V vertex points | E edge points | F face points]; faces: for each
///                  face f, for each corner k, the quad (vertex k, edge k, face point, edge k−1).
///   Loop           vertices [V vertex points | E edge points]; faces: for each triangle
///                  (a, b, c) with edges e0 = ab, e1 = bc, e2 = ca: (a, e0, e2), (b, e1, e0),
///                  (c, e2, e1), (e0, e1, e2).
///   Doo–Sabin      vertices [H corner points] (corner h of face f: face_start[f] + k);
///                  faces: [F face-faces | one quad per interior edge | one polygon per interior
///                  vertex] (faces at border edges and border vertices are dropped, as CGAL).
///   √3             vertices [V vertex points | per face: its center, or on levels that refine
///                  the border (the 2nd, 4th, ...) for a face with a border edge its two border
///                  points]; faces: per edge, the two triangles of the flipped edge, or the
///                  one triangle of a border edge.
/// Unreferenced vertices are copied unchanged (dropped by Doo–Sabin); a mesh without faces is
/// returned as it is.
/// \throws InputError a face with fewer than 3 vertices or repeating a vertex, an index out of
///   range, a non-manifold or inconsistently oriented edge, a non-manifold vertex, a non-triangle
///   face for Loop or √3, levels < 0, or an output beyond kMaxSubdivisionEntries.
PolygonMesh subdivide(const PolygonMesh& mesh, const SubdivideOptions& options);

/// Face-varying attributes (texture coordinates, colours): `dims` values per corner, in the
/// order of face_vertices, so seams (a vertex with different values in different faces) are
/// kept. subdivide() interpolates them within each old face and never smooths them: applying
/// Catmull–Clark to texture coordinates makes textures swim (Akleman, Chen, Srinivasan §5).
struct CornerAttributes {
  int dims = 0;                ///< values per corner (2 for UVs)
  std::vector<double> values;  ///< dims · face_vertices.size()
};

/// subdivide(mesh, options) that also replaces `attributes` (given for mesh's corners) by the
/// values at the result's corners. Per level:
///   Catmull–Clark, Loop  a corner at an old vertex keeps its old corner's value; at an edge
///                        point, the mean of the edge's two corners in the same old face; at a
///                        face point, the mean of the face's corners.
///   Doo–Sabin            a corner point's value is the Doo–Sabin mask over its face's corners
///                        (weights in (0, 1) summing to 1; on quads bilinear at (1/4, 1/4)).
///   √3                   a centre's value is its face's mean; a border point's (2a + b)/3 or
///                        (a + 2b)/3 of its edge's corners; an old vertex's corner in a triangle
///                        of a flipped edge takes its corner's value in the face of the edge's
///                        smaller corner.
/// \throws InputError as subdivide(), and when dims < 1 or the value count is not
///   dims · face_vertices.size() or a value is not finite.
PolygonMesh subdivide(const PolygonMesh& mesh, const SubdivideOptions& options,
                      CornerAttributes& attributes);

}  // namespace cover
