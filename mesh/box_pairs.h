#pragma once
// Broad phase: every pair of closed axis-aligned boxes that meet, found with a uniform grid
// (cells about the mean box size, coarsened until the boxes cover at most a few cells each).
// Each box is entered in the cells its box covers; a pair meeting in several cells is reported
// once, by the cell holding the lower corner of the two boxes' intersection (the floor of a
// coordinate is monotone, so that cell lies in both boxes' cell ranges). Within a cell holding
// many boxes, a sort on the lower x bound and a sweep replace the all-pairs loop. Meshes of
// similar-sized triangles cover about one to four cells per triangle, so this costs a sort of a
// few entries per box, against the recursive streaming of CGAL::box_intersection_d.

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "cover/solid/types.h"

namespace cover {

/// Calls pair(a, b), a < b, once for every pair of boxes (indices into `boxes`) whose closed
/// boxes meet (touching counts), in no particular order and possibly from several threads at
/// once. When `pair` returns true the search stops early (other threads finish their chunk).
/// Empty boxes meet nothing. Precondition: finite coordinates, boxes.size() < 2^32.
void box_pairs(std::span<const Bbox> boxes, const std::function<bool(uint32_t, uint32_t)>& pair);

/// The pairs (a, b), a < b, of boxes of different colours (color[a] != color[b]) that meet,
/// sorted; cells holding boxes of one colour only are skipped. Deterministic. Precondition: as
/// box_pairs(), color.size() == boxes.size().
std::vector<std::pair<uint32_t, uint32_t>> box_pairs_between(std::span<const Bbox> boxes,
                                                             std::span<const uint32_t> color);

/// box_pairs_between(), and in the same grid pass every meeting pair (a, b), a < b, of ONE
/// colour passed to same(a, b) — possibly from several threads at once, in no particular order
/// (e.g. each colour's self-intersection test next to the pairs between colours: one pass
/// instead of one per colour plus one between them). Cells of one colour are not skipped.
std::vector<std::pair<uint32_t, uint32_t>> box_pairs_between(
    std::span<const Bbox> boxes, std::span<const uint32_t> color,
    const std::function<void(uint32_t, uint32_t)>& same);

/// A box's corners for the filter below: three ids (a triangle's vertices) and which of them are
/// marked (bit i: id[i]). A mark belongs to the id: every box holding a marked id marks it.
struct BoxCorners {
  std::array<uint32_t, 3> id;
  uint8_t marked = 0;
};

/// The same, except that same(a, b) is not called for pairs of one colour sharing a marked
/// corner id: those are dropped inside the scan, without a call or a look elsewhere (the
/// meeting pairs of a mesh are mostly neighbours sharing a vertex; a self-intersection test
/// whose marked vertices prove their fans' pairs apart, mesh/validate.h star_vertices, then
/// sees only the rest). corners.size() == boxes.size().
std::vector<std::pair<uint32_t, uint32_t>> box_pairs_between(
    std::span<const Bbox> boxes, std::span<const uint32_t> color,
    std::span<const BoxCorners> corners, const std::function<void(uint32_t, uint32_t)>& same);

/// Triangles' corners as BoxCorners, each corner id marked where flag[id] is set.
std::vector<BoxCorners> marked_corners(std::span<const std::array<uint32_t, 3>> tris,
                                       std::span<const uint8_t> flag);

}  // namespace cover
