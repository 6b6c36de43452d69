// Face triangulation (mesh/triangulate.h): fans of convex faces, constrained triangulations of
// the rest (every loop vertex a corner, holes behind false edges left empty, the loop's
// orientation kept), and the two kinds of boundaries that cross themselves.
#include "cover/mesh/triangulate.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <set>
#include <vector>

namespace cover {
namespace {

using Tris = std::vector<std::array<uint32_t, 3>>;

/// Points (x, y, 0), so the projection is the xy plane.
std::vector<Vec3> planar(const std::vector<std::array<double, 2>>& xy) {
  std::vector<Vec3> p;
  for (const auto& [x, y] : xy) p.push_back({x, y, 0});
  return p;
}

/// Signed xy area of each triangle, summed (exact for these small binary coordinates).
double signed_area(const std::vector<Vec3>& p, const Tris& tris) {
  double sum = 0;
  for (const auto& t : tris) sum += 0.5 * cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]).z;
  return sum;
}

TEST(TriangulateFace, ConvexFaceIsItsFan) {
  const auto p = planar({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  Tris tris;
  EXPECT_EQ(triangulate_face(p, std::vector<uint32_t>{0, 1, 2, 3}, tris), FaceTiling::kSimple);
  EXPECT_EQ(tris, (Tris{{0, 1, 2}, {0, 2, 3}}));
}

TEST(TriangulateFace, StraightCornerStaysATileCorner) {
  // A unit square with vertex 4 in the middle of its bottom side: not fanned.
  const auto p = planar({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0}});
  Tris tris;
  EXPECT_EQ(triangulate_face(p, std::vector<uint32_t>{0, 4, 1, 2, 3}, tris), FaceTiling::kSimple);
  EXPECT_EQ(signed_area(p, tris), 1);
  std::set<uint32_t> corners;
  for (const auto& t : tris) corners.insert(t.begin(), t.end());
  EXPECT_EQ(corners.size(), 5u);
}

TEST(TriangulateFace, NonConvexKeepsTheLoopOrientation) {
  // An L: the 2×2 square without its top-right quarter.
  const auto p = planar({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
  const std::vector<uint32_t> ccw{0, 1, 2, 3, 4, 5}, cw{5, 4, 3, 2, 1, 0};
  Tris up, down;
  EXPECT_EQ(triangulate_face(p, ccw, up), FaceTiling::kSimple);
  EXPECT_EQ(triangulate_face(p, cw, down), FaceTiling::kSimple);
  EXPECT_EQ(signed_area(p, up), 3);
  EXPECT_EQ(signed_area(p, down), -3);
  for (const auto& t : up) EXPECT_GT(cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]).z, 0);
}

TEST(TriangulateFace, HoleBehindFalseEdgesStaysEmpty) {
  // Outer square 0..3 (4×4), inner square 4..7 (clockwise), joined by the false edge 0–4.
  const auto p = planar({{0, 0}, {4, 0}, {4, 4}, {0, 4}, {1, 1}, {1, 3}, {3, 3}, {3, 1}});
  Tris tris;
  EXPECT_EQ(triangulate_face(p, std::vector<uint32_t>{0, 1, 2, 3, 0, 4, 5, 6, 7, 4}, tris),
            FaceTiling::kSimple);
  EXPECT_EQ(signed_area(p, tris), 16 - 4);
  for (const auto& t : tris) {
    const Vec3 c = (1.0 / 3) * (p[t[0]] + p[t[1]] + p[t[2]]);
    EXPECT_FALSE(c.x > 1 && c.x < 3 && c.y > 1 && c.y < 3);
  }
}

TEST(TriangulateFace, StarWindsTwiceAndIsFanned) {
  std::vector<Vec3> p;
  for (int i = 0; i < 5; ++i) {
    const double a = 2 * std::numbers::pi * (2 * i) / 5;
    p.push_back({std::cos(a), std::sin(a), 0});
  }
  Tris tris;
  EXPECT_EQ(triangulate_face(p, std::vector<uint32_t>{0, 1, 2, 3, 4}, tris), FaceTiling::kWinding);
  EXPECT_EQ(tris, (Tris{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
}

TEST(TriangulateFace, CrossingBoundaryGivesNoTriangles) {
  const auto p = planar({{0, 0}, {1, 1}, {1, 0}, {0, 1}});  // a bow tie
  Tris tris;
  EXPECT_EQ(triangulate_face(p, std::vector<uint32_t>{0, 1, 2, 3}, tris), FaceTiling::kCrossing);
  EXPECT_TRUE(tris.empty());
}

TEST(TriangulateFace, CollinearFaceHasNoTriangles) {
  const auto p = planar({{0, 0}, {1, 0}, {2, 0}, {3, 0}});
  Tris tris;
  EXPECT_EQ(triangulate_face(p, std::vector<uint32_t>{0, 1, 2, 3}, tris), FaceTiling::kSimple);
  EXPECT_EQ(triangulate_face(p, std::vector<uint32_t>{0, 1, 2}, tris), FaceTiling::kSimple);
  EXPECT_TRUE(tris.empty());
}

TEST(TriangulateFace, DominantAxis) {
  EXPECT_EQ(dominant_axis({0, 0, 1}), 2);
  EXPECT_EQ(dominant_axis({-3, 2, 1}), 0);
  EXPECT_EQ(dominant_axis({1, -1, 0.5}), 0);  // ties go to the lower axis
  EXPECT_EQ(dominant_axis({0.5, 1, -1}), 1);
}

}  // namespace
}  // namespace cover
