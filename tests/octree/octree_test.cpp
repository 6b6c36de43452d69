// Octrees (octree/octree.h, io/octree_io.h): every full / empty leaf checked against the
// brute-force classification, partial leaves crossed by a surface (CGAL's exact overlap test as
// the oracle), volume bounds, occupancy re-derived point by point, thread independence, and the
// .htg / .bt / .json files read back independently (XML scan, liboctomap, nlohmann_json).
#include "cover/octree/octree.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Gmpq.h>
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/covering/volume.h"
#include "cover/io/octree_io.h"
#include "cover/io/scene.h"
#include "cover/octree/detail/box_overlap.h"
#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"
#include "cover/solid/predicates.h"
#include "cover/solid/primitives.h"
#include "helpers.h"

namespace cover {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

Solid box_solid(Vec3 lo, Vec3 hi) { return make_leaf(make_box(lo, hi), "box"); }

VoxelBounds cube(Vec3 min, double size) {
  VoxelBounds b;
  b.min = min;
  b.size = size;
  return b;
}

Octree build(const Solid& s, const VoxelBounds& b, int depth, int samples = 4) {
  OctreeOptions o;
  o.depth = depth;
  o.samples = samples;
  return build_octree(s, b, o);
}

/// The exact closed box of a node: its faces are grid planes bounds.min + m·h (octree.h), m the
/// integer corner scaled to the finest level (computed here, independently of Octree::box).
Bbox cell_box(const Octree& t, const Octree::Node& n) {
  const double h = t.cell_size(t.depth);
  const long long span = 1LL << (t.depth - n.depth);
  Bbox b;
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const long long m = static_cast<long long>(n.cell[a]) * span;
    lo[a] = t.bounds.min[a] + static_cast<double>(m) * h;
    hi[a] = t.bounds.min[a] + static_cast<double>(m + span) * h;
  }
  b.min = {lo[0], lo[1], lo[2]};
  b.max = {hi[0], hi[1], hi[2]};
  return b;
}

bool cgal_meets(const Bvh::Tri& t, const Bbox& b) {
  const K::Triangle_3 tri({t.a.x, t.a.y, t.a.z}, {t.b.x, t.b.y, t.b.z}, {t.c.x, t.c.y, t.c.z});
  const K::Iso_cuboid_3 box({b.min.x, b.min.y, b.min.z}, {b.max.x, b.max.y, b.max.z});
  return CGAL::do_intersect(tri, box);
}

std::vector<size_t> leaves_of(const Octree& t, CellState s) {
  std::vector<size_t> out;
  for (size_t i = 0; i < t.nodes.size(); ++i)
    if (t.nodes[i].first_child == 0 && t.nodes[i].state == s) out.push_back(i);
  return out;
}

/// At most `count` of `ids`, chosen with a fixed seed (all when there are few).
std::vector<size_t> sample(std::vector<size_t> ids, size_t count, std::mt19937_64& rng) {
  if (ids.size() <= count) return ids;
  std::shuffle(ids.begin(), ids.end(), rng);
  ids.resize(count);
  return ids;
}

/// Structure and correctness of every sampled leaf: full / empty cells hold only inside / outside
/// random points (brute-force classification), partial cells are met by some triangle (CGAL),
/// occupancies lie in [0, 1] and inner nodes have 8 children one level down.
void check_leaves(const Solid& s, const Octree& t, size_t max_cells = 2000) {
  ASSERT_FALSE(t.nodes.empty());
  for (size_t i = 0; i < t.nodes.size(); ++i) {
    const Octree::Node& n = t.nodes[i];
    EXPECT_GE(n.occupancy, 0.0f);
    EXPECT_LE(n.occupancy, 1.0f);
    EXPECT_LE(n.depth, t.depth);
    if (n.first_child != 0) {
      EXPECT_EQ(n.state, CellState::kPartial);
      ASSERT_LE(n.first_child + 8u, t.nodes.size());
      EXPECT_GT(n.first_child, i);
      for (uint32_t c = 0; c < 8; ++c) EXPECT_EQ(t.nodes[n.first_child + c].depth, n.depth + 1);
    } else {
      if (n.state == CellState::kFull) {
        EXPECT_EQ(n.occupancy, 1.0f);
      } else if (n.state == CellState::kEmpty) {
        EXPECT_EQ(n.occupancy, 0.0f);
      } else {
        EXPECT_EQ(n.depth, t.depth);
      }
    }
  }
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> unit(0.001, 0.999);
  std::vector<Vec3> points;
  std::vector<CellState> expected;
  for (CellState state : {CellState::kFull, CellState::kEmpty})
    for (size_t id : sample(leaves_of(t, state), max_cells, rng)) {
      const Bbox b = cell_box(t, t.nodes[id]);
      for (int k = 0; k < 3; ++k) {
        points.push_back({b.min.x + unit(rng) * (b.max.x - b.min.x),
                          b.min.y + unit(rng) * (b.max.y - b.min.y),
                          b.min.z + unit(rng) * (b.max.z - b.min.z)});
        expected.push_back(state);
      }
    }
  const std::vector<PointClass> got = classify_brute_force(s, points);
  for (size_t i = 0; i < points.size(); ++i)
    EXPECT_EQ(got[i], expected[i] == CellState::kFull ? PointClass::kInside : PointClass::kOutside)
        << points[i].x << " " << points[i].y << " " << points[i].z;
  const Bvh bvh(s);
  for (size_t id : sample(leaves_of(t, CellState::kPartial), max_cells / 10, rng)) {
    const Bbox b = cell_box(t, t.nodes[id]);
    bool crossed = false;
    for (uint32_t i = 0; i < bvh.triangle_count(); ++i)
      crossed = crossed || cgal_meets(bvh.triangle(i), b);
    EXPECT_TRUE(crossed) << "partial node " << id;
  }
}

/// Σ full-cell volumes ≤ exact ≤ Σ (full + partial) cell volumes.
void expect_volume_bounds(const Octree& t, double exact) {
  double full = 0, partial = 0;
  for (const Octree::Node& n : t.nodes) {
    if (n.first_child != 0) continue;
    const double v = std::pow(t.cell_size(n.depth), 3);
    if (n.state == CellState::kFull) full += v;
    if (n.state == CellState::kPartial) partial += v;
  }
  EXPECT_LE(full, exact * (1 + 1e-9));
  EXPECT_GE(full + partial, exact * (1 - 1e-9));
  EXPECT_GT(partial, 0);
}

/// Partial occupancies equal the share of the samples³ sub-grid centres classified inside (the
/// surface counting ½), every sub-point classified on its own by the brute-force path.
void expect_occupancy_by_points(const Solid& s, const Octree& t, int samples, size_t cells) {
  std::mt19937_64 rng(777);
  for (size_t id : sample(leaves_of(t, CellState::kPartial), cells, rng)) {
    const Bbox b = cell_box(t, t.nodes[id]);
    std::vector<Vec3> subs;
    for (int k = 0; k < samples; ++k)
      for (int j = 0; j < samples; ++j)
        for (int i = 0; i < samples; ++i)
          subs.push_back({b.min.x + (i + 0.5) * ((b.max.x - b.min.x) / samples),
                          b.min.y + (j + 0.5) * ((b.max.y - b.min.y) / samples),
                          b.min.z + (k + 0.5) * ((b.max.z - b.min.z) / samples)});
    int halves = 0;
    for (PointClass c : classify_brute_force(s, subs))
      halves += c == PointClass::kInside ? 2 : (c == PointClass::kOutside ? 0 : 1);
    EXPECT_EQ(t.nodes[id].occupancy,
              static_cast<float>(halves / (2.0 * samples * samples * samples)))
        << "node " << id;
  }
}

