// tiles_meet (mesh/self_intersect.cpp): the exact contact test of two triangles of a mesh, with
// its 2D path for coplanar pairs, against an independent reference — CGAL's exact 3D
// intersection tests (Epeck) under CGAL::Polygon_mesh_processing::self_intersections' rules for
// shared vertices — on exactly coplanar triangles of tilted lattice planes (shared corners,
// collinear corners, touching edges, containment) and on pairs lifted off the plane.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "cover/mesh/validate.h"

namespace cover {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;

bool reference_meet(const std::array<uint32_t, 3>& a, const std::array<uint32_t, 3>& b,
                    const std::vector<Vec3>& v) {
  auto p = [&](uint32_t i) { return K::Point_3(v[i].x, v[i].y, v[i].z); };
  int shared = 0, ia = 0, ib = 0;
  std::array<bool, 3> as{}, bs{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j]) ++shared, as[i] = bs[j] = true, ia = i, ib = j;
  const K::Triangle_3 ta(p(a[0]), p(a[1]), p(a[2])), tb(p(b[0]), p(b[1]), p(b[2]));
  if (shared == 3) return true;
  if (shared == 2) {
    int ra = 0, rb = 0;
    for (int i = 0; i < 3; ++i) {
      if (!as[i]) ra = i;
      if (!bs[i]) rb = i;
    }
    const K::Point_3 q0 = p(a[(ra + 1) % 3]), q1 = p(a[(ra + 2) % 3]);
    return CGAL::coplanar(q0, q1, p(a[ra]), p(b[rb])) &&
           CGAL::coplanar_orientation(q0, q1, p(a[ra]), p(b[rb])) == CGAL::POSITIVE;
  }
  if (shared == 1)
    return CGAL::do_intersect(ta, K::Segment_3(p(b[(ib + 1) % 3]), p(b[(ib + 2) % 3]))) ||
           CGAL::do_intersect(tb, K::Segment_3(p(a[(ia + 1) % 3]), p(a[(ia + 2) % 3])));
  return CGAL::do_intersect(ta, tb);
}

TEST(TilesMeet, CoplanarAndLiftedPairsAgreeWithCgalsExactTests) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> coord(-2, 2), pick(0, 5), lift(0, 7);
  int meeting = 0, apart = 0, coplanar_meeting = 0;
  for (int plane = 0; plane < 3; ++plane)
    for (int trial = 0; trial < 2000; ++trial) {
      // Exactly representable lattice points of x + 2y + 3z = 1, 3x − y + 2z = 1 (z a half
      // integer) and the axis plane z = 0.5.
      std::vector<Vec3> v;
      for (int i = 0; i < 6; ++i) {
        const double s = coord(rng), t = coord(rng);
        if (plane == 0) v.push_back({1 - 2 * s - 3 * t, s, t});
        if (plane == 1) v.push_back({s, t, (1 - 3 * s + t) / 2});
        if (plane == 2) v.push_back({s, t, 0.5});
      }
      std::array<uint32_t, 3> a{0, 1, 2}, b{3, 4, 5};
      for (uint32_t& c : b)
        if (pick(rng) < 2) c = static_cast<uint32_t>(pick(rng) % 3);  // a corner of a
      if (b[0] == b[1] || b[1] == b[2] || b[0] == b[2]) continue;
      // Now and then b's own corners leave the plane: the non-coplanar paths too.
      if (lift(rng) == 0)
        for (uint32_t& c : b)
          if (c >= 3) v[c].z += 0.25 * (1 + lift(rng));
      auto collinear = [&](const std::array<uint32_t, 3>& t) {
        auto q = [&](uint32_t i) { return K::Point_3(v[i].x, v[i].y, v[i].z); };
        return CGAL::collinear(q(t[0]), q(t[1]), q(t[2]));
      };
      if (collinear(a) || collinear(b)) continue;
      const bool expected = reference_meet(a, b, v);
      EXPECT_EQ(tiles_meet(a, b, v), expected) << plane << " " << trial;
      EXPECT_EQ(tiles_meet(b, a, v), expected) << plane << " " << trial << " (swapped)";
      (expected ? meeting : apart) += 1;
      const K::Point_3 a0(v[a[0]].x, v[a[0]].y, v[a[0]].z), a1(v[a[1]].x, v[a[1]].y, v[a[1]].z),
          a2(v[a[2]].x, v[a[2]].y, v[a[2]].z);
      bool flat = true;
      for (uint32_t c : b)
        flat = flat && CGAL::coplanar(a0, a1, a2, K::Point_3(v[c].x, v[c].y, v[c].z));
      coplanar_meeting += flat && expected;
    }
  EXPECT_GT(meeting, 1000);
  EXPECT_GT(apart, 1000);
  EXPECT_GT(coplanar_meeting, 800);
}

