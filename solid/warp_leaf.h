#pragma once
// Warp leaves: Barr's twist, taper and bend (the HybridTree's warping nodes) applied to any
// child solid (meshes, fields, whole subtrees), as plain data. Their kernels (validation, the
// map and its inverse, sound enclosures over boxes) are in field/warp.h; a Solid holds them in
// Solid::warps and a Leaf refers to one by Leaf::warp.
//
// Conventions
//   frame     E(p) = F·(p − point), F the 3 × 3 matrix whose rows are e0 = e2 × e1, e1 = the
//             axis direction and e2 = `toward` made orthogonal to e1 (bend; any unit vector ⊥ e1
//             otherwise), each rounded to doubles. E is DEFINED by these stored doubles (F is
//             orthogonal up to rounding, and the kernels use F⁻¹ in exact rationals), so the map
//             below is a bijection whose inverse is exact in rationals.
//   warp      w = E⁻¹ ∘ L ∘ E with L acting on local coordinates (x, y, z) = E(p), y along the
//             axis:
//     twist   L(x, y, z) = (x cos θ − z sin θ, y, x sin θ + z cos θ), θ = a·y (a in radians per
//             unit: `degrees_per_unit`·π/180): with e0 = e2 × e1, a right-hand turn about the
//             axis direction by θ.
//     taper   L(x, y, z) = (s·x, y, s·z), s(y) linear from scale[0] at y = range[0] to scale[1]
//             at y = range[1], constant beyond the range; s > 0. Rational, so its inverse is.
//     bend    Barr 1984 with rate k = 1/radius toward +z, bend centre y0 = center, bent region
//             y ∈ range = [y_min, y_max]: ŷ = clamp(y, y_min, y_max), θ = k(ŷ − y0),
//             L(x, y, z) = (x, −sin θ (z − 1/k) + y0 + cos θ (y − ŷ),
//                              cos θ (z − 1/k) + 1/k + sin θ (y − ŷ)).
//             Inverse (Barr's printed one is wrong): with (u, v) = (Y − y0, Z − 1/k) and
//             φ = atan2(u, −v), the bent region is φ ∈ [θ_min, θ_max] (θ_min = k(y_min − y0)):
//             y = y0 + φ/k, z = 1/k − √(u² + v²); beyond θ_max (θ̂ = θ_max, c = cos θ̂,
//             s = sin θ̂): y = y_max + (c·u + s·v), z = 1/k + (−s·u + c·v) (and the same with
//             θ_min below); φ outside [θ_min − π/2, θ_max + π/2] is not in the image. w is a
//             bijection onto its image on the half-space z < 1/k, which must hold the child
//             (validated), and θ_max − θ_min ≤ π.
//   membership  p is inside the warped child iff w⁻¹(p) is inside the child; the leaf's box is a
//             sound enclosure of w(child's box).

#include <cstdint>
#include <memory>
#include <string_view>

#include "cover/solid/types.h"

namespace cover {

struct Solid;

enum class WarpKind : uint8_t { kTwist, kTaper, kBend };

/// "twist", "taper", "bend".
inline std::string_view to_string(WarpKind kind) {
  constexpr std::string_view kNames[] = {"twist", "taper", "bend"};
  return kNames[static_cast<int>(kind)];
}

struct WarpLeaf {
  WarpKind kind = WarpKind::kTwist;
  Vec3 point;                   ///< a point of the axis (the frame's origin)
  Vec3 direction{0, 1, 0};      ///< the axis direction as given (any length, not zero)
  Vec3 toward{0, 0, 1};         ///< bend: the direction the axis bends toward (not ∥ axis)
  double degrees_per_unit = 0;  ///< twist: degrees of turn per unit length along the axis
  double range[2] = {0, 1};     ///< taper, bend: [y_min, y_max] along the axis, y_min < y_max
  double scale[2] = {1, 1};     ///< taper: s at range[0] and range[1], both > 0
  double center = 0;            ///< bend: y0, where θ = 0
  double radius = 1;            ///< bend: the radius of curvature 1/k > 0
  /// The frame's rows e0, e1, e2 (set by field::make_frame from point, direction, toward).
  Vec3 frame[3]{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  /// The warped child (shared: copies of a Solid share it; it does not change).
  std::shared_ptr<const Solid> child;
};

}  // namespace cover
