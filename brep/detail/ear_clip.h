#pragma once
// Ear-clipping triangulation of one weakly simple polygon (O'Rourke 1998 §1.6; [Erleben2006 §4]
// uses the same ear search). Shared by the cap (exact constructed points, cap.cpp) and by the
// splitting of non-convex input faces (input doubles, clip.cpp); only the geometry callbacks
// differ.
//
// Nodes 0..n−1 are the polygon's corners in counter-clockwise order. Nodes with equal id() are the
// same point (a pinched vertex or both ends of a bridge, [Erleben2006 §6]). An ear (a, b, c) is cut
// when b is strictly convex and no other node blocks it: a reflex (or flat) node inside or on the
// closed triangle, or a node at a corner's point whose edge leaves that corner into the triangle
// (or along the diagonal a–c). Only reflex nodes and nodes sharing an id are tested (a convex node
// inside an ear implies a reflex one inside). Valid ears whose tip is nearly flat (Geometry::thin,
// a quality hint that never decides validity) are cut only when a full turn finds no other: a
// near-collinear chain is then fanned from a far node instead of getting slivers whose diagonals
// pass within rounding distance of the tip. No ear in a full turn only happens on degenerate input:
// the first convex node (else any node) is cut and `forced` counts it.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace cover::brep::detail {