// Pairs with no, one or two shared corners in general position and near-degenerate ones
// (corners of a small 3D lattice: collinear in some projection, coplanar, on each other's
// lines), the cases the 2D projection filters decide: the same answers as the reference.
TEST(TilesMeet, PairsInSpaceAgreeWithCgalsExactTests) {
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> coord(-2, 2), shared(0, 2), corner(0, 2);
  int meeting[3] = {0, 0, 0}, apart[3] = {0, 0, 0};
  for (int trial = 0; trial < 60000; ++trial) {
    std::vector<Vec3> v;
    for (int i = 0; i < 6; ++i)
      v.push_back({double(coord(rng)), double(coord(rng)), double(coord(rng))});
    std::array<uint32_t, 3> a{0, 1, 2}, b{3, 4, 5};
    const int count = shared(rng);
    const int first = corner(rng);
    for (int i = 0; i < count; ++i) b[(first + i) % 3] = static_cast<uint32_t>((first + 2 * i) % 3);
    if (b[0] == b[1] || b[1] == b[2] || b[0] == b[2]) continue;
    auto collinear = [&](const std::array<uint32_t, 3>& t) {
      auto q = [&](uint32_t i) { return K::Point_3(v[i].x, v[i].y, v[i].z); };
      return CGAL::collinear(q(t[0]), q(t[1]), q(t[2]));
    };
    if (collinear(a) || collinear(b)) continue;
    const bool expected = reference_meet(a, b, v);
    EXPECT_EQ(tiles_meet(a, b, v), expected) << trial;
    EXPECT_EQ(tiles_meet(b, a, v), expected) << trial << " (swapped)";
    (expected ? meeting : apart)[count] += 1;
  }
  for (int count = 0; count <= 2; ++count) {
    EXPECT_GT(meeting[count], 300) << count;
    EXPECT_GT(apart[count], 3000) << count;
  }
}

// star_vertices: a flagged vertex's fan has no two triangles that meet beyond their shared
// corners (by the reference), over random fans around the origin: corners of a small 3D
// lattice (collinear rays, flat and sharp fans), flat fans that wind twice, and cycles whose
// order is shuffled. The flag must also be given where it is due (convex flat fans, cube
// corners, vertices on a straight sharp edge), or the test could pass with no flags at all.
TEST(StarVertices, FlaggedFansHaveNoMeetingPairs) {
  std::mt19937 rng(13);
  std::uniform_int_distribution<int> coord(-2, 2), kind(0, 3), size(3, 9);
  int flagged = 0, refused_meeting = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int d = size(rng), k = kind(rng);
    std::vector<Vec3> v{{0, 0, 0}};
    for (int i = 0; i < d; ++i) {
      if (k == 0) {  // lattice corners in space
        v.push_back({double(coord(rng)), double(coord(rng)), double(coord(rng))});
      } else {  // a flat fan in z = 0 (k = 1 once around, k = 2 twice), k = 3 lifted
        const double turns = k == 2 ? 2 : 1;
        const double angle = 2 * M_PI * turns * (i + 0.5 * (coord(rng) + 2) / 5) / d;
        v.push_back({std::round(4 * std::cos(angle)), std::round(4 * std::sin(angle)),
                     k == 3 ? double(coord(rng)) : 0});
      }
    }
    std::vector<uint32_t> order(d);
    for (int i = 0; i < d; ++i) order[i] = static_cast<uint32_t>(i + 1);
    if (trial % 7 == 0) std::shuffle(order.begin(), order.end(), rng);
    std::vector<std::array<uint32_t, 3>> tris;
    bool degenerate = false;
    for (int i = 0; i < d; ++i) {
      const std::array<uint32_t, 3> t{0, order[i], order[(i + 1) % d]};
      const K::Point_3 p0(0, 0, 0), p1(v[t[1]].x, v[t[1]].y, v[t[1]].z),
          p2(v[t[2]].x, v[t[2]].y, v[t[2]].z);
      degenerate = degenerate || t[1] == t[2] || CGAL::collinear(p0, p1, p2);
      tris.push_back(t);
    }
    if (degenerate) continue;
    bool meet = false;
    for (size_t i = 0; i < tris.size(); ++i)
      for (size_t j = i + 1; j < tris.size(); ++j)
        meet = meet || reference_meet(tris[i], tris[j], v);
    const bool star = star_vertices(tris, {}, v)[0] != 0;
    EXPECT_FALSE(star && meet) << trial;
    flagged += star;
    refused_meeting += !star && meet;
  }
  EXPECT_GT(flagged, 2000);
  EXPECT_GT(refused_meeting, 2000);
  // Fans the flag is due to: a convex flat fan, a cube corner, a vertex on a cube's edge.
  auto fan = [](std::vector<Vec3> v, std::vector<std::array<uint32_t, 3>> tris) {
    return star_vertices(tris, {}, v)[0] != 0;
  };
  EXPECT_TRUE(fan({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 1, 0}, {-1, -1, 0}, {0, -1, 0}},
                  {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 1}}));
  // Corner (0,0,0) of the unit cube, outward: faces x = 0, y = 0, z = 0 as two triangles each.
  EXPECT_TRUE(fan({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}},
                  {{0, 2, 4}, {0, 4, 1}, {0, 1, 6}, {0, 6, 3}, {0, 3, 5}, {0, 5, 2}}));
  // Midpoint of the cube edge x = 0, y = 0 (faces x = 0 and y = 0 meet there at a right angle).
  EXPECT_TRUE(fan({{0, 0, 1}, {0, 0, 0}, {0, 0, 2}, {1, 0, 0}, {1, 0, 2}, {0, 1, 0}, {0, 1, 2}},
                  {{0, 1, 3}, {0, 3, 4}, {0, 4, 2}, {0, 2, 6}, {0, 6, 5}, {0, 5, 1}}));
  // A flat hexagonal fan that winds twice: refused.
  std::vector<Vec3> twice{{0, 0, 0}};
  std::vector<std::array<uint32_t, 3>> twice_tris;
  for (int i = 0; i < 6; ++i)
    twice.push_back({std::round(4 * std::cos(4 * M_PI * i / 6)),
                     std::round(4 * std::sin(4 * M_PI * i / 6)), 0});
  for (uint32_t i = 0; i < 6; ++i) twice_tris.push_back({0, i + 1, (i + 1) % 6 + 1});
  EXPECT_FALSE(fan(twice, twice_tris));
}

}  // namespace
}  // namespace cover