Solid elephant() { return load_input(test::cgal_mesh("elephant.off")).solid; }

VoxelBounds default_bounds(const Solid& s, int depth) {
  return default_voxel_bounds(s.bbox(), 1 << std::max(depth, 2));
}

TEST(BoxOverlap, AgreesWithCgalOnTouchingAndRandomCases) {
  const Bbox b = [] {
    Bbox x;
    x.add(Vec3{0, 0, 0});
    x.add(Vec3{1, 1, 1});
    return x;
  }();
  const auto meets = [&](Vec3 a, Vec3 c, Vec3 d) {
    const bool got = detail::triangle_meets_box(a, c, d, b);
    EXPECT_EQ(got, cgal_meets({a, c, d}, b));
    return got;
  };
  EXPECT_TRUE(meets({1, 0, 0}, {2, 0, 0}, {1, 1, 0}));      // an edge on a box face
  EXPECT_TRUE(meets({1, 1, 1}, {2, 1, 1}, {1, 2, 1}));      // a vertex on a corner
  EXPECT_TRUE(meets({1, -1, -1}, {1, 3, -1}, {1, -1, 3}));  // lying in a face plane
  EXPECT_FALSE(meets({std::nextafter(1.0, 2.0), -1, -1}, {1.5, 3, -1}, {1.5, -1, 3}));
  EXPECT_TRUE(meets({-1, 0.5, 2}, {2, 0.5, 2}, {0.5, 0.5, -1}));  // through the middle
  EXPECT_TRUE(meets({0, 2, 0}, {2, 0, 0}, {2, 2, 5}));  // touches the corner (1, 1, 0) only
  EXPECT_FALSE(meets({0.1, 2.1, 0}, {2.1, 0.1, 0}, {2.1, 2.1, 1}));  // just misses it
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.6, 1.6);
  std::uniform_int_distribution<int> grid(-2, 6);
  for (int i = 0; i < 20000; ++i) {
    // Half the vertices on a quarter grid: faces, edges and corners get touched exactly.
    const auto v = [&] {
      return i % 2 ? Vec3{u(rng), u(rng), u(rng)}
                   : Vec3{grid(rng) / 4.0, grid(rng) / 4.0, grid(rng) / 4.0};
    };
    const Vec3 a = v(), c = v(), d = v();
    if (orient2d(a, c, d, 0) == 0 && orient2d(a, c, d, 1) == 0 && orient2d(a, c, d, 2) == 0)
      continue;  // collinear: never a covering triangle
    meets(a, c, d);
  }
}

TEST(BoxOverlap, CrossesIsTheOpenBox) {
  // Oracle: with vertices on a quarter grid, a triangle that enters the open unit box has points
  // there at a distance from its faces far above 2^-20 (small-denominator fractions), so it meets
  // the closed box shrunk by 2^-20 (CGAL, exact on these doubles). Random triangles: crossing
  // implies meeting the box, and meeting the shrunk box implies crossing.
  Bbox b, shrunk;
  b.add(Vec3{0, 0, 0});
  b.add(Vec3{1, 1, 1});
  const double e = std::ldexp(1.0, -20);
  shrunk.add(Vec3{e, e, e});
  shrunk.add(Vec3{1 - e, 1 - e, 1 - e});
  const auto crosses = [&](Vec3 a, Vec3 c, Vec3 d) {
    return detail::triangle_crosses_box(a, c, d, b);
  };
  EXPECT_FALSE(crosses({1, 0, 0}, {2, 0, 0}, {1, 1, 0}));               // an edge on a box face
  EXPECT_FALSE(crosses({1, -1, -1}, {1, 3, -1}, {1, -1, 3}));           // lying in a face plane
  EXPECT_FALSE(crosses({0, 2, 0}, {2, 0, 0}, {2, 2, 5}));               // touches a corner only
  EXPECT_FALSE(crosses({-1, 0.5, 1}, {2, 0.5, 1}, {0.5, 2, 1}));        // in the top face plane
  EXPECT_TRUE(crosses({-1, 0.5, 2}, {2, 0.5, 2}, {0.5, 0.5, -1}));      // through the middle
  EXPECT_TRUE(crosses({0.5, 0.5, 0.5}, {2, 0.5, 0.5}, {0.5, 2, 0.5}));  // a vertex inside
  EXPECT_TRUE(crosses({1, 0, 0}, {0, 1, 0}, {0, 0, 1}));  // vertices on corners, face inside
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-0.6, 1.6);
  std::uniform_int_distribution<int> grid(-2, 6);
  for (int i = 0; i < 20000; ++i) {
    const bool on_grid = i % 2 == 0;
    const auto v = [&] {
      return on_grid ? Vec3{grid(rng) / 4.0, grid(rng) / 4.0, grid(rng) / 4.0}
                     : Vec3{u(rng), u(rng), u(rng)};
    };
    const Vec3 a = v(), c = v(), d = v();
    if (orient2d(a, c, d, 0) == 0 && orient2d(a, c, d, 1) == 0 && orient2d(a, c, d, 2) == 0)
      continue;  // collinear: never a covering triangle
    const bool got = crosses(a, c, d), inner = cgal_meets({a, c, d}, shrunk);
    if (on_grid) {
      EXPECT_EQ(got, inner) << i;
    } else {
      EXPECT_TRUE(!got || cgal_meets({a, c, d}, b)) << i;
      EXPECT_TRUE(!inner || got) << i;
    }
  }
}

TEST(BoxOverlap, PointBoxesAgreeWithCgal) {
  // A box of zero size (Builder::centre_on_surface asks whether a triangle passes through a
  // point): on an edge's line the edge filter has no magnitude and orient2d decides every sign
  // (a wrong sign from an unset cache entry shows under valgrind even where the answer holds).
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> grid(-2, 6);
  const auto v = [&] { return Vec3{grid(rng) / 4.0, grid(rng) / 4.0, grid(rng) / 4.0}; };
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = v(), c = v(), d = v(), p = i % 2 ? v() : a + 0.5 * (c - a);
    if (orient2d(a, c, d, 0) == 0 && orient2d(a, c, d, 1) == 0 && orient2d(a, c, d, 2) == 0)
      continue;  // collinear: never a covering triangle
    Bbox b;
    b.add(p);
    EXPECT_EQ(detail::triangle_meets_box(a, c, d, b), cgal_meets({a, c, d}, b)) << i;
  }
}

