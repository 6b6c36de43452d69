// Step 2 for self-intersecting leaves (boolean/evaluate.h, "self-intersecting leaves"): the tri
// pairs of ONE leaf that go into the arrangement next to the pairs of different leaves, and the
// removal of the contacts every mesh has with itself (its shared vertices and edges).
//
// Notation (as in boolean/detail/arrangement_steps.h)
//   t, u     tris of the same self-intersecting leaf whose closed double boxes meet, t < u
//   shared   the point ids t and u have in common (0–3): two tris of a leaf touch at shared
//            vertices and edges without crossing there
//
// Which pairs (exact orient3d on the doubles, no construction):
//   * no shared id, or one: the pair goes through intersect_pairs() like any other; a hit that is
//     only the shared vertex is dropped afterwards (drop_shared);
//   * two shared ids (a shared edge a–b): when u's third corner is off plane(t), the planes meet
//     in line a–b and t ∩ u is exactly the edge: skipped. Coplanar, the tris either lie on the
//     two sides of a–b (the hit is the edge, dropped) or fold over each other (an overlap
//     polygon, kept);
//   * three shared ids (a tri repeated, either orientation): coplanar, the whole tri overlaps.
// Keeping every remaining contact is always sound — a constraint that is no crossing only splits
// pieces and patches further — so the filters above only spare work.
#include <CGAL/box_intersection_d.h>

#include <algorithm>

#include "cover/boolean/detail/arrangement_steps.h"
#include "cover/solid/predicates.h"

namespace cover::boolean_detail {

namespace {

int shared_ids(const Tri& t, const Tri& u, uint32_t out[3]) {
  int n = 0;
  for (uint32_t a : t.v)
    for (uint32_t b : u.v)
      if (a == b) out[n++] = a;
  return n;
}

}  // namespace

std::vector<std::pair<uint32_t, uint32_t>> same_leaf_pairs(const std::vector<Tri>& tris,
                                                           const std::vector<Vec3>& pos,
                                                           const std::vector<uint8_t>& self) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, uint32_t,
                                                        CGAL::Box_intersection_d::ID_EXPLICIT>;
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (size_t begin = 0; begin < tris.size();) {
    size_t end = begin;
    while (end < tris.size() && tris[end].leaf == tris[begin].leaf) ++end;
    const uint32_t leaf = tris[begin].leaf;
    const size_t first = begin;
    begin = end;
    if (leaf >= self.size() || !self[leaf]) continue;
    std::vector<Box> boxes;
    boxes.reserve(end - first);
    for (size_t i = first; i < end; ++i) {
      CGAL::Bbox_3 b;
      for (uint32_t v : tris[i].v)
        b += CGAL::Bbox_3(pos[v].x, pos[v].y, pos[v].z, pos[v].x, pos[v].y, pos[v].z);
      boxes.emplace_back(b, static_cast<uint32_t>(i));
    }
    // Closed boxes: touching tris are candidates too.
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
      const uint32_t t = std::min(x.info(), y.info()), u = std::max(x.info(), y.info());
      uint32_t s[3];
      if (shared_ids(tris[t], tris[u], s) == 2) {
        uint32_t third = kNone;
        for (uint32_t v : tris[u].v)
          if (v != s[0] && v != s[1]) third = v;
        const Tri& a = tris[t];
        if (orient3d(pos[a.v[0]], pos[a.v[1]], pos[a.v[2]], pos[third]) != 0) return;
      }
      pairs.emplace_back(t, u);
    });
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

void drop_shared(const std::vector<Tri>& tris,
                 const std::vector<std::pair<uint32_t, uint32_t>>& pairs,
                 const std::vector<Point>& points, std::vector<Hit>& hits) {
  for (size_t p = 0; p < pairs.size(); ++p) {
    const Tri& t = tris[pairs[p].first];
    const Tri& u = tris[pairs[p].second];
    Hit& hit = hits[p];
    if (t.leaf != u.leaf || hit.empty()) continue;
    uint32_t s[3];
    const int n = shared_ids(t, u, s);
    if (n == 0) continue;
    auto is_shared = [&](const Point& x) {
      for (int i = 0; i < n; ++i)
        if (x == points[s[i]]) return true;
      return false;
    };
    bool only_shared = true;
    if (hit.ends[0].id != kNone) {  // transversal: a point or a segment of ids
      for (const End& e : hit.ends) only_shared = only_shared && std::find(s, s + n, e.id) != s + n;
    } else if (hit.segments.size() <= 1) {  // coplanar: one point or one segment
      for (const Point& x : hit.points) only_shared = only_shared && is_shared(x);
      for (const K::Segment_3& x : hit.segments)
        only_shared = only_shared && is_shared(x.source()) && is_shared(x.target());
    } else {
      only_shared = false;  // an overlap polygon
    }
    if (only_shared) hit = Hit{};
  }
}

}  // namespace cover::boolean_detail
