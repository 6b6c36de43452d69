// select_pieces hands assemble() the kept triangles' half-edges in group_half_edges' order,
// filtered from the pieces' grouping (boolean/select.cpp) instead of grouping the kept
// triangles again. The order decides the pairing around crowded edges and the output's vertex
// numbering, so it must be exactly the order group_half_edges gives over the kept triangles:
// checked here over unions, differences and intersections with reversed pieces (differences),
// coincident faces (shared box faces) and crowded edges (boxes touching along an edge); and
// group_half_edges against a plain stable sort by edge key.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "cover/boolean/detail/arrangement.h"
#include "cover/boolean/evaluate.h"
#include "cover/solid/primitives.h"
#include "cover/solid/solid.h"

namespace cover::boolean_detail {
namespace {

void expect_grouping_of_kept(const Solid& solid) {
  EvaluatePhases seconds;
  std::vector<uint8_t> self;
  const Arrangement arr = build_arrangement(solid, true, 64, seconds, self);
  std::vector<uint32_t> leaves, grouped, want, scratch;
  size_t patches = 0;
  const auto kept = select_pieces(solid, arr, 64, leaves, patches, grouped);
  ASSERT_FALSE(kept.empty());
  auto from = [&](uint32_t h) { return kept[h / 3][h % 3]; };
  auto to = [&](uint32_t h) { return kept[h / 3][(h % 3 + 1) % 3]; };
  group_half_edges(kept.size(), arr.points.size(), from, to, want, scratch);
  EXPECT_EQ(grouped, want);
  // group_half_edges itself (parallel counting by parts): a stable sort by edge key.
  std::vector<uint32_t> sorted(3 * kept.size());
  std::iota(sorted.begin(), sorted.end(), 0u);
  std::stable_sort(sorted.begin(), sorted.end(), [&](uint32_t x, uint32_t y) {
    return edge_key(from(x), to(x)) < edge_key(from(y), to(y));
  });
  EXPECT_EQ(want, sorted);
}

Solid box(Vec3 lo, Vec3 hi) { return make_leaf(make_box(lo, hi), "box"); }
Solid ball(Vec3 c, double r) { return make_leaf(make_sphere(c, r, 24), "sphere"); }

TEST(KeptGrouping, IsGroupHalfEdgesOverTheKeptTriangles) {
  expect_grouping_of_kept(subtract({box({0, 0, 0}, {2, 2, 2}), ball({1, 1, 1.9}, 0.8)}));
  expect_grouping_of_kept(unite({ball({0, 0, 0}, 1), ball({0.7, 0.2, 0.1}, 0.9)}));
  expect_grouping_of_kept(intersect({box({0, 0, 0}, {2, 2, 2}), ball({1.5, 1, 1}, 1.1)}));
  // Coincident faces (a shared face) and edges with four faces (boxes touching along an edge).
  expect_grouping_of_kept(unite({box({0, 0, 0}, {1, 1, 1}), box({1, 0, 0}, {2, 1, 1})}));
  expect_grouping_of_kept(unite({box({0, 0, 0}, {1, 1, 1}), box({1, 1, 0}, {2, 2, 1})}));
  expect_grouping_of_kept(
      subtract({box({0, 0, 0}, {3, 3, 3}), box({1, 1, 1}, {2, 2, 4}), ball({1.5, 1.5, 0}, 0.7)}));
}

}  // namespace
}  // namespace cover::boolean_detail