TEST(BoxOverlap, CrossedOctantsIsCrossesPerOctant) {
  // OctantOverlap::crossed_octants (all octants at once, as the octree's lists use it) against
  // crosses(o) octant by octant, on quarter-grid triangles and lattices (touching cases) and on
  // random ones, for every subset of wanted octants drawn at random; at every vector level
  // this CPU has (the edge axes' AVX2 path and the scalar one).
  const detail::Simd best = detail::best_simd();
  for (int level = 0; level <= static_cast<int>(best); ++level) {
    detail::use_simd(static_cast<detail::Simd>(level));
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> u(-0.6, 1.6);
    std::uniform_int_distribution<int> grid(-2, 6), step(1, 3), mask(0, 255);
    for (int i = 0; i < 20000; ++i) {
      const bool on_grid = i % 2 == 0;
      const auto x = [&] { return on_grid ? grid(rng) / 4.0 : u(rng); };
      const Vec3 a{x(), x(), x()}, c{x(), x(), x()}, d{x(), x(), x()};
      if (orient2d(a, c, d, 0) == 0 && orient2d(a, c, d, 1) == 0 && orient2d(a, c, d, 2) == 0)
        continue;  // collinear: never a covering triangle
      double planes[3][3];
      for (auto& axis : planes) {
        axis[0] = grid(rng) / 8.0;
        axis[1] = axis[0] + step(rng) / 8.0;
        axis[2] = axis[1] + step(rng) / 8.0;
      }
      if (i % 8 == 3)  // the split point an ulp from vertex a: edge signs the filter cannot decide
        for (int k = 0; k < 3; ++k) {
          const double s = step(rng) / 8.0;
          planes[k][1] = std::nextafter(a[k], (i / 8 + k) % 2 ? 2.0 : -2.0);
          planes[k][0] = planes[k][1] - s;
          planes[k][2] = planes[k][1] + s;
        }
      detail::OctantOverlap one(a, c, d, planes);
      const uint8_t wanted = static_cast<uint8_t>(i % 4 == 1 ? mask(rng) : 0xFF);
      uint8_t expected = 0;
      for (int o = 0; o < 8; ++o)
        if ((wanted >> o & 1) && one.crosses(o)) expected |= static_cast<uint8_t>(1 << o);
      detail::OctantOverlap all(a, c, d, planes);
      EXPECT_EQ(all.crossed_octants(wanted), expected) << level << " " << i;
    }
  }
  detail::use_simd(best);
}

TEST(BoxOverlap, PlaneSideIsExact) {
  Bbox b;
  b.add(Vec3{-1, -1, -1});
  b.add(Vec3{1, 1, 1});
  const Vec3 a{-0.3, 0.1, 0.7}, c{0.9, -0.2, 0.1}, d{0.2, 0.8, -0.6};
  const detail::PlaneSide side(a, c, d, b);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 20000; ++i) {
    Vec3 p{u(rng), u(rng), u(rng)};
    if (i % 2) {  // on or next to the plane: the exact path decides
      const double s = u(rng), r = u(rng) * (1 - std::abs(s));
      p = a + s * (c - a) + r * (d - a);
    }
    if (!b.contains(p)) continue;
    EXPECT_EQ(side.sign(p), orient3d(a, c, d, p));
  }
}

TEST(BoxOverlap, PlaneMasksAreSignAtEverySimdLevel) {
  // grid_masks (4³ points) and lattice_masks (3³) against sign() point by point, at every
  // vector level this CPU has: planes through quarter-grid points (many points exactly on
  // them: the exact fallback) and random ones.
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> grid(-4, 4);
  const detail::Simd best = detail::best_simd();
  for (int level = 0; level <= static_cast<int>(best); ++level) {
    detail::use_simd(static_cast<detail::Simd>(level));
    ASSERT_EQ(detail::simd(), static_cast<detail::Simd>(level));
    for (int i = 0; i < 4000; ++i) {
      const bool on_grid = i % 2 == 0;
      const auto x = [&] { return on_grid ? grid(rng) / 4.0 : u(rng); };
      const Vec3 a{x(), x(), x()}, c{x(), x(), x()}, d{x(), x(), x()};
      double xs[3][4], planes[3][3];
      for (int k = 0; k < 3; ++k) {
        const double lo = grid(rng) / 8.0, step = (1 + i % 3) / 8.0;
        for (int j = 0; j < 4; ++j) xs[k][j] = lo + (j + 0.5) * step / 2;
        for (int j = 0; j < 3; ++j) planes[k][j] = lo + j * step;
      }
      Bbox box;
      box.min = {planes[0][0], planes[1][0], planes[2][0]};
      box.max = {planes[0][2], planes[1][2], planes[2][2]};
      const detail::PlaneSide side(a, c, d, box);
      uint64_t pos = 0, neg = 0;
      side.grid_masks(xs[0], xs[1], xs[2], 4, pos, neg);
      for (int p = 0; p < 64; ++p) {
        const int s = side.sign({xs[0][p & 3], xs[1][(p >> 2) & 3], xs[2][p >> 4]});
        ASSERT_EQ(int(pos >> p & 1) - int(neg >> p & 1), s) << level << " " << i << " " << p;
      }
      // cell_masks over a sibling set: cell c takes the half (c >> a) & 1 of axis a, each half
      // 4 sub-points (both halves inside `box`).
      double halves[3][2][4];
      for (int k = 0; k < 3; ++k)
        for (int h = 0; h < 2; ++h)
          for (int j = 0; j < 4; ++j)
            halves[k][h][j] = planes[k][h] + (j + 0.5) * (planes[k][h + 1] - planes[k][h]) / 4;
      const double* const hx[2] = {halves[0][0], halves[0][1]};
      const double* const hy[2] = {halves[1][0], halves[1][1]};
      const double* const hz[2] = {halves[2][0], halves[2][1]};
      const auto cells = static_cast<uint8_t>(i % 255 + 1);
      uint64_t cpos[8] = {}, cneg[8] = {};
      side.cell_masks(hx, hy, hz, 4, cells, cpos, cneg);
      for (int cell = 0; cell < 8; ++cell) {
        if (!(cells >> cell & 1)) continue;
        for (int p = 0; p < 64; ++p) {
          const int s = side.sign(
              {hx[cell & 1][p & 3], hy[(cell >> 1) & 1][(p >> 2) & 3], hz[cell >> 2][p >> 4]});
          ASSERT_EQ(int(cpos[cell] >> p & 1) - int(cneg[cell] >> p & 1), s)
              << level << " " << i << " " << cell << " " << p;
        }
      }
      uint32_t lpos = 0, lneg = 0;
      side.lattice_masks(planes, lpos, lneg);
      EXPECT_EQ((lpos | lneg) >> 27, 0u);
      for (int p = 0; p < 27; ++p) {
        const int s = side.sign({planes[0][p % 3], planes[1][p / 3 % 3], planes[2][p / 9]});
        ASSERT_EQ(int(lpos >> p & 1) - int(lneg >> p & 1), s) << level << " " << i << " " << p;
      }
    }
  }
  detail::use_simd(best);
}

TEST(BoxOverlap, EdgeOrientationsAreOrient3dAtEverySimdLevel) {
  // Quarter-grid points (many coplanar quadruples: the exact path) and random ones.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> grid(-2, 2);
  const detail::Simd best = detail::best_simd();
  for (int level = 0; level <= static_cast<int>(best); ++level) {
    detail::use_simd(static_cast<detail::Simd>(level));
    int zeros = 0;
    for (int i = 0; i < 20000; ++i) {
      const bool on_grid = i % 2 == 0;
      const auto x = [&] { return on_grid ? grid(rng) / 4.0 : u(rng); };
      const Vec3 r{x(), x(), x()}, a{x(), x(), x()}, b{x(), x(), x()}, c{x(), x(), x()};
      Vec3 q{x(), x(), x()};
      if (i % 4 == 1)  // q on the plane of r, a, b up to rounding: the filter cannot decide
        q = a + u(rng) * (b - a) + u(rng) * (r - a);
      int o[3];
      detail::edge_orientations(r, q, a, b, c, o);
      ASSERT_EQ(o[0], orient3d(r, q, a, b)) << level << " " << i;
      ASSERT_EQ(o[1], orient3d(r, q, b, c)) << level << " " << i;
      ASSERT_EQ(o[2], orient3d(r, q, c, a)) << level << " " << i;
      zeros += o[0] == 0;
    }
    EXPECT_GT(zeros, 100);
  }
  detail::use_simd(best);
}

