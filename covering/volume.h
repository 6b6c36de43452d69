#pragma once
// Volume and area of a CSG solid from its simplicial covering (paper §5, DESIGN.md §3).
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
// Everything else is integrated over parallel rays (covering/ray.h spans): N×N rays over the
// bounding sphere of a box known to contain the result, along a fixed generic direction (no face
// of a typical model is parallel to it, so the span length is a continuous piecewise-linear
// function of the ray and the midpoint rule converges as O(h²)). Two such directions are used;
// volume is their mean and error_bound the a-posteriori estimate |V_d1 − V_d2| + |V_d1(N) −
// V_d1(N/2)| (the lattices err independently; an estimate, not a proof). N doubles from 256 until error_bound ≤ target_relative_error·V or
// N reaches max_rays. Unbounded results (a complement at the root) throw NotComputable.

#include <functional>
#include <optional>
#include <string>

#include "solid/solid.h"

namespace cover {

struct VolumeOptions {
  bool exact = false;                   ///< require an exact method (B-rep: not available yet)
  int rays = 0;                         ///< rays per side for the ray method (0: adaptive)
  double target_relative_error = 1e-4;  ///< adaptive ray method stops below this
  int max_rays = 2048;                  ///< adaptive ray method: largest N
  /// Called on the calling thread with the estimated share of the work done, 0..1
  /// (non-decreasing); default: none. The result does not depend on it.
  std::function<void(double fraction)> progress;
};

struct VolumeResult {
  double volume = 0;
  std::optional<double> area;  ///< empty where it would need boundary evaluation
  std::string method;          ///< "covering" or "rays"
  int rays = 0;                ///< rays per side used by the ray method
  double error_bound = 0;      ///< 0 for exact methods
};

/// Signed covering volume Σ over all stored faces (the paper's summed value; see above for
/// when it is the result's volume). Deterministic for any thread count.
double covering_volume(const Solid& solid);

/// Empty when the covering volume of `solid` is its volume; otherwise why not (one line).
std::optional<std::string> covering_inexact_reason(const Solid& solid);

/// Volume (and area where known) of the solid. Throws NotComputable when no available method is
/// exact for this expression (see above).
VolumeResult volume(const Solid& solid, const VolumeOptions& options = {});

}  // namespace cover
