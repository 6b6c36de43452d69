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
// Everything else needs the ray method (fast-queries issue): volume() then throws NotComputable.

#include <optional>
#include <string>

#include "solid/solid.h"

namespace cover {

struct VolumeOptions {
  bool exact = false;  ///< require an exact method (B-rep evaluation is not available yet)
};

struct VolumeResult {
  double volume = 0;
  std::optional<double> area;  ///< empty where it would need boundary evaluation
  std::string method;          ///< "covering"
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