TEST(Octree, BoxSphereElephantAndDifferenceAreExactAndConservative) {
  const Solid box = box_solid({0.1, 0.2, 0.3}, {0.8, 0.7, 0.9});
  const Octree tb = build(box, cube({0, 0, 0}, 1), 5);
  check_leaves(box, tb);
  expect_volume_bounds(tb, 0.7 * 0.5 * 0.6);
  expect_occupancy_by_points(box, tb, 4, 40);

  const Solid sphere = make_leaf(make_sphere({0.1, -0.2, 0.3}, 0.75, 24), "sphere");
  const Octree ts = build(sphere, default_bounds(sphere, 5), 5, 3);
  check_leaves(sphere, ts);
  expect_volume_bounds(ts, covering_volume(sphere));
  expect_occupancy_by_points(sphere, ts, 3, 40);

  const Solid e = elephant();
  const Octree te = build(e, default_bounds(e, 6), 6);
  check_leaves(e, te);
  expect_volume_bounds(te, covering_volume(e));
  expect_occupancy_by_points(e, te, 4, 30);

  // A notch cut through a box (analytic volume) and a sphere carved out of a box.
  const Solid notch =
      subtract({box_solid({0, 0, 0}, {1, 1, 1}), box_solid({0.5, 0.3, -0.5}, {1.5, 0.7, 1.5})});
  const Octree tn = build(notch, cube({-0.1, -0.1, -0.1}, 1.3), 5);
  check_leaves(notch, tn);
  expect_volume_bounds(tn, 1 - 0.5 * 0.4);
  const Solid ball = make_leaf(make_sphere({0.1, 0, 0}, 0.6, 16), "sphere");
  const Solid hollow = subtract({box_solid({-1, -1, -1}, {1, 1, 1}), ball});
  const Octree th = build(hollow, default_bounds(hollow, 5), 5);
  check_leaves(hollow, th);
  expect_volume_bounds(th, 8 - covering_volume(ball));
  expect_occupancy_by_points(hollow, th, 4, 30);
}

/// Two meshes concatenated into one PolygonMesh (one leaf: windings up to 2 where they overlap).
PolygonMesh concatenate(const PolygonMesh& a, const PolygonMesh& b) {
  PolygonMesh m = a;
  const uint32_t base = static_cast<uint32_t>(m.vertices.size());
  for (const Vec3& v : b.vertices) m.vertices.push_back(v);
  for (size_t f = 0; f < b.face_count(); ++f) {
    for (uint32_t v : b.face(f)) m.face_vertices.push_back(base + v);
    m.face_start.push_back(static_cast<uint32_t>(m.face_vertices.size()));
  }
  return m;
}

TEST(Octree, EveryPartialOccupancyMatchesItsPoints) {
  // The last level classifies one reference per sibling set and derives the other side classes
  // from the segment's signed crossings (octree.cpp, sibling_masks): every partial cell checked,
  // where the winding's sign matters (one leaf of two overlapping spheres: inside the overlap the
  // winding is 2, entering it from one sphere adds 1) and where segments pass through edges and
  // points lie on planes (box faces at multiples of h/8, where the sub-points sit at the odd
  // multiples; in union, difference, intersection and complement).
  const Solid spheres = make_leaf(
      concatenate(make_sphere({0, 0, 0}, 0.6, 12), make_sphere({0.35, 0.1, 0.05}, 0.5, 10)),
      "spheres");
  const Octree ts = build(spheres, cube({-0.8, -0.8, -0.8}, 1.8), 3);
  check_leaves(spheres, ts);
  expect_occupancy_by_points(spheres, ts, 4, SIZE_MAX);
  for (const Octree::Node& n : ts.nodes) {  // the nodes' integer corners give their exact boxes
    const Bbox a = ts.box(n), b = cell_box(ts, n);
    ASSERT_TRUE(a.min == b.min && a.max == b.max && ts.min(n) == b.min);
  }

  std::mt19937_64 rng(2026);
  const double h = 1.0 / 8;  // cells of depth 3 over the unit cube
  std::uniform_int_distribution<int> step(1, 63);
  const auto snapped_box = [&] {
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      int i = step(rng), j = step(rng);
      if (i == j) ++j;
      (a == 0 ? lo.x : a == 1 ? lo.y : lo.z) = std::min(i, j) * h / 8;
      (a == 0 ? hi.x : a == 1 ? hi.y : hi.z) = std::max(i, j) * h / 8;
    }
    return box_solid(lo, hi);
  };
  for (int round = 0; round < 4; ++round) {
    const Solid s = subtract({unite({snapped_box(), snapped_box(), snapped_box()}),
                              intersect({snapped_box(), complement(snapped_box())})});
    const Octree t = build(s, cube({0, 0, 0}, 1), 3);
    check_leaves(s, t);
    expect_occupancy_by_points(s, t, 4, SIZE_MAX);
  }
  // Octahedra centred on sub-points, their vertices h/8-snapped: their edges run along the
  // sub-grid's diagonals, so segments between sub-points (within a sibling set, and from one
  // set's reference to another's across their grandparent) pass through edges and vertices.
  const double h4 = h / 2;  // depth 4: more sibling sets share a grandparent
  std::uniform_int_distribution<int> centre(4, 58), radius(3, 24);
  const auto octahedron = [&] {
    Vec3 c;
    for (int a = 0; a < 3; ++a)
      (a == 0 ? c.x : a == 1 ? c.y : c.z) = (2 * centre(rng) + 1) * h4 / 8;
    const double r = radius(rng) * h4 / 8;
    PolygonMesh m;
    m.vertices = {c + Vec3{r, 0, 0}, c - Vec3{r, 0, 0}, c + Vec3{0, r, 0},
                  c - Vec3{0, r, 0}, c + Vec3{0, 0, r}, c - Vec3{0, 0, r}};
    for (uint32_t z : {4u, 5u})
      for (uint32_t x : {0u, 1u})
        for (uint32_t y : {2u, 3u}) {
          // Counter-clockwise seen from outside: (x, y, z) positive when the signs agree.
          const bool flip = ((x == 1) != (y == 3)) != (z == 5);
          for (uint32_t v :
               flip ? std::array<uint32_t, 3>{x, z, y} : std::array<uint32_t, 3>{x, y, z})
            m.face_vertices.push_back(v);
          m.face_start.push_back(static_cast<uint32_t>(m.face_vertices.size()));
        }
    return make_leaf(m, "octahedron");
  };
  for (int round = 0; round < 4; ++round) {
    const Solid s = subtract({unite({octahedron(), octahedron(), snapped_box()}), octahedron()});
    const Octree t = build(s, cube({0, 0, 0}, 1), 4);
    check_leaves(s, t);
    expect_occupancy_by_points(s, t, 4, SIZE_MAX);
  }
}

TEST(Octree, MoreThan64SubPointsPerCellGroupWithoutMasks) {
  // 5³ sub-points do not fit one 64-bit mask per cell: the last level groups them by side
  // vectors instead (octree.cpp, sibling_representatives); the same exact occupancies.
  const Solid sphere = make_leaf(make_sphere({0.1, -0.2, 0.3}, 0.75, 24), "sphere");
  const Octree t = build(sphere, default_bounds(sphere, 4), 4, 5);
  check_leaves(sphere, t);
  expect_occupancy_by_points(sphere, t, 5, 40);
}

