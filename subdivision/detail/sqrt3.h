#pragma once
// The triangles of a √3 level (subdivide.h gives the order): triangle i comes from the edge e
// with first[e] <= i < first[e + 1] (two per interior edge: the flipped pair; one per border
// edge), and each of its corners is either an old corner's vertex or the "apex" of an old
// corner's face: its centre, or on a border-refining level one of its two border points.
// Shared by the faces (subdivide.cpp) and the corner attributes (attributes.cpp).

#include <algorithm>
#include <cstdint>
#include <vector>

#include "cover/subdivision/detail/evaluate.h"

namespace cover::subdivision_detail {

/// A corner of a new triangle: old corner h's vertex, or (apex) the point of face_of[h] that
/// sqrt3_apex_slot(h) names.
struct Sqrt3Corner {
  uint32_t corner;
  bool apex;
};

/// first[e]: the first triangle of edge e; first[#E] the triangle count.
inline std::vector<uint32_t> sqrt3_first_triangles(const Topology& t) {
  const size_t ne = t.edge_count();
  std::vector<uint32_t> first(ne + 1, 0);
  for (size_t e = 0; e < ne; ++e)
    first[e + 1] = first[e] + (t.opposite[t.edge_half[e]] == kNone ? 1 : 2);
  return first;
}

/// The apex of corner h: 0 for its face's centre (or, in a face whose border corner r is refined
/// on this level, its border point near vertex(r) when h = prev(r)), 1 for the border point near
/// vertex(next(r)).
inline uint32_t sqrt3_apex_which(const Topology& t, const Layout& l, uint32_t h) {
  const uint32_t f = t.face_of[h];
  const uint32_t r = l.refine_border ? l.refined[f] : kNone;
  return r == kNone || h == t.prev(r) ? 0 : 1;
}

/// The corners of triangle i.
inline void sqrt3_triangle(const Topology& t, const Layout& l, const std::vector<uint32_t>& first,
                           size_t i, Sqrt3Corner out[3]) {
  // Edge of triangle i: the last e with first[e] <= i.
  const auto e =
      static_cast<uint32_t>(std::upper_bound(first.begin(), first.end(), i) - first.begin() - 1);
  const uint32_t h = t.edge_half[e], o = t.opposite[h];
  if (o != kNone) {
    if (i == first[e]) {
      out[0] = {h, true}, out[1] = {h, false}, out[2] = {o, true};
    } else {
      out[0] = {o, true}, out[1] = {t.next(h), false}, out[2] = {h, true};
    }
  } else if (l.refine_border && l.refined[t.face_of[h]] == h) {
    // The border triangle (border point near a, border point near b, the third vertex); the
    // apexes of h: prev(h)'s is the point near a, h's own the point near b.
    out[0] = {t.prev(h), true}, out[1] = {h, true}, out[2] = {t.prev(h), false};
  } else {
    out[0] = {h, false}, out[1] = {t.next(h), false}, out[2] = {h, true};
  }
}

}  // namespace cover::subdivision_detail
