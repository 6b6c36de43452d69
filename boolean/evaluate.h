#pragma once
// Boundary evaluation of a CSG solid (DESIGN.md §6 "evaluation to a B-rep"): the regularized
// result of the expression as ONE closed, outward-oriented, 2-manifold triangle mesh.
//
// Route (boolean/detail/arrangement.h has the notation and the exactness scheme):
//   1. every leaf face is triangulated (fan when convex, else a constrained triangulation);
//   2. triangles of different leaves whose boxes meet are intersected exactly (configuration by
//      exact orient3d on the doubles, edge ∩ plane points built once each in CGAL Epeck);
//   3. each intersected triangle is re-triangulated with the intersection segments as
//      constraints: split directly when one segment runs between its edges / corners, else a
//      2D constrained Delaunay triangulation in its dominant projection (exact intersections);
//   4. the pieces of each leaf are grouped into patches bounded by intersection curves, and one
//      exact interior point per patch is classified by an exact ray count per leaf;
//   5. a piece is kept iff the expression differs on its two sides (regularized), oriented
//      outward; coincident pieces of several leaves are kept once (lowest leaf);
//   6. edges with more than two kept faces are paired by exact angular order, and vertices are
//      split per fan, so the output is a 2-manifold; exact points are rounded to nearest doubles.

#include <cstdint>

#include "solid/polygon_mesh.h"
#include "solid/solid.h"

namespace cover {

struct EvaluateOptions {
  bool check_leaves = true;  ///< refuse self-intersecting leaves (exact CGAL test per leaf)
  size_t grain = 64;         ///< items per parallel chunk (results never depend on it)
};

/// Wall-clock seconds per step of evaluate() (the numbers of the route above), for profiling.
struct EvaluatePhases {
  double check = 0;        ///< leaf self-intersection check (0 without check_leaves)
  double triangulate = 0;  ///< step 1
  double pairs = 0;        ///< step 2: candidate pairs (box intersection)
  double intersect = 0;    ///< step 2: exact pairwise intersections
  double split = 0;        ///< step 3: per-tri re-triangulation
  double identify = 0;     ///< step 3: global point identity, pieces and cut edges
  double select = 0;       ///< steps 4–5
  double assemble = 0;     ///< step 6 and the mesh report
};

struct EvaluateResult {
  PolygonMesh mesh;        ///< triangles, outward; empty (no faces) when the result is empty
  double volume = 0;       ///< signed volume of `mesh` (doubles, after rounding)
  double area = 0;         ///< surface area of `mesh`
  int64_t genus = 0;       ///< Σ over components of the genus (χ = 2 − 2g per closed component)
  int64_t components = 0;  ///< connected components of `mesh`
  size_t candidate_pairs = 0;     ///< triangle pairs of different leaves with meeting boxes
  size_t intersecting_pairs = 0;  ///< pairs that really meet
  size_t patches = 0;             ///< classified patches
  EvaluatePhases seconds;         ///< time per step
};

/// Evaluates `solid` (closed leaves; the nonzero winding rule per leaf) to a B-rep.
/// Throws InputError when a leaf is self-intersecting (check_leaves) — the per-leaf arrangement
/// would need self-intersection resolution, which is not implemented. Deterministic: the same
/// mesh for any thread count.
EvaluateResult evaluate(const Solid& solid, const EvaluateOptions& options = {});

}  // namespace cover