TEST(Octree, GridAlignedBoxHasNoPartialCells) {
  // Faces on grid planes only touch the cells on either side (their boundaries), so no cell is
  // crossed below the box's own level: every leaf is full or empty and the full ones tile it.
  const Solid box = box_solid({0.25, 0.25, 0.5}, {0.75, 0.625, 0.875});
  const Octree t = build(box, cube({0, 0, 0}, 1), 4);
  check_leaves(box, t, 1000);
  EXPECT_EQ(t.leaf_counts()[static_cast<size_t>(CellState::kPartial)], 0u);
  double full = 0;
  for (const Octree::Node& n : t.nodes)
    if (n.first_child == 0 && n.state == CellState::kFull)
      full += std::pow(t.cell_size(n.depth), 3);
  EXPECT_DOUBLE_EQ(full, 0.5 * 0.375 * 0.375);
  // The box's corner at the root's centre: the 8 uncrossed children must not share one
  // classification (the one full child is told apart from the 7 empty ones).
  const Solid octant = box_solid({0.5, 0.5, 0.5}, {1, 1, 1});
  const Octree o = build(octant, cube({0, 0, 0}, 1), 3);
  check_leaves(octant, o);
  ASSERT_EQ(o.nodes.size(), 9u);
  EXPECT_EQ(o.leaf_counts(), (std::array<uint64_t, 3>{7, 1, 0}));
  EXPECT_EQ(o.nodes[8].state, CellState::kFull);
}

TEST(Octree, UncrossedRootAndDepthZero) {
  const Solid box = box_solid({0, 0, 0}, {4, 4, 4});
  const Octree inside = build(box, cube({1, 1, 1}, 1), 5);
  ASSERT_EQ(inside.nodes.size(), 1u);
  EXPECT_EQ(inside.nodes[0].state, CellState::kFull);
  const Octree outside = build(box, cube({5, 1, 1}, 1), 5);
  ASSERT_EQ(outside.nodes.size(), 1u);
  EXPECT_EQ(outside.nodes[0].state, CellState::kEmpty);
  EXPECT_EQ(outside.leaf_counts(), (std::array<uint64_t, 3>{1, 0, 0}));
  const Octree root = build(box, cube({3, 3, 3}, 2), 0, 2);  // one eighth of the cube inside
  ASSERT_EQ(root.nodes.size(), 1u);
  EXPECT_EQ(root.nodes[0].state, CellState::kPartial);
  EXPECT_EQ(root.nodes[0].occupancy, 0.125f);
}

TEST(Octree, InvalidOptionsThrow) {
  const Solid box = box_solid({0, 0, 0}, {1, 1, 1});
  EXPECT_THROW(build(box, cube({0, 0, 0}, 1), 17), InputError);
  EXPECT_THROW(build(box, cube({0, 0, 0}, 1), -1), InputError);
  EXPECT_THROW(build(box, cube({0, 0, 0}, 1), 3, 0), InputError);
  EXPECT_THROW(build(box, cube({0, 0, 0}, 0), 3), InputError);
  EXPECT_THROW(build(box, cube({0, NAN, 0}, 1), 3), InputError);
}

TEST(Octree, SameNodesForOneAndTwoThreads) {
  const Solid e = elephant();
  const VoxelBounds b = default_bounds(e, 7);
  Octree one, two;
  {
    ThreadLimit limit(1);
    one = build(e, b, 7);
  }
  {
    ThreadLimit limit(2);
    two = build(e, b, 7);
  }
  ASSERT_EQ(one.nodes.size(), two.nodes.size());
  for (size_t i = 0; i < one.nodes.size(); ++i) {
    const Octree::Node &p = one.nodes[i], &q = two.nodes[i];
    ASSERT_TRUE(p.first_child == q.first_child && p.depth == q.depth && p.state == q.state &&
                p.occupancy == q.occupancy && p.cell == q.cell)
        << "node " << i;
  }
}

// ---- files --------------------------------------------------------------------------------------

/// Attribute `name` of the first tag that starts at or after `from` and contains `key`.
std::string attribute(const std::string& xml, const std::string& key, const std::string& name) {
  const size_t at = xml.find(key);
  EXPECT_NE(at, std::string::npos) << key;
  if (at == std::string::npos) return "";
  const size_t open = xml.rfind('<', at), close = xml.find('>', at);
  const std::string tag = xml.substr(open, close - open);
  const size_t a = tag.find(" " + name + "=\"");
  if (a == std::string::npos) return "";
  const size_t v = a + name.size() + 3;
  return tag.substr(v, tag.find('"', v) - v);
}

/// Text between the DataArray named `name` and its closing tag, trimmed.
std::string array_text(const std::string& xml, const std::string& name) {
  const size_t at = xml.find("Name=\"" + name + "\"");
  const size_t begin = xml.find('>', at) + 1, end = xml.find("</DataArray>", begin);
  std::string body = xml.substr(begin, end - begin);
  body.erase(0, body.find_first_not_of(" \n"));
  body.erase(body.find_last_not_of(" \n") + 1);
  return body;
}

std::vector<uint8_t> unbase64(const std::string& text) {
  std::vector<uint8_t> out;
  uint32_t acc = 0;
  int bits = 0;
  for (char ch : text) {
    const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* p = std::strchr(digits, ch);
    if (ch == '=' || p == nullptr || ch == '\0') break;
    acc = (acc << 6) | static_cast<uint32_t>(p - digits);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<uint8_t>(acc >> bits));
    }
  }
  return out;
}

/// Decoded inline binary array: the UInt64 byte count, then exactly that many bytes (the file
/// declares the machine's byte order).
std::vector<uint8_t> binary_array(const std::string& xml, const std::string& name) {
  std::vector<uint8_t> raw = unbase64(array_text(xml, name));
  if (raw.size() < 8) {
    ADD_FAILURE() << name << ": no header";
    return {};
  }
  uint64_t size = 0;
  std::memcpy(&size, raw.data(), 8);
  EXPECT_EQ(raw.size(), 8 + size) << name;
  return {raw.begin() + 8, raw.end()};
}

/// Every opening tag closed in order (declarations and self-closing tags aside).
bool balanced(const std::string& xml) {
  std::vector<std::string> open;
  for (size_t at = xml.find('<'); at != std::string::npos; at = xml.find('<', at + 1)) {
    const size_t end = xml.find('>', at);
    if (end == std::string::npos) return false;
    const std::string tag = xml.substr(at + 1, end - at - 1);
    if (tag.empty() || tag[0] == '?' || tag.back() == '/') continue;
    const std::string name =
        tag.substr(tag[0] == '/', tag.find_first_of(" /", 1) - (tag[0] == '/'));
    if (tag[0] != '/') {
      open.push_back(name);
    } else {
      if (open.empty() || open.back() != name) return false;
      open.pop_back();
    }
  }
  return open.empty();
}

class OctreeFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    solid_ = subtract({elephant(), box_solid({-1, -1, 0.05}, {1, 1, 1})});  // the top sliced off
    tree_ = build(solid_, default_bounds(solid_, 5), 5);
    bt_tree_ = build(solid_, octomap_bounds(solid_.bbox(), 5), 5);
    dir_ = test::temp_dir("octree");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  Solid solid_;
  Octree tree_;
  Octree bt_tree_;  ///< over octomap_bounds: a .bt can be written
  std::filesystem::path dir_;
};

