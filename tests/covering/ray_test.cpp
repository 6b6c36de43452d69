// Ray casting through the non-evaluated solid (covering/ray.h): hits, signs and spans against
// analytic answers, the tie rule on edges and faces, unbounded spans, and the batch, single and
// depth-first casts against each other.
#include "cover/covering/ray.h"

#include <gtest/gtest.h>

#include <random>

#include "cover/solid/primitives.h"
#include "helpers.h"

namespace cover {
namespace {

Solid box(Vec3 lo, Vec3 hi) { return make_leaf(make_box(lo, hi), "box"); }

RayResult cast_one(const Solid& s, const Ray& r) {
  const Bvh bvh(s);
  return cast(bvh, s.tree, s.leaves.size(), r);
}

TEST(Ray, BoxHitsSignsAndSpan) {
  const Solid s = box({0, 0, 0}, {1, 1, 1});
  const RayResult r = cast_one(s, {{-1, 0.5, 0.25}, {1, 0, 0}});
  ASSERT_EQ(r.hits.size(), 2u);
  EXPECT_DOUBLE_EQ(r.hits[0].t, 1.0);
  EXPECT_EQ(r.hits[0].sign, -1);  // entering
  EXPECT_DOUBLE_EQ(r.hits[1].t, 2.0);
  EXPECT_EQ(r.hits[1].sign, 1);  // leaving
  ASSERT_EQ(r.spans.size(), 1u);
  EXPECT_DOUBLE_EQ(r.spans[0].t0, 1.0);
  EXPECT_DOUBLE_EQ(r.spans[0].t1, 2.0);
  const Bvh bvh(s);
  const FirstHit f = first_hit(bvh, r);
  ASSERT_TRUE(f.hit);
  EXPECT_DOUBLE_EQ(f.t, 1.0);
  EXPECT_LT(f.normal.x, 0);  // outward normal faces the ray
}

TEST(Ray, DifferenceSpans) {
  const Solid s = subtract({box({0, 0, 0}, {1, 1, 1}), box({0.25, -1, -1}, {0.75, 2, 2})});
  const RayResult r = cast_one(s, {{-1, 0.5, 0.5}, {1, 0, 0}});
  ASSERT_EQ(r.spans.size(), 2u);
  EXPECT_DOUBLE_EQ(r.spans[0].t0, 1.0);
  EXPECT_DOUBLE_EQ(r.spans[0].t1, 1.25);
  EXPECT_DOUBLE_EQ(r.spans[1].t0, 1.75);
  EXPECT_DOUBLE_EQ(r.spans[1].t1, 2.0);
}

TEST(Ray, EdgesAndFacesAreCountedOnce) {
  // Rays along an edge, through a vertex, and in a face's plane: the perturbed line crosses
  // the closed surface an even number of times with signs summing to zero (winding 0 far away).
  const Solid s = box({0, 0, 0}, {1, 1, 1});
  const Ray rays[] = {{{-1, 0, 0}, {1, 0, 0}},     {{-1, -1, -1}, {1, 1, 1}},
                      {{-1, 0.5, 1}, {1, 0, 0}},   {{-1, 1, 0.5}, {1, 0, 0}},
                      {{0.5, 0.5, -1}, {0, 0, 1}}, {{-1, 0.5, 0.5}, {1, 0.5, 0}}};
  for (const Ray& ray : rays) {
    const RayResult r = cast_one(s, ray);
    int winding = 0;
    for (const RayHit& h : r.hits) winding += h.sign;
    EXPECT_EQ(winding, 0);
    EXPECT_EQ(r.hits.size() % 2, 0u);
    for (const Span& sp : r.spans) EXPECT_LT(sp.t0, sp.t1);
  }
}

TEST(Ray, OriginInsideAndUnboundedSpans) {
  const Solid s = box({0, 0, 0}, {1, 1, 1});
  RayResult r = cast_one(s, {{0.5, 0.5, 0.5}, {0, 0, 1}});
  ASSERT_EQ(r.spans.size(), 1u);
  EXPECT_EQ(r.spans[0].enter, Span::kNone);  // starts at the origin
  EXPECT_DOUBLE_EQ(r.spans[0].t1, 0.5);
  r = cast_one(complement(s), {{0.5, 0.5, 0.5}, {0, 0, 1}});
  ASSERT_EQ(r.spans.size(), 1u);
  EXPECT_DOUBLE_EQ(r.spans[0].t0, 0.5);
  EXPECT_EQ(r.spans[0].exit, Span::kNone);  // never ends
}

TEST(Ray, BatchSingleAndDepthFirstAgree) {
  const Solid s = unite({make_leaf(make_sphere({0, 0, 0}, 1, 24), "sphere"),
                         box({0.2, -0.5, -0.5}, {1.8, 0.5, 0.5})});
  const Prepared prepared(s);
  const Bvh& bvh = prepared.bvh();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Ray> rays;
  for (int i = 0; i < 500; ++i) rays.push_back({{u(rng), u(rng), -3}, {u(rng), u(rng), 1}});
  const std::vector<RayResult> batch = cast(prepared, rays, CastOptions{64});
  for (size_t i = 0; i < rays.size(); ++i) {
    const RayResult single = cast(bvh, s.tree, s.leaves.size(), rays[i]);
    const RayResult depth = cast_depth_first(bvh, s.tree, s.leaves.size(), rays[i]);
    ASSERT_EQ(single.hits.size(), batch[i].hits.size()) << i;
    ASSERT_EQ(depth.hits.size(), single.hits.size()) << i;
    for (size_t k = 0; k < single.hits.size(); ++k) {
      EXPECT_EQ(single.hits[k].t, batch[i].hits[k].t);
      EXPECT_EQ(single.hits[k].t, depth.hits[k].t);
      EXPECT_EQ(single.hits[k].sign, depth.hits[k].sign);
    }
    ASSERT_EQ(single.spans.size(), depth.spans.size());
    const VisibleHit want = first_visible(single, 0, INFINITY);
    const VisibleHit got = first_visible(bvh, s.tree, s.leaves.size(), rays[i], 0, INFINITY);
    EXPECT_EQ(want.hit, got.hit) << i;
    if (want.hit) {
      EXPECT_EQ(want.t, got.t) << i;
    }
  }
}

}  // namespace
}  // namespace cover
