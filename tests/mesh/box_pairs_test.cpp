// Grid broad phase (mesh/box_pairs.h) against all pairs: random boxes of mixed sizes, boxes that
// only touch (closed boxes meet), flat and point boxes, empty boxes, colours; each pair reported
// once.
#include "cover/mesh/box_pairs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <random>
#include <utility>
#include <vector>

namespace cover {
namespace {

bool meet(const Bbox& a, const Bbox& b) {
  return !a.empty() && !b.empty() && a.min.x <= b.max.x && b.min.x <= a.max.x &&
         a.min.y <= b.max.y && b.min.y <= a.max.y && a.min.z <= b.max.z && b.min.z <= a.max.z;
}

/// Boxes on a coarse lattice (many exact touches) of sizes from 0 (points, flat boxes) to large,
/// plus empty ones.
std::vector<Bbox> random_boxes(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pos(0, 60), size(0, 6), big(0, 40);
  std::vector<Bbox> boxes(n);
  for (size_t i = 0; i < n; ++i) {
    if (i % 97 == 5) continue;  // empty
    const bool large = i % 31 == 0;
    Vec3 lo{pos(rng) * 0.25, pos(rng) * 0.25, pos(rng) * 0.25};
    boxes[i].add(lo);
    boxes[i].add(lo + Vec3{(large ? big(rng) : size(rng)) * 0.25,
                           (large ? big(rng) : size(rng)) * 0.25,
                           (i % 7 == 0 ? 0 : size(rng)) * 0.25});
  }
  return boxes;
}

std::vector<std::pair<uint32_t, uint32_t>> brute(const std::vector<Bbox>& boxes,
                                                 const std::vector<uint32_t>* color) {
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (uint32_t a = 0; a < boxes.size(); ++a)
    for (uint32_t b = a + 1; b < boxes.size(); ++b)
      if (meet(boxes[a], boxes[b]) && (!color || (*color)[a] != (*color)[b]))
        pairs.emplace_back(a, b);
  return pairs;
}

TEST(BoxPairs, EveryMeetingPairOnceAsAllPairs) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const std::vector<Bbox> boxes = random_boxes(3000, seed);
    std::mutex m;
    std::vector<std::pair<uint32_t, uint32_t>> got;
    box_pairs(boxes, [&](uint32_t a, uint32_t b) {
      std::lock_guard<std::mutex> lock(m);
      got.emplace_back(a, b);
      return false;
    });
    std::sort(got.begin(), got.end());
    const auto want = brute(boxes, nullptr);
    EXPECT_GT(want.size(), boxes.size());
    EXPECT_EQ(got, want) << "seed " << seed;  // sorted: no pair twice
  }
}

TEST(BoxPairs, BetweenColoursAndEarlyStop) {
  const std::vector<Bbox> boxes = random_boxes(3000, 7);
  std::vector<uint32_t> color(boxes.size());
  for (size_t i = 0; i < color.size(); ++i) color[i] = static_cast<uint32_t>(i * 7 % 3);
  EXPECT_EQ(box_pairs_between(boxes, color), brute(boxes, &color));
  std::atomic<int> calls{0};
  box_pairs(boxes, [&](uint32_t, uint32_t) { return ++calls >= 1; });
  EXPECT_LT(calls.load(), 100);  // stopped: at most a chunk per thread after the first
}

// box_pairs_between with corners: same() gets exactly the meeting pairs of one colour that share
// no marked corner id (ids from a small pool, so that many pairs share some), the pairs between
// colours are all returned, in the general scan and when every box is one point.
TEST(BoxPairs, OneColourPairsSharingAMarkedCornerAreDropped) {
  for (unsigned seed : {11u, 12u}) {
    for (bool point : {false, true}) {
      std::vector<Bbox> boxes = random_boxes(point ? 300 : 3000, seed);
      if (point)
        for (Bbox& b : boxes)
          if (!b.empty()) b = Bbox{}, b.add(Vec3{1, 2, 3});
      std::mt19937 rng(seed);
      std::uniform_int_distribution<uint32_t> id(0, 40);
      std::vector<uint8_t> mark(41);
      for (uint8_t& m : mark) m = rng() % 2;
      std::vector<uint32_t> color(boxes.size());
      std::vector<BoxCorners> corners(boxes.size());
      for (size_t i = 0; i < boxes.size(); ++i) {
        color[i] = static_cast<uint32_t>(i * 7 % 3);
        for (int c = 0; c < 3; ++c) {
          corners[i].id[c] = id(rng);
          corners[i].marked |= static_cast<uint8_t>(mark[corners[i].id[c]] << c);
        }
      }
      std::mutex m;
      std::vector<std::pair<uint32_t, uint32_t>> same;
      const auto between = box_pairs_between(boxes, color, corners, [&](uint32_t a, uint32_t b) {
        std::lock_guard<std::mutex> lock(m);
        same.emplace_back(a, b);
      });
      EXPECT_EQ(between, brute(boxes, &color));
      std::vector<std::pair<uint32_t, uint32_t>> want;
      for (const auto& [a, b] : brute(boxes, nullptr)) {
        if (color[a] != color[b]) continue;
        bool shared = false;
        for (uint32_t x : corners[a].id)
          for (uint32_t y : corners[b].id) shared = shared || (x == y && mark[x]);
        if (!shared) want.emplace_back(a, b);
      }
      std::sort(same.begin(), same.end());
      EXPECT_GT(want.size(), 10u);
      EXPECT_EQ(same, want) << "seed " << seed << (point ? ", one point" : "");
    }
  }
}

TEST(BoxPairs, AllBoxesOnePointAndTooFew) {
  std::vector<Bbox> boxes(4);
  for (int i = 0; i < 3; ++i) boxes[i].add(Vec3{1, 2, 3});  // boxes[3] empty
  const std::vector<uint32_t> color{0, 1, 1, 0};
  EXPECT_EQ(box_pairs_between(boxes, color),
            (std::vector<std::pair<uint32_t, uint32_t>>{{0, 1}, {0, 2}}));
  EXPECT_TRUE(box_pairs_between(std::vector<Bbox>(1), std::vector<uint32_t>{0}).empty());
}

}  // namespace
}  // namespace cover