TEST_F(OctreeFiles, HtgDescribesTheTreeBreadthFirst) {
  write_octree(dir_ / "t.htg", tree_, 0.5);
  const std::string xml = test::read_file(dir_ / "t.htg");
  ASSERT_TRUE(balanced(xml));
  EXPECT_EQ(attribute(xml, "<VTKFile", "type"), "HyperTreeGrid");
  EXPECT_EQ(attribute(xml, "<VTKFile", "version"), "1.0");
  EXPECT_EQ(attribute(xml, "<VTKFile", "byte_order"),
            std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian");
  EXPECT_EQ(attribute(xml, "<HyperTreeGrid", "Dimensions"), "2 2 2");
  EXPECT_EQ(attribute(xml, "<HyperTreeGrid", "BranchFactor"), "2");
  const size_t n = tree_.nodes.size();
  EXPECT_EQ(attribute(xml, "<Tree ", "NumberOfVertices"), std::to_string(n));
  int levels = 0;
  std::map<int, long long> per_level;
  for (const Octree::Node& node : tree_.nodes) {
    levels = std::max(levels, node.depth + 1);
    ++per_level[node.depth];
  }
  EXPECT_EQ(attribute(xml, "<Tree ", "NumberOfLevels"), std::to_string(levels));
  std::string counts;
  for (const auto& [d, c] : per_level) {
    if (d > 0) counts += ' ';
    counts += std::to_string(c);
  }
  EXPECT_EQ(array_text(xml, "NbVerticesByLevel"), counts);
  const double x0 = std::stod(array_text(xml, "XCoordinates"));
  EXPECT_EQ(x0, tree_.bounds.min.x);
  // Descriptor: one bit per vertex above the deepest level, most significant bit first.
  const size_t described = n - static_cast<size_t>(per_level.rbegin()->second);
  EXPECT_EQ(attribute(xml, "Name=\"Descriptor\"", "NumberOfTuples"), std::to_string(described));
  const std::vector<uint8_t> bits = binary_array(xml, "Descriptor");
  ASSERT_EQ(bits.size(), (described + 7) / 8);
  for (size_t i = 0; i < described; ++i)
    EXPECT_EQ((bits[i / 8] >> (7 - i % 8)) & 1, tree_.nodes[i].first_child != 0 ? 1 : 0) << i;
  for (size_t i = described; i < n; ++i) EXPECT_EQ(tree_.nodes[i].first_child, 0u);
  const std::vector<uint8_t> state = binary_array(xml, "state");
  const std::vector<uint8_t> occupancy = binary_array(xml, "occupancy");
  ASSERT_EQ(state.size(), n);
  ASSERT_EQ(occupancy.size(), 4 * n);
  for (size_t i = 0; i < n; ++i) {
    EXPECT_EQ(state[i], static_cast<uint8_t>(tree_.nodes[i].state));
    float f;
    std::memcpy(&f, occupancy.data() + 4 * i, 4);
    EXPECT_EQ(f, tree_.nodes[i].occupancy);
  }
}

/// Runs tests/octree/read_htg.py (VTK's vtkXMLHyperTreeGridReader) on `file`; its JSON, or null
/// with a test failure when the script (or VTK inside it) fails.
nlohmann::json read_htg_with_vtk(const std::filesystem::path& file) {
  const std::string python =
      std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::filesystem::path out = file.string() + ".out";
  const std::string cmd = python + " '" +
                          (test::source_dir() / "tests/octree/read_htg.py").string() + "' '" +
                          file.string() + "' >'" + out.string() + "'";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(status, 0) << cmd;
  if (status != 0) return nullptr;
  const nlohmann::json j = nlohmann::json::parse(test::read_file(out), nullptr, false);
  std::filesystem::remove(out);
  EXPECT_FALSE(j.is_discarded()) << cmd;
  return j.is_discarded() ? nlohmann::json() : j;
}

/// Cover's leaves in VTK's depth-first order (children x fastest, then y, then z: the octree's
/// Morton child order).
void leaves_depth_first(const Octree& t, uint32_t node, std::vector<uint32_t>& out) {
  if (t.nodes[node].first_child == 0) {
    out.push_back(node);
    return;
  }
  for (uint32_t c = 0; c < 8; ++c) leaves_depth_first(t, t.nodes[node].first_child + c, out);
}

TEST_F(OctreeFiles, HtgLoadsInVtkWithTheSameLeaves) {
  // Issue 5: the .htg must load in VTK itself (python3-vtk9) with the same leaf cells, states
  // and occupancies; also for a depth-0 tree (the root alone).
  const Octree flat = build(solid_, default_bounds(solid_, 2), 0);
  for (const Octree* tree : std::initializer_list<const Octree*>{&tree_, &flat}) {
    write_octree(dir_ / "t.htg", *tree, 0.5);
    const nlohmann::json j = read_htg_with_vtk(dir_ / "t.htg");
    ASSERT_TRUE(j.is_object());
    EXPECT_EQ(j["trees"], 1);
    EXPECT_EQ(j["vertices"], tree->nodes.size());
    std::vector<uint32_t> leaves;
    leaves_depth_first(*tree, 0, leaves);
    const auto& cells = j["leaves"];
    ASSERT_EQ(cells.size(), leaves.size());
    const double tol = 1e-12 * tree->bounds.size;
    for (size_t k = 0; k < leaves.size(); ++k) {
      const Octree::Node& node = tree->nodes[leaves[k]];
      const auto& c = cells[k];
      ASSERT_EQ(c[0].get<int>(), node.depth) << "leaf " << k;
      const double h = tree->cell_size(node.depth);
      const Vec3 min = tree->min(node);
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(c[1 + 2 * a].get<double>(), min[a], tol) << "leaf " << k;
        EXPECT_NEAR(c[2 + 2 * a].get<double>(), min[a] + h, tol) << "leaf " << k;
      }
      EXPECT_EQ(c[7].get<int>(), static_cast<int>(node.state)) << "leaf " << k;
      EXPECT_EQ(c[8].get<float>(), node.occupancy) << "leaf " << k;
    }
  }
}

/// Whether a leaf is occupied in a .bt written at `threshold`.
bool bt_occupied(const Octree::Node& node, double threshold) {
  return node.state == CellState::kFull ||
         (node.state == CellState::kPartial && node.occupancy >= threshold);
}

/// The Cover leaf holding the finest cell (i, j, k) (0 ≤ i, j, k < 2^depth).
const Octree::Node& leaf_at(const Octree& t, uint32_t i, uint32_t j, uint32_t k) {
  uint32_t id = 0;
  for (int d = 0; t.nodes[id].first_child != 0; ++d) {
    const int shift = t.depth - d - 1;
    id = t.nodes[id].first_child + ((i >> shift) & 1) + 2 * ((j >> shift) & 1) +
         4 * ((k >> shift) & 1);
  }
  return t.nodes[id];
}

