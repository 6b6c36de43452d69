#pragma once
// A uniform grid over the BVH's box that remembers which cells no surface touches, and whether
// such a cell lies inside or outside the result (internal to covering/). Exact by construction:
// the grid planes are fixed doubles, a triangle marks every cell whose CLOSED extent meets its
// box (exact comparisons), and an unmarked closed cell meets no leaf surface, so every leaf's
// winding — hence the result's membership — is constant on it. Face-adjacent unmarked cells share
// a face no surface touches, so a flood fill labels whole components from ONE exact
// classification each (octree/octree.h uses the same argument for its cells).
// Used by classify() when many points are queried: most random points then cost one lookup.

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "cover/covering/bvh.h"

namespace cover::detail {

class CellGrid {
 public:
  /// `member(p)` must return the result's membership at a point p on no surface.
  /// `settled(box)` (optional), for results with open leaves: true only when, on the closed box,
  /// every open leaf's membership is that of the closed-up leaf (W ≠ 0: no cone triangle meets
  /// the box and |w_C| < 1/2 there, gwn.h winding_below). Empty cells it does not settle are
  /// marked like surface cells (−1), so the membership is again constant on each component of
  /// the rest (W is, as no surface of any closure meets it). Checked on blocks of 8³ cells,
  /// split into octants where it fails.
  CellGrid(const Bvh& bvh, int resolution, const std::function<bool(const Vec3&)>& member,
           const std::function<bool(const Bbox&)>& settled = {});

  /// 1 inside, 0 outside, −1 unknown (p is in a surface cell or outside the grid).
  int lookup(const Vec3& p) const;

 private:
  size_t index(int i, int j, int k) const {
    return (static_cast<size_t>(k) * n_ + static_cast<size_t>(j)) * n_ + static_cast<size_t>(i);
  }
  int n_ = 0;
  std::array<std::vector<double>, 3> planes_;  ///< n+1 increasing coordinates per axis
  std::array<double, 3> scale_{};              ///< cells per unit length (index guess only)
  std::vector<int8_t> state_;                  ///< −1 surface, 0 outside, 1 inside
};

}  // namespace cover::detail
