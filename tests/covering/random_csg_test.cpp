// Seeded random CSG trees (in the spirit of Manifold's fuzz test): the accelerated classifier
// equals the brute-force covering path on random points and on points exactly on faces, edges and
// vertices; vol(A∪B) + vol(A∩B) = vol(A) + vol(B) within the reported error bounds; and scaled
// copies of a scene (by powers of two, so the doubles scale exactly) classify identically; the
// front-to-back first visible point of a ray equals the one from all of cast()'s spans; the
// batch cast() (rays walking the BVH together) and the single-ray cast() give every ray exactly
// the result of the depth-first walk (cast_depth_first).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "cover/covering/bounds.h"
#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/covering/ray.h"
#include "cover/covering/volume.h"
#include "cover/io/mesh_io.h"
#include "cover/io/scene.h"
#include "cover/solid/errors.h"
#include "cover/solid/primitives.h"
#include "cover/solid/transform.h"
#include "helpers.h"

namespace cover {
namespace {

/// A random leaf: a box with grid-aligned corners (many coincident faces between leaves), a
/// sphere, or the knot1 mesh, under a random transform.
Solid random_leaf(std::mt19937_64& rng, const PolygonMesh& knot) {
  std::uniform_int_distribution<int> kind(0, 2), cell(-4, 4);
  std::uniform_real_distribution<double> u(-1, 1);
  PolygonMesh m;
  switch (kind(rng)) {
    case 0: {
      const Vec3 lo{cell(rng) * 0.25, cell(rng) * 0.25, cell(rng) * 0.25};
      m = make_box(lo, lo + Vec3{0.25 + 0.25 * (cell(rng) + 4), 0.5, 0.75});
      break;
    }
    case 1:
      m = make_sphere({u(rng), u(rng), u(rng)}, 0.3 + 0.4 * std::abs(u(rng)), 12);
      break;
    default:
      m = knot;
      apply_transform(Transform::trs(Vec3{0.02, 0.02, 0.02}, {u(rng), u(rng), 1}, 90 * u(rng),
                                     {u(rng), u(rng), u(rng)}),
                      m);
  }
  return make_leaf(std::move(m), "leaf");
}

Solid random_tree(std::mt19937_64& rng, const PolygonMesh& knot, int depth) {
  std::uniform_int_distribution<int> op(0, 4);
  if (depth == 0) return random_leaf(rng, knot);
  const int o = op(rng);
  if (o == 4) return complement(random_tree(rng, knot, depth - 1));
  std::vector<Solid> parts{random_tree(rng, knot, depth - 1), random_tree(rng, knot, depth - 1)};
  if (o == 0 || o == 3) return unite(std::move(parts));
  if (o == 1) return intersect(std::move(parts));
  return subtract(std::move(parts));
}

TEST(RandomCsg, AcceleratedEqualsBruteForce) {
  const PolygonMesh knot = read_mesh(test::cgal_mesh("knot1.off"));
  std::mt19937_64 rng(12345);
  for (int trial = 0; trial < 16; trial += test::kCheckedStride) {
    const Solid s = random_tree(rng, knot, 1 + trial % 3);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    std::uniform_int_distribution<int> grid(-6, 6);
    std::vector<Vec3> pts;
    for (int i = 0; i < 400; ++i) pts.push_back({u(rng), u(rng), u(rng)});
    // Points on the box lattice: exactly on faces, edges and vertices of the box leaves.
    for (int i = 0; i < 300; ++i)
      pts.push_back({grid(rng) * 0.25, grid(rng) * 0.25, grid(rng) * 0.25});
    // Mesh and primitive vertices: exactly on surfaces.
    for (size_t i = 0; i < s.vertices.size(); i += s.vertices.size() / 12 + 1)
      pts.push_back(s.vertices[i]);
    ClassifyOptions many;
    many.grid_min_points = 1;  // exercise the empty-cell grid too
    EXPECT_EQ(classify(s, pts, many), classify_brute_force(s, pts)) << "trial " << trial;
  }
}

TEST(RandomCsg, FrontToBackFirstVisibleEqualsAllHits) {
  const PolygonMesh knot = read_mesh(test::cgal_mesh("knot1.off"));
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> grid(-6, 6), axis(0, 2);
  int compared = 0, caps = 0;  // visible points compared (some trees are empty)
  for (int trial = 0; trial < 24; ++trial) {
    const Solid s = random_tree(rng, knot, 1 + trial % 3);
    const Bvh bvh(s);
    for (int i = 0; i < 600; ++i) {
      Ray r;
      if (i % 3 == 0) {  // axis-aligned through the box lattice: along faces, edges, vertices
        double o[3] = {grid(rng) * 0.25, grid(rng) * 0.25, grid(rng) * 0.25}, d[3] = {0, 0, 0};
        const int k = axis(rng);
        o[k] = -4;
        d[k] = 1;
        r.origin = {o[0], o[1], o[2]};
        r.dir = {d[0], d[1], d[2]};
      } else {  // from far outside (front to back) or from inside the scene (the fallback)
        const double reach = i % 3 == 1 ? 4 : 1;
        r.origin = {reach * u(rng), reach * u(rng), reach * u(rng)};
        if (i % 3 == 1) r.origin = (4 / std::sqrt(dot(r.origin, r.origin))) * r.origin;
        r.dir = Vec3{u(rng), u(rng), u(rng)} - r.origin;
      }
      const RayResult all = cast(bvh, s.tree, s.leaves.size(), r);
      // Windows: the whole ray, one starting inside the scene (section caps), one ending there.
      const double a = 0.5 + std::abs(u(rng)), b = a + std::abs(u(rng));
      constexpr double kInf = std::numeric_limits<double>::infinity();
      for (const auto& [lo, hi] :
           {std::pair{0.0, kInf}, std::pair{a, kInf}, std::pair{0.0, a}, std::pair{a, b}}) {
        const VisibleHit want = first_visible(all, lo, hi);
        const VisibleHit got = first_visible(bvh, s.tree, s.leaves.size(), r, lo, hi);
        ASSERT_EQ(got.hit, want.hit) << "trial " << trial << " ray " << i;
        if (!want.hit) continue;
        ++compared;
        caps += want.cap;
        EXPECT_EQ(got.cap, want.cap) << "trial " << trial << " ray " << i;
        EXPECT_EQ(got.t, want.t) << "trial " << trial << " ray " << i;
        if (!want.cap) {
          EXPECT_EQ(got.enter.tri, want.enter.tri) << "trial " << trial << " ray " << i;
          EXPECT_EQ(got.enter.sign, want.enter.sign) << "trial " << trial << " ray " << i;
        }
      }
    }
  }
  EXPECT_GT(compared, 10000);
  EXPECT_GT(caps, 1000);
}

TEST(RandomCsg, BatchCastEqualsSingleRays) {
  const PolygonMesh knot = read_mesh(test::cgal_mesh("knot1.off"));
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> grid(-6, 6), axis(0, 2);
  size_t hits = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const Solid s = random_tree(rng, knot, 1 + trial % 3);
    const Prepared prepared(s);
    const Bvh& bvh = prepared.bvh();
    std::vector<Ray> rays(700);
    for (size_t i = 0; i < rays.size(); ++i) {
      Ray& r = rays[i];
      if (i % 3 == 0) {  // axis-aligned through the box lattice: along faces, edges, vertices
        double o[3] = {grid(rng) * 0.25, grid(rng) * 0.25, grid(rng) * 0.25}, d[3] = {0, 0, 0};
        o[axis(rng)] = -4;
        d[i % 2 ? 0 : 2] = i % 4 ? 1 : -1;
        r.origin = {o[0], o[1], o[2]};
        r.dir = {d[0], d[1], d[2]};
      } else {  // from far outside, or from inside the scene
        const double reach = i % 3 == 1 ? 4 : 1;
        r.origin = {reach * u(rng), reach * u(rng), reach * u(rng)};
        r.dir = Vec3{u(rng), u(rng), u(rng)} - r.origin;
      }
    }
    // The depth-first walk is the reference; the single-ray cast() (a batch of one) and the
    // batches at several grains must give every ray exactly its result.
    std::vector<RayResult> want(rays.size()), single(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      want[i] = cast_depth_first(bvh, s.tree, s.leaves.size(), rays[i]);
      single[i] = cast(bvh, s.tree, s.leaves.size(), rays[i]);
    }
    for (const size_t grain : {size_t{0}, size_t{1}, size_t{97}, size_t{256}}) {
      const std::vector<RayResult> batch =
          grain == 0 ? single : cast(prepared, rays, CastOptions{grain});
      ASSERT_EQ(batch.size(), rays.size());
      for (size_t i = 0; i < rays.size(); ++i) {
        const RayResult& one = want[i];
        const RayResult& got = batch[i];
        ASSERT_EQ(got.hits.size(), one.hits.size()) << "trial " << trial << " ray " << i;
        for (size_t h = 0; h < one.hits.size(); ++h) {
          EXPECT_EQ(got.hits[h].t, one.hits[h].t) << "trial " << trial << " ray " << i;
          EXPECT_EQ(got.hits[h].tri, one.hits[h].tri) << "trial " << trial << " ray " << i;
          EXPECT_EQ(got.hits[h].leaf, one.hits[h].leaf);
          EXPECT_EQ(got.hits[h].face, one.hits[h].face);
          EXPECT_EQ(got.hits[h].sign, one.hits[h].sign);
        }
        ASSERT_EQ(got.spans.size(), one.spans.size()) << "trial " << trial << " ray " << i;
        for (size_t k = 0; k < one.spans.size(); ++k) {
          EXPECT_EQ(got.spans[k].t0, one.spans[k].t0);
          EXPECT_EQ(got.spans[k].t1, one.spans[k].t1);
          EXPECT_EQ(got.spans[k].enter, one.spans[k].enter);
          EXPECT_EQ(got.spans[k].exit, one.spans[k].exit);
        }
        hits += one.hits.size();
      }
    }
  }
  EXPECT_GT(hits, 10000u);
}

TEST(RandomCsg, UnionIntersectionVolumeIdentity) {
  const PolygonMesh knot = read_mesh(test::cgal_mesh("knot1.off"));
  std::mt19937_64 rng(777);
  int compared = 0;
  for (int trial = 0; trial < 4; ++trial) {
    Solid a = random_tree(rng, knot, 1), b = random_tree(rng, knot, 1);
    if (!is_bounded(a) || !is_bounded(b)) continue;  // unbounded operands have no volume
    const VolumeResult va = volume(a), vb = volume(b), vu = volume(unite({a, b})),
                       vi = volume(intersect({a, b}));
    const double slack = va.error_bound + vb.error_bound + vu.error_bound + vi.error_bound +
                         1e-9 * (va.volume + vb.volume);
    EXPECT_NEAR(vu.volume + vi.volume, va.volume + vb.volume, slack) << "trial " << trial;
    ++compared;
  }
  EXPECT_GT(compared, 0);  // the seed must give bounded operands, or the test tests nothing
}

TEST(RandomCsg, ScaledCopiesClassifyIdentically) {
  const PolygonMesh knot = read_mesh(test::cgal_mesh("knot1.off"));
  std::mt19937_64 rng(4242);
  const Solid s = random_tree(rng, knot, 2);
  std::uniform_int_distribution<int> grid(-6, 6);
  std::vector<Vec3> pts;
  for (int i = 0; i < 1500; ++i)
    pts.push_back({grid(rng) * 0.25, grid(rng) * 0.25, grid(rng) * 0.25});
  const auto reference = classify(s, pts);
  for (double scale : {0x1p-30, 0x1p30}) {  // 2^±30: every coordinate scales exactly
    Solid t = s;
    for (Vec3& v : t.vertices) v = scale * v;
    for (Leaf& l : t.leaves) l.bbox = {scale * l.bbox.min, scale * l.bbox.max};
    std::vector<Vec3> q = pts;
    for (Vec3& p : q) p = scale * p;
    EXPECT_EQ(classify(t, q), reference) << scale;
  }
}

}  // namespace
}  // namespace cover