TEST_F(OctreeFiles, BtPlacesCellsAtTheirWorldCoordinates) {
  // Loaded with liboctomap, every finest cell's world centre (Cover's own box, in world
  // coordinates) finds an OctoMap voxel of the cell's occupancy and resolution-sized extent,
  // and every OctoMap leaf lies inside the cube: the map sits where the model is. The fixture's
  // cube (octomap_bounds) is not aligned with OctoMap's own octants, and a cube far from the
  // origin checks that no centring remains.
  const Octree far = build(solid_, cube({-3.5, 1000.25, -0.75}, 2), 4);
  for (const Octree* t : std::initializer_list<const Octree*>{&bt_tree_, &far}) {
    for (double threshold : {0.5, 0.1}) {
      write_octree(dir_ / "t.bt", *t, threshold);
      octomap::OcTree read(0.1);
      ASSERT_TRUE(read.readBinary((dir_ / "t.bt").string()));
      const double h = t->cell_size(t->depth);
      EXPECT_EQ(read.getResolution(), h);
      const uint32_t n = 1u << t->depth;
      for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < n; ++j)
          for (uint32_t k = 0; k < n; ++k) {
            const Vec3 c{t->bounds.min.x + (i + 0.5) * h, t->bounds.min.y + (j + 0.5) * h,
                         t->bounds.min.z + (k + 0.5) * h};
            const octomap::OcTreeNode* leaf = read.search(c.x, c.y, c.z);
            ASSERT_NE(leaf, nullptr) << i << " " << j << " " << k;
            ASSERT_EQ(read.isNodeOccupied(leaf), bt_occupied(leaf_at(*t, i, j, k), threshold))
                << i << " " << j << " " << k;
          }
      // Every OctoMap leaf inside the cube; their volume is the cube's.
      double volume = 0;
      for (auto it = read.begin_leafs(); it != read.end_leafs(); ++it) {
        const double half = 0.5 * it.getSize();
        const octomap::point3d p = it.getCoordinate();
        for (int a = 0; a < 3; ++a) {
          EXPECT_GE(p(a) - half, t->bounds.min[a] - 1e-9 * t->bounds.size);
          EXPECT_LE(p(a) + half, t->bounds.min[a] + t->bounds.size * (1 + 1e-9));
        }
        volume += std::pow(it.getSize(), 3);
      }
      EXPECT_DOUBLE_EQ(volume, std::pow(t->bounds.size, 3));
    }
  }
}

TEST_F(OctreeFiles, BtCubeOffOctomapGridRefused) {
  // A cube whose min is no whole multiple of size/2^depth, or beyond OctoMap's ±32768 keys,
  // cannot be placed: refused with the reason, nothing written.
  const Octree off = build(solid_, cube({0.01, 0, 0}, 2), 3);
  try {
    write_octree(dir_ / "t.bt", off, 0.5);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("whole multiples of the resolution"), std::string::npos)
        << e.what();
  }
  const Octree beyond = build(solid_, cube({4096, 0, 0}, 1), 4);  // 65536 cells of 1/16 away
  try {
    write_octree(dir_ / "t.bt", beyond, 0.5);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("keys reach ±32768 cells"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "t.bt"));
}

/// Whether 2^depth cells of side h from some whole multiple m·h hold `box` with one cell of
/// margin per side within OctoMap's keys (−32768 ≤ m ≤ 32768 − 2^depth), in exact rationals.
bool octomap_cube_exists(const Bbox& box, int depth, double h) {
  const double n = std::ldexp(1.0, depth);
  for (int a = 0; a < 3; ++a) {
    const CGAL::Gmpq lo(box.min[a]), hi(box.max[a]), step(h);
    // floor(lo/h) − 1 ≥ m and m ≥ ceil(hi/h) + 1 − n: some m in range.
    const CGAL::Gmpq low = lo / step, high = hi / step;
    const double below = std::floor(CGAL::to_double(low)), above = std::ceil(CGAL::to_double(high));
    double b = below, t = above;
    if (CGAL::Gmpq(b) > low) --b;
    if (CGAL::Gmpq(b + 1) <= low) ++b;
    if (CGAL::Gmpq(t) < high) ++t;
    if (CGAL::Gmpq(t - 1) >= high) --t;
    if (std::max(t + 1 - n, -32768.0) > std::min(b - 1, 32768 - n)) return false;
  }
  return true;
}

TEST(OctomapBounds, CubeOnOctomapsGridHoldsTheBoxWithExactCells) {
  // Boxes of sizes 1e-3 to 10 within ±100, depths 2 to 16: the cube holds the box with a cell
  // of margin, starts at a whole multiple of its cell, stays within ±32768 cells, and its cell
  // has at most 4 significant bits, and no smaller such cell would do (checked in exact
  // rationals).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-100, 100), e(1e-3, 10);
  for (int trial = 0; trial < 300; ++trial) {
    Bbox box;
    const Vec3 lo{u(rng), u(rng), u(rng)};
    box.add(lo);
    box.add(lo + Vec3{e(rng), e(rng), e(rng)});
    const int depth = 2 + trial % 15;
    const VoxelBounds b = octomap_bounds(box, depth);
    const double n = std::ldexp(1.0, depth), h = std::ldexp(b.size, -depth);
    int exponent = 0;
    const double q = std::ldexp(std::frexp(h, &exponent), 4);  // h = q·2^(exponent − 4)
    EXPECT_EQ(q, std::floor(q)) << trial;
    for (int a = 0; a < 3; ++a) {
      const double m = b.min[a] / h;
      EXPECT_EQ(m, std::floor(m));
      EXPECT_EQ(m * h, b.min[a]);
      EXPECT_GE(m, -32768);
      EXPECT_LE(m + n, 32768);
      EXPECT_LE(b.min[a] + h, box.min[a]);
      EXPECT_GE(b.min[a] + b.size - h, box.max[a]);
    }
    const double extent =
        std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z});
    EXPECT_GE(h * (n - 2), extent);
    const double smaller = q > 8 ? std::ldexp(q - 1, exponent - 4) : std::ldexp(15, exponent - 5);
    EXPECT_FALSE(octomap_cube_exists(box, depth, smaller)) << trial;
  }
  // Near the origin the cell is within 9/8 of extent/(2^depth − 3) (one margin cell per side
  // wherever the box lies on the grid): bunny00's box at depth 9.
  Bbox unit;
  unit.add(Vec3{0, 0, 0});
  unit.add(Vec3{1, 1, 1});
  EXPECT_LE(std::ldexp(octomap_bounds(unit, 9).size, -9), 1.125 / 509);
  // Depth 16 spans all of OctoMap's keys: the cube is OctoMap's whole range.
  const VoxelBounds all = octomap_bounds(unit, 16);
  EXPECT_EQ(all.min.x, -0.5 * all.size);
}

/// The oracle for .bt: liboctomap's own OcTree built from the octree's leaves at their world
/// keys (key = cell index + min/res + 2^15; each leaf split into OctoMap-aligned cubes, halving
/// until aligned), fully pruned (every node whose 8 children are leaves of one value becomes a
/// leaf, bottom-up), then written as OcTree::writeBinary writes it.
class OctomapOracle : public octomap::OcTree {
 public:
  OctomapOracle(const Octree& tree, double threshold)
      : octomap::OcTree(tree.cell_size(tree.depth)) {
    const int depth = tree.depth;
    const double h = tree.cell_size(depth);
    std::array<int64_t, 3> base{};
    for (int a = 0; a < 3; ++a) base[a] = std::llround(tree.bounds.min[a] / h) + 32768;
    for (const Octree::Node& node : tree.nodes) {
      if (node.first_child != 0) continue;
      const float value =
          bt_occupied(node, threshold) ? getClampingThresMaxLog() : getClampingThresMinLog();
      const int64_t span = int64_t{1} << (depth - node.depth);
      place({base[0] + node.cell[0] * span, base[1] + node.cell[1] * span,
             base[2] + node.cell[2] * span},
            span, value);
    }
  }

  std::string bytes() {
    updateInnerOccupancy();
    toMaxLikelihood();
    for (unsigned c = 0; c < 8; ++c)
      if (root != nullptr && nodeChildExists(root, c)) prune_all(getNodeChild(root, c));
    std::ostringstream s;
    s.precision(17);
    s << binaryFileHeader << "\n# (written by Cover)\nid " << getTreeType() << "\nsize " << size()
      << "\nres " << getResolution() << "\ndata\n";
    writeBinaryData(s);
    return s.str();
  }