/// Triangles (a, b, c) of node indices, counter-clockwise, in cutting order: ear tip b is removed
/// from the polygon; the last triangle is the final remainder. Geometry provides
/// `int orient(a, b, c)` (exact sign, > 0 counter-clockwise), `uint32_t id(node)` and
/// `bool box_may_contain(p, a, b, c)` (conservative filter: false only if p is outside the
/// triangle's bounding box), `std::array<double, 4> bounds(node)` (conservative [xlo, xhi, ylo,
/// yhi] of the node's point, for the candidate grid) and `bool thin(a, b, c)` (the angle at b
/// is nearly flat).
/// Precondition: n ≥ 3.
template <class Geometry>
std::vector<std::array<uint32_t, 3>> ear_clip(uint32_t n, const Geometry& g, int64_t& forced) {
  std::vector<std::array<uint32_t, 3>> tris;
  tris.reserve(n - 2);
  std::vector<uint32_t> prev(n), next(n);
  for (uint32_t i = 0; i < n; ++i) {
    prev[i] = i == 0 ? n - 1 : i - 1;
    next[i] = i + 1 == n ? 0 : i + 1;
  }
  std::vector<uint8_t> alive(n, 1), reflex(n), dup(n, 0);
  {
    std::vector<std::pair<uint32_t, uint32_t>> ids(n);
    for (uint32_t i = 0; i < n; ++i) ids[i] = {g.id(i), i};
    std::sort(ids.begin(), ids.end());
    for (uint32_t i = 1; i < n; ++i)
      if (ids[i].first == ids[i - 1].first) dup[ids[i].second] = dup[ids[i - 1].second] = 1;
  }
  // Candidate blockers (reflex or sharing an id) bucketed in a uniform grid of about n/2 cells
  // over the conservative bounds, so an ear test visits the cells its triangle's box overlaps.
  std::array<double, 4> box = g.bounds(0);
  for (uint32_t i = 1; i < n; ++i) {
    const std::array<double, 4> b = g.bounds(i);
    box = {std::min(box[0], b[0]), std::max(box[1], b[1]), std::min(box[2], b[2]),
           std::max(box[3], b[3])};
  }
  const int side = std::max(1, static_cast<int>(std::sqrt(n / 2.0)));
  const double sx = box[1] > box[0] ? side / (box[1] - box[0]) : 0;
  const double sy = box[3] > box[2] ? side / (box[3] - box[2]) : 0;
  auto cell_x = [&](double x) {
    return std::clamp(static_cast<int>((x - box[0]) * sx), 0, side - 1);
  };
  auto cell_y = [&](double y) {
    return std::clamp(static_cast<int>((y - box[2]) * sy), 0, side - 1);
  };
  std::vector<std::vector<uint32_t>> cells(static_cast<size_t>(side) * side);
  for (uint32_t i = 0; i < n; ++i) {
    reflex[i] = g.orient(prev[i], i, next[i]) <= 0;
    if (!reflex[i] && !dup[i]) continue;
    const std::array<double, 4> b = g.bounds(i);
    for (int y = cell_y(b[2]); y <= cell_y(b[3]); ++y)
      for (int x = cell_x(b[0]); x <= cell_x(b[1]); ++x)
        cells[static_cast<size_t>(y) * side + x].push_back(i);
  }
  // Does node p block the ear (a, b, c)?
  auto blocks = [&](uint32_t p, uint32_t a, uint32_t b, uint32_t c) {
    if (!g.box_may_contain(p, a, b, c)) return false;
    const uint32_t ip = g.id(p);
    if (ip == g.id(a) || ip == g.id(b) || ip == g.id(c)) {
      for (uint32_t q : {prev[p], next[p]}) {
        if (ip == g.id(a) && g.orient(a, b, q) > 0 && g.orient(c, a, q) >= 0) return true;
        if (ip == g.id(c) && g.orient(b, c, q) > 0 && g.orient(c, a, q) >= 0) return true;
        if (ip == g.id(b) && g.orient(a, b, q) > 0 && g.orient(b, c, q) > 0) return true;
      }
      return false;
    }
    if (!reflex[p]) return false;
    return g.orient(a, b, p) >= 0 && g.orient(b, c, p) >= 0 && g.orient(c, a, p) >= 0;
  };
  auto is_ear = [&](uint32_t b) {
    const uint32_t a = prev[b], c = next[b];
    if (g.orient(a, b, c) <= 0) return false;
    const std::array<double, 4> ba = g.bounds(a), bb = g.bounds(b), bc = g.bounds(c);
    const int x0 = cell_x(std::min({ba[0], bb[0], bc[0]})),
              x1 = cell_x(std::max({ba[1], bb[1], bc[1]}));
    const int y0 = cell_y(std::min({ba[2], bb[2], bc[2]})),
              y1 = cell_y(std::max({ba[3], bb[3], bc[3]}));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (uint32_t p : cells[static_cast<size_t>(y) * side + x])
          if (alive[p] && (reflex[p] || dup[p]) && p != a && p != b && p != c && blocks(p, a, b, c))
            return false;
    return true;
  };
  auto cut = [&](uint32_t b) {
    const uint32_t a = prev[b], c = next[b];
    tris.push_back({a, b, c});
    next[a] = c;
    prev[c] = a;
    alive[b] = 0;
    reflex[a] = g.orient(prev[a], a, c) <= 0;
    reflex[c] = g.orient(a, c, next[c]) <= 0;
  };
  uint32_t remaining = n, ear = 0, stop = 0;
  bool allow_thin = false;
  while (remaining > 3) {
    if ((allow_thin || !g.thin(prev[ear], ear, next[ear])) && is_ear(ear)) {
      const uint32_t c = next[ear];
      cut(ear);
      --remaining;
      ear = stop = c;
      allow_thin = false;
      continue;
    }
    ear = next[ear];
    if (ear != stop) continue;
    if (!allow_thin) {
      allow_thin = true;
      continue;
    }
    ++forced;
    uint32_t pick = ear;
    for (uint32_t k = 0, v = ear; k < remaining; ++k, v = next[v])
      if (g.orient(prev[v], v, next[v]) > 0) {
        pick = v;
        break;
      }
    const uint32_t c = next[pick];
    cut(pick);
    --remaining;
    ear = stop = c;
    allow_thin = false;
  }
  tris.push_back({prev[ear], ear, next[ear]});
  return tris;
}

}  // namespace cover::brep::detail
