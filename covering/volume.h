#pragma once
// Volume and area of a CSG solid from its simplicial covering ([Segura2004 §5]).
//
// The covering volume Σ_f Σ [O, v0, vi, vi+1] over the stored (combined-orientation) faces equals
// ∫ Σ_L c_L·w_L. It is the volume of the result only where Σ_L c_L·w_L equals the result's
// indicator almost everywhere. covering_exactness() decides that structurally, never guessing:
//   leaf            simple: winding ∈ {0, 1} (not self-intersecting, and its shells nest with
//                   alternating orientation or have disjoint boxes)
//   union           children exact and pairwise interior-disjoint boxes (volumes add)
//   difference      first child exact; every subtrahend's box interior-disjoint from the first's
//                   (it removes nothing)
//   intersection    one child: that child; children whose boxes share no interior: empty (0)
//   complement      unbounded: never
// Everything else is integrated over parallel rays (detail/ray_volume.h): a quadtree of ray
// cells in the plane orthogonal to a generic direction, refined where the span length is not
// provably affine, with an error bound that bounds the error (not an estimate). The adaptive
// method refines until error_bound ≤ target_relative_error·|volume| or max_rays rays are spent
// (then target_met is false and the bound still holds); `rays` = N fixes the finest cells at
// 1/2^⌈log2 N⌉ of the square. Unbounded results throw NotComputable.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "cover/covering/bvh.h"
#include "cover/covering/prepared.h"
#include "cover/solid/solid.h"

namespace cover {

struct VolumeOptions {
  bool exact =
      false;     ///< require the covering to be exact (else NotComputable; evaluate() is exact)
  int rays = 0;  ///< ray method: finest cells 1/2^⌈log2 rays⌉ of the square (0: adaptive)
  double target_relative_error = 1e-4;  ///< adaptive ray method stops once the bound is below
  size_t max_rays = size_t{1} << 22;    ///< adaptive ray method: budget of rays cast
  /// Bracket method (field leaves): stops once the certified half-width is below this times V.
  /// Its cells grow as 1/target² (the bracket's width is the boundary's area times the cell
  /// size), hence a coarser default than the rays'; max_rays bounds the cells of one level.
  double bracket_relative_error = 1e-2;
  /// Called on the calling thread with the estimated share of the work done, 0..1
  /// (non-decreasing); default: none. The result does not depend on it.
  std::function<void(double fraction)> progress;
};

struct VolumeResult {
  double volume = 0;
  std::optional<double> area;  ///< empty where it would need boundary evaluation
  std::string method;      ///< "covering", "rays", "winding" (open leaves) or "bracket" (fields)
  size_t rays = 0;         ///< rays cast by the ray method; cells settled by the bracket method
  double error_bound = 0;  ///< 0 for exact methods; |volume − exact| ≤ error_bound
  bool target_met = true;  ///< ray method: error_bound ≤ target_relative_error·|volume|
};

/// Signed covering volume Σ over all stored faces (the paper's summed value; see above for
/// when it is the result's volume). Deterministic for any thread count.
double covering_volume(const Solid& solid);

/// Empty when the covering volume of `solid` is its volume; otherwise why not (one line).
std::optional<std::string> covering_inexact_reason(const Solid& solid);

/// Volume (and area where known) of the prepared solid: the covering's value where it is exact,
/// else the ray method with its bound (method "rays"). With open leaves, the winding method
/// (method "winding"): the centres of an n³ grid over the result's box classified as classify()
/// does (n = 128, or options.rays clamped to 2..1024), the volume h³·(centres not outside), the
/// error bound h³·(voxels whose class differs from a face neighbour's, or on the grid's border
/// while not outside), which holds where the grid resolves the boundary.
/// With field leaves, the bracket method (method "bracket"): cells of an octree over the result's
/// box settled by interval bounds of each field over the cell and the exact winding numbers of
/// mesh leaves no covering triangle's box meets; V_in = the full cells, V_out = V_in + the
/// undecided ones, both outward rounded, refined until (V_out − V_in)/2 ≤
/// bracket_relative_error·V or the next level would hold more than max_rays cells; volume = the
/// midpoint, error_bound = its distance to either end (certified), rays = the cells settled;
/// options.exact as well (a curved solid has no exact volume in doubles).
/// \throws NotComputable for an unbounded result, and with options.exact when the covering is
/// not exact for this expression (see above; evaluate() is); InputError with options.exact and
/// an open leaf without field or warp leaves.
VolumeResult volume(const Prepared& prepared, const VolumeOptions& options = {});

/// One-shot: prepares the solid, then measures. \throws as above.
VolumeResult volume(const Solid& solid, const VolumeOptions& options = {});

}  // namespace cover