 private:
  /// The cube of `span` keys from `lo`: one OctoMap node when aligned, else its 8 halves.
  void place(const std::array<int64_t, 3>& lo, int64_t span, float value) {
    if (lo[0] % span == 0 && lo[1] % span == 0 && lo[2] % span == 0) {
      const octomap::OcTreeKey key(static_cast<uint16_t>(lo[0]), static_cast<uint16_t>(lo[1]),
                                   static_cast<uint16_t>(lo[2]));
      set_leaf(key, static_cast<unsigned>(16 - std::countr_zero(static_cast<uint64_t>(span))),
               value);
      return;
    }
    const int64_t half = span / 2;
    for (int c = 0; c < 8; ++c)
      place({lo[0] + (c & 1) * half, lo[1] + ((c >> 1) & 1) * half, lo[2] + ((c >> 2) & 1) * half},
            half, value);
  }

  void prune_all(octomap::OcTreeNode* node) {
    for (unsigned c = 0; c < 8; ++c)
      if (nodeChildExists(node, c) && nodeHasChildren(getNodeChild(node, c)))
        prune_all(getNodeChild(node, c));
    if (isNodeCollapsible(node)) pruneNode(node);
  }

  void set_leaf(const octomap::OcTreeKey& key, unsigned depth, float log_odds) {
    if (root == nullptr) {
      root = new octomap::OcTreeNode();
      ++tree_size;
    }
    octomap::OcTreeNode* node = root;
    for (unsigned d = 0; d < depth; ++d) {
      const unsigned pos = octomap::computeChildIdx(key, static_cast<int>(tree_depth - 1 - d));
      node = nodeChildExists(node, pos) ? getNodeChild(node, pos) : createNodeChild(node, pos);
    }
    node->setLogOdds(log_odds);
  }
};

TEST_F(OctreeFiles, BtIsTheBytesLiboctomapWrites) {
  // The direct .bt writer against liboctomap's own tree of the same leaves at their world keys:
  // the fixture at several thresholds; depths 1, 2, 3 and 16; cubes aligned with OctoMap's
  // octants and not; a root leaf; a cell whose 8 children are full leaves (two boxes meeting
  // on a grid plane inside it).
  const auto expect_same = [&](const Octree& t, double threshold, const std::string& what) {
    write_octree(dir_ / "t.bt", t, threshold);
    EXPECT_EQ(test::read_file(dir_ / "t.bt"), OctomapOracle(t, threshold).bytes()) << what;
  };
  for (double threshold : {0.0, 0.1, 0.5, 1.0}) expect_same(bt_tree_, threshold, "elephant");
  const Solid halves =
      unite({box_solid({0, 0, 0}, {0.25, 0.5, 0.5}), box_solid({0.25, 0, 0}, {0.5, 0.5, 0.5})});
  for (int depth : {1, 2, 3}) {
    expect_same(build(halves, cube({0, 0, 0}, 1), depth), 0.5, "halves");
    expect_same(build(halves, cube({-0.5, -0.5, -0.5}, 1), depth), 0.5, "halves, shifted");
  }
  const Solid small = box_solid({0.1, 0.2, 0.3}, {0.1004, 0.2003, 0.3002});
  expect_same(build(small, cube({-0.5, -0.5, -0.5}, 1), 16), 0.5, "depth 16");
  expect_same(build(small, cube({2, 2, 2}, 1), 3), 0.5, "root leaf");
  expect_same(build(small, cube({2.125, 1.875, 2.375}, 1), 3), 0.5, "root leaf, shifted");
  expect_same(build(small, cube({-0.5, -0.5, -0.5}, 1), 16), 0.0, "depth 16, threshold 0");
}

TEST_F(OctreeFiles, JsonListsEveryLeaf) {
  write_octree(dir_ / "t.json", tree_, 0.5);
  const nlohmann::json j = nlohmann::json::parse(test::read_file(dir_ / "t.json"));
  EXPECT_EQ(j["depth"], tree_.depth);
  EXPECT_EQ(j["nodes"], tree_.nodes.size());
  EXPECT_EQ(j["bounds"]["size"].get<double>(), tree_.bounds.size);
  EXPECT_EQ(j["bounds"]["min"][1].get<double>(), tree_.bounds.min.y);
  const auto counts = tree_.leaf_counts();
  EXPECT_EQ(j["leaves"]["empty"], counts[0]);
  EXPECT_EQ(j["leaves"]["full"], counts[1]);
  EXPECT_EQ(j["leaves"]["partial"], counts[2]);
  const auto& cells = j["cells"];
  ASSERT_EQ(cells.size(), counts[0] + counts[1] + counts[2]);
  EXPECT_EQ(j["cell_fields"], nlohmann::json({"depth", "i", "j", "k", "state", "occupancy"}));
  size_t k = 0;
  for (const Octree::Node& node : tree_.nodes) {
    if (node.first_child != 0) continue;
    const auto& c = cells[k++];
    ASSERT_EQ(c.size(), 6u);
    EXPECT_EQ(c[0].get<int>(), node.depth);
    // The corner (i, j, k) at the cell's depth gives back its exact lower corner.
    const double s = tree_.cell_size(node.depth);
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(tree_.bounds.min[a] + c[1 + a].get<int64_t>() * s, tree_.min(node)[a]) << k;
    EXPECT_EQ(c[4].get<int>(), static_cast<int>(node.state));
    EXPECT_EQ(c[5].get<float>(), node.occupancy);
  }
}

TEST_F(OctreeFiles, ErrorsNameTheFileAndLeaveNothingBehind) {
  EXPECT_TRUE(is_octree_extension("a.HTG"));
  EXPECT_TRUE(is_octree_extension("a.bt"));
  EXPECT_FALSE(is_octree_extension("a.vti"));
  EXPECT_THROW(write_octree(dir_ / "t.vti", tree_, 0.5), InputError);
  EXPECT_THROW(write_octree(dir_ / "t.bt", tree_, 1.5), InputError);
  EXPECT_THROW(write_octree(dir_ / "missing" / "t.json", tree_, 0.5), InputError);
  const Octree flat = build(solid_, default_bounds(solid_, 2), 0);
  try {
    write_octree(dir_ / "flat.bt", flat, 0.5);
    ADD_FAILURE() << "depth 0 written as .bt";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("flat.bt"), std::string::npos);
  }
  write_octree(dir_ / "flat.htg", flat, 0.5);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_),
                          std::filesystem::directory_iterator()),
            1);
}

// A solid with no leaf (the empty set) gives the root alone, empty, one-shot or prepared,
// without reading its empty CSG tree.
TEST(Octree, SolidWithNoLeafIsOneEmptyRoot) {
  const Solid none;
  const VoxelBounds cube{{-1, -1, -1}, 2};
  for (const Octree& t :
       {build_octree(none, cube, {.depth = 4}), build_octree(Prepared(none), cube, {.depth = 4})}) {
    ASSERT_EQ(t.nodes.size(), 1u);
    EXPECT_EQ(t.nodes[0].state, CellState::kEmpty);
    EXPECT_EQ(t.nodes[0].first_child, 0u);
    EXPECT_EQ(t.depth, 4);
  }
  EXPECT_THROW(build_octree(none, cube, {.depth = 17}), InputError);
}

}  // namespace
}  // namespace cover
