#pragma once
// Boundary evaluation of a CSG solid (docs/design.md#exactness, Evaluation): the regularized
// result of the expression as ONE closed, outward-oriented, 2-manifold triangle mesh.
//
// Route (boolean/detail/arrangement.h has the notation and the exactness scheme):
//   1. every leaf face is triangulated (fan when convex, else a constrained triangulation);
//   2. triangles of different leaves whose boxes meet are intersected exactly (configuration by
//      exact orient3d on the doubles, edge ∩ plane points built once each in CGAL Epeck), and
//      so are those of one self-intersecting leaf, less their shared vertices and edges;
//   3. each intersected triangle is re-triangulated with the intersection segments as
//      constraints: split directly when one segment runs between its edges / corners, else a
//      2D constrained Delaunay triangulation in its dominant projection (exact intersections);
//   4. the pieces of each leaf are grouped into patches bounded by intersection curves, and one
//      exact interior point per patch is classified by an exact ray count per leaf: its winding
//      numbers on both sides (w and w ∓ the coincident faces), each leaf by the nonzero rule;
//   5. a piece is kept iff the expression differs on its two sides (regularized), oriented
//      outward; coincident pieces (of several leaves, or of one) are kept once (lowest tri);
//   6. edges with more than two kept faces are paired by exact angular order, and vertices are
//      split per fan, so the output is a 2-manifold; exact points are rounded to nearest doubles;
//   7. faces that the independent rounding made touch or cross (distinct exact points a few
//      ulps apart, or on one double point) are found exactly among the faces with a rounded
//      vertex, and repaired by collapsing rounding-scale edges (mesh/rounding_repair.h).

#include <cstdint>
#include <optional>
#include <vector>

#include "cover/solid/polygon_mesh.h"
#include "cover/solid/solid.h"

namespace cover {

/// Wall-clock seconds per step of evaluate() (the numbers of the route above), for profiling.
struct EvaluatePhases {
  double check = 0;        ///< leaf self-intersection test with the candidate pairs of step 2
                           ///< (one grid pass; 0 without check_leaves)
  double triangulate = 0;  ///< step 1
  double pairs = 0;        ///< step 2: candidate pairs (box intersection) without check_leaves;
                           ///< with it, only the same-leaf pairs of self-intersecting leaves
  double intersect = 0;    ///< step 2: exact pairwise intersections
  double split = 0;        ///< step 3: per-tri re-triangulation
  double identify = 0;     ///< step 3: global point identity, pieces and cut edges
  double select = 0;       ///< steps 4–5
  double assemble = 0;     ///< step 6 and the mesh report
  double repair = 0;       ///< step 7: rounding contacts found and repaired
};

struct EvaluateOptions {
  /// Find self-intersecting leaves (exact CGAL tests of each leaf's triangle pairs, in the grid
  /// pass of the candidate pairs) and resolve them in the arrangement; false trusts that no leaf
  /// intersects itself (a leaf that does then gives an undefined, possibly invalid, result).
  bool check_leaves = true;
  size_t grain = 64;  ///< items per parallel chunk (results never depend on it)
  /// Also compute EvaluateResult::exact_volume (rationals over every kept triangle: slower).
  /// evaluate() then throws NotComputable when that volume is not 0 but below the normal
  /// doubles (2.2e-308, a solid of side below about 1e-103): no double states it exactly.
  bool exact_volume = false;
  /// When given, receives the wall-clock seconds per step (profiling; the result is the same).
  EvaluatePhases* phases = nullptr;
  /// Mixed evaluation (Model::evaluate, docs/design.md "Mixed evaluation"): each field, warp and
  /// open-mesh leaf is first meshed by polygonize/polygonize.h at `mesh_resolution` cells along
  /// its box's largest extent, every vertex within `mesh_tolerance` of its surface (0: the cell
  /// size / 1024); the exact Booleans then combine those meshes with the mesh leaves.
  int mesh_resolution = 128;
  double mesh_tolerance = 0;
};

/// A leaf that mixed evaluation meshed (EvaluateResult::meshed).
struct MeshedLeaf {
  uint32_t leaf = 0;     ///< Solid::leaves index
  size_t triangles = 0;  ///< of its mesh
  double cell_size = 0;  ///< the polygonizer's step
  double tolerance = 0;  ///< certified: every vertex of its mesh within this of its surface
  size_t uncertain = 0;  ///< points whose class could not be certified (circle skeletons)
  size_t clipped = 0;    ///< grid-border points found inside (the leaf reaches past its box)
};

struct EvaluateResult {
  PolygonMesh mesh;  ///< triangles, outward; empty (no faces) when the result is empty
  std::vector<uint32_t> face_leaf;  ///< per face of `mesh`: the leaf (Solid::leaves index) whose
                                    ///< surface it lies on (the lowest, on coincident faces)
  double volume = 0;  ///< signed volume of `mesh` (doubles, after rounding; summed about
                      ///< the centre of its box, at a power-of-two scale: no cancellation
                      ///< far from the origin, no underflow for tiny solids)
  /// With EvaluateOptions::exact_volume: the volume of the exact result (its exact points, before
  /// rounding), summed in rationals and rounded to the nearest double once.
  std::optional<double> exact_volume;
  double area = 0;         ///< surface area of `mesh`
  int64_t genus = 0;       ///< Σ over components of the genus (χ = 2 − 2g per closed component)
  int64_t components = 0;  ///< connected components of `mesh`
  size_t candidate_pairs = 0;     ///< triangle pairs with meeting boxes (of different leaves,
                                  ///< or of one self-intersecting leaf)
  size_t intersecting_pairs = 0;  ///< pairs that really meet
  size_t patches = 0;             ///< classified patches
  int64_t collapsed_edges = 0;    ///< step 7: rounding-scale edges collapsed (usually 0)
  int64_t rounding_contacts = 0;  ///< step 7: face pairs still meeting (0: none left)
  /// Mixed evaluation: the leaves that were meshed first, in leaf order (empty when every leaf
  /// is a closed mesh: the result is then exact up to the final rounding).
  std::vector<MeshedLeaf> meshed;
  double tolerance = 0;  ///< the largest meshed leaf's tolerance (0 when none was meshed)
};

/// Evaluates `solid` (closed leaves; the nonzero winding rule per leaf) to a B-rep. A
/// self-intersecting leaf stands for its nonzero-winding set, as in classify(): its own crossing
/// curves join the arrangement and winding numbers decide. Throws InputError when a leaf face's
/// boundary crosses itself. Deterministic: the same mesh and face_leaf for any thread count.
EvaluateResult evaluate(const Solid& solid, const EvaluateOptions& options = {});

}  // namespace cover
