#pragma once
// Volume of any bounded CSG result by integrating ray span lengths, with an error bound that
// is a proof, not an estimate (volume.h states when this path runs).
//
// Notation: d is a fixed generic unit direction, (u, v) coordinates in the plane orthogonal to
// d, L(u, v) the total length of the result's spans along the line through (u, v) (cast()).
// Volume = ∫ L du dv over a square containing the result's projection. The square is split as a
// quadtree of cells; each cell C carries the covering triangles whose projections meet it.
//   certified cell   every triangle of C contains C's projection strictly, and no two of them
//                    change depth order over C: every line through C crosses the same triangles
//                    in the same order, so L is affine on C and the midpoint rule is exact
//                    (∫_C L = area·L(centre)). A cell with no triangle has L ≡ 0.
//   other cells      L is continuous for closed leaves (a crossing moves continuously and pairs
//                    of crossings appear at equal depth), with |∇L| ≤ G = Σ_i g_i over C's
//                    triangles (g_i = |∇ depth_i|), and 0 ≤ L ≤ T (T: the depth extent of C's
//                    triangles). So |∫_C L − area·L(centre)| ≤ area·min(r·G, T), r = C's
//                    half-diagonal. These cells are split further.
// Refinement goes level by level over the uncertified cells until the summed bound is at most
// target_relative_error·|V|, or a fixed level (--rays), or the ray budget is spent (then the
// result says the target was not met). A floating-point allowance (2^-40 relative) covers the
// rounding of span lengths and sums. Geometric tests use a relative margin, always on the
// conservative side: a doubtful cell is never certified and a doubtful triangle stays in the list.

#include <cstddef>
#include <functional>

#include "cover/covering/bvh.h"
#include "cover/covering/prepared.h"
#include "cover/solid/solid.h"

namespace cover::detail {

struct RayVolumeOptions {
  double target_relative_error = 1e-4;  ///< stop refining once bound ≤ this·|V| (adaptive)
  int fixed_level = -1;                 ///< ≥ 0: refine every uncertified cell to this level only
  size_t max_rays = size_t{1} << 22;    ///< budget of cast rays (adaptive)
  std::function<void(double)> progress;  ///< fraction of the budget or of the levels done
};

struct RayVolume {
  double volume = 0;
  double error_bound = 0;  ///< |volume − exact volume| ≤ error_bound
  size_t rays = 0;         ///< rays cast
  int level = 0;           ///< finest quadtree level reached (2^level cells per side)
  bool target_met = false;
};

/// Precondition: `box` contains the (bounded) result; closed leaves.
RayVolume ray_volume(const Prepared& prepared, const Bbox& box, const RayVolumeOptions& options);

}  // namespace cover::detail
