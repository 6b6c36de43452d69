#include "cover/solid/primitives.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace cover {

PolygonMesh make_box(Vec3 lo, Vec3 hi) {
  PolygonMesh m;
  // Vertex i has x = bit 0, y = bit 1, z = bit 2 of i.
  for (int i = 0; i < 8; ++i)
    m.vertices.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  m.add_face({0, 2, 3, 1});  // z = lo, normal −z
  m.add_face({4, 5, 7, 6});  // z = hi, normal +z
  m.add_face({0, 1, 5, 4});  // y = lo, normal −y
  m.add_face({2, 6, 7, 3});  // y = hi, normal +y
  m.add_face({0, 4, 6, 2});  // x = lo, normal −x
  m.add_face({1, 3, 7, 5});  // x = hi, normal +x
  return m;
}

PolygonMesh make_sphere(Vec3 c, double r, int segments) {
  const int slices = std::max(3, segments);
  const int stacks = std::max(2, segments / 2);
  PolygonMesh m;
  m.vertices.push_back({c.x, c.y, c.z - r});  // south pole, index 0
  for (int i = 1; i < stacks; ++i) {
    const double phi = std::numbers::pi * i / stacks - std::numbers::pi / 2;
    for (int j = 0; j < slices; ++j) {
      const double theta = 2 * std::numbers::pi * j / slices;
      m.vertices.push_back({c.x + r * std::cos(phi) * std::cos(theta),
                            c.y + r * std::cos(phi) * std::sin(theta), c.z + r * std::sin(phi)});
    }
  }
  const auto north = static_cast<uint32_t>(m.vertices.size());
  m.vertices.push_back({c.x, c.y, c.z + r});
  auto ring = [&](int i, int j) {
    return static_cast<uint32_t>(1 + (i - 1) * slices + (j % slices));
  };
  // Triangles around the poles, quads between rings; counter-clockwise seen from outside.
  // Quads of a UV sphere are planar (their four vertices lie on two parallel circles and two
  // meridian planes — an isosceles trapezoid).
  for (int j = 0; j < slices; ++j) m.add_face({0, ring(1, j + 1), ring(1, j)});
  for (int i = 1; i + 1 < stacks; ++i)
    for (int j = 0; j < slices; ++j)
      m.add_face({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j)});
  for (int j = 0; j < slices; ++j)
    m.add_face({north, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
  return m;
}

PolygonMesh make_cylinder(Vec3 base, Vec3 top, double r, int segments) {
  const int n = std::max(3, segments);
  Vec3 axis = top - base;
  // Orthonormal frame (u, v, axis/|axis|) with u, v spanning the cross-section.
  const double len = std::sqrt(dot(axis, axis));
  const Vec3 w = (1.0 / len) * axis;
  const Vec3 helper = std::abs(w.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  Vec3 u = cross(helper, w);
  u = (1.0 / std::sqrt(dot(u, u))) * u;
  const Vec3 v = cross(w, u);
  PolygonMesh m;
  for (int end = 0; end < 2; ++end) {
    const Vec3 o = end == 0 ? base : top;
    for (int j = 0; j < n; ++j) {
      const double t = 2 * std::numbers::pi * j / n;
      m.vertices.push_back(o + (r * std::cos(t)) * u + (r * std::sin(t)) * v);
    }
  }
  std::vector<uint32_t> cap;
  for (int j = n - 1; j >= 0; --j) cap.push_back(static_cast<uint32_t>(j));  // base, normal −w
  m.add_face(cap);
  cap.clear();
  for (int j = 0; j < n; ++j) cap.push_back(static_cast<uint32_t>(n + j));  // top, normal +w
  m.add_face(cap);
  for (int j = 0; j < n; ++j) {
    const auto a = static_cast<uint32_t>(j), b = static_cast<uint32_t>((j + 1) % n);
    m.add_face({a, b, static_cast<uint32_t>(n) + b, static_cast<uint32_t>(n) + a});
  }
  return m;
}

}  // namespace cover
