#pragma once
// Exact point classification against a CSG solid ([Segura2004 §2 Theorem 2]).
//
// Per leaf, the covering sum at Q with the covering origin O pushed to infinity along −s·e_k
// equals the signed count of covering triangles crossed by the half-line Q + t·s·e_k, t > 0:
// the leaf's winding number (nonzero rule: inside iff w ≠ 0). The axis direction s·e_k is the
// one leaving the solid's box soonest (any choice gives the same number). Ties (half-line
// through a triangle's edge or vertex) are broken by a symbolic perturbation Q + ε·e_u + ε²·e_w
// in the projection — consistent for every triangle, hence the count of a genuinely perturbed
// point, with no epsilon.
// Points exactly on a leaf's surface are found exactly (orient3d = 0 and closed containment) and
// classified at the RESULT level from the arrangement of the face planes through the point
// (covering/detail/local.h): inside / outside when the result is locally full / empty (a face of A
// buried in B for A∪B is inside), otherwise face / edge / vertex of the result's boundary.
// classify() walks a BVH (covering/bvh.h): only boxes that the half-line can meet are visited,
// O(log n) per query; for many points it first labels the grid cells no surface touches
// (covering/detail/cell_grid.h, exact) and visits the remaining points in spatial order.
// classify_brute_force() visits every covering triangle: the independent O(faces) path that tests
// compare against. Both use the same exact per-triangle decision.

#include <cstdint>
#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "cover/covering/bvh.h"
#include "cover/covering/gwn.h"
#include "cover/covering/prepared.h"
#include "cover/solid/solid.h"
#include "cover/solid/voxel_bounds.h"

namespace cover {

enum class PointClass : uint8_t { kOutside, kInside, kFace, kEdge, kVertex };

/// "outside", "inside", "face", "edge", "vertex".
std::string_view to_string(PointClass c);

struct ClassifyOptions {
  size_t grain = 256;              ///< points per parallel chunk (results never depend on it)
  size_t grid_min_points = 20000;  ///< build the empty-cell grid from this many points on
  int grid_max_resolution = 64;    ///< cells per axis of that grid, at most
  /// Open leaves (Leaf::open) are inside where |generalized winding number| > 1/2 (gwn.h),
  /// evaluated on the Prepared's trees with these options (a one-shot call also builds the
  /// trees with them).
  GwnOptions gwn_options;
};

/// Classifies every point of the prepared solid. Thread-count independent.
/// Field leaves (solid/field_leaf.h): inside where the certified sign of f − T is positive
/// (field/field.h sign); a point on a field's surface is classified from the tree over the
/// memberships that leaf takes on either side (face where they differ).
/// Open leaves: membership by the generalized winding number (|w| > 1/2, gwn.h) for points off
/// their surface; a point on an open leaf's surface is classified by the same local analysis as
/// on a closed leaf (its faces read as the leaf's boundary there). With open leaves the empty-cell
/// grid keeps only cells where every closure's cones subtend |w_C| < 0.4 (gwn.h winding_below;
/// docs/design.md "Open leaves"). \pre points are finite (Model::classify checks).
std::vector<PointClass> classify(const Prepared& prepared, std::span<const Vec3> points,
                                 const ClassifyOptions& options = {});

/// classify() and the number of points it could not certify (`uncertain`): points where a
/// circle skeleton's interval enclosure of f − T contains 0 (decided by the double evaluation's
/// sign: inside when f > T) and points where several surfaces meet in a way the tree does not
/// settle (reported face). Always 0 for solids of meshes and polynomial fields off such points.
struct Classification {
  std::vector<PointClass> classes;
  size_t uncertain = 0;
};
Classification classify_counted(const Prepared& prepared, std::span<const Vec3> points,
                                const ClassifyOptions& options = {});

/// One-shot: prepares the solid, then classifies.
std::vector<PointClass> classify(const Solid& solid, std::span<const Vec3> points,
                                 const ClassifyOptions& options = {});

/// The centres (VoxelLattice::centre, global indices) of the index box `box` of `lattice` that
/// classify() finds not outside, as calls member(i, j, k) with box-local indices, i slowest, on
/// the calling thread; classified in batches of whole x slabs of about 2^20 centres (bounded
/// memory). How grids answer open leaves (voxel/voxelize.h, volume()'s winding method).
void classify_lattice(const Prepared& prepared, const VoxelLattice& lattice, const IndexBox& box,
                      const std::function<void(int i, int j, int k)>& member);

/// The same classification visiting every covering triangle for every point (reference path;
/// open leaves by the direct solid-angle sum, generalized_winding_direct).
std::vector<PointClass> classify_brute_force(const Solid& solid, std::span<const Vec3> points,
                                             const ClassifyOptions& options = {});

/// Per point and leaf, row-major (point i's leaf l at i·leaves + l): the leaf's exact winding
/// number at the point, and whether the point lies on that leaf's surface (where a winding
/// number is undefined; `winding` then holds the count of the perturbed point, which is a
/// neighbouring value). Thread-count independent.
struct LeafWindings {
  size_t leaves = 0;
  std::vector<int32_t> winding;
  std::vector<uint8_t> on_surface;
};

/// Every leaf's winding number at every point: a closed leaf's exact winding number; an open
/// leaf's generalized winding number w rounded to the nearest integer (gwn.h open_windings): 0
/// exactly where |w| ≤ 1/2 as classify() decides it, so an entry is nonzero exactly where
/// classify() counts that leaf inside. Where a point is on leaf l's surface (on_surface) the
/// entry is undefined: a closed leaf's holds a neighbouring count, an open leaf's 0.
LeafWindings leaf_windings(const Prepared& prepared, std::span<const Vec3> points,
                           const ClassifyOptions& options = {});

/// Winding number of each leaf at q (exact), for q on no leaf's surface; on_surface[l] is set
/// for the leaves whose surface contains q (their winding is then meaningless).
void leaf_windings(const Solid& solid, const Vec3& q, std::vector<int>& winding,
                   std::vector<uint8_t>& on_surface);

}  // namespace cover
