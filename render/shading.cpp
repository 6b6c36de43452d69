#include "cover/render/shading.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "cover/solid/parallel.h"

namespace cover {
namespace {

Vec3 unit(Vec3 v) {
  const double l = std::sqrt(dot(v, v));
  return l > 0 ? (1.0 / l) * v : v;
}

}  // namespace

ShadingNormals shading_normals(const Solid& s, double crease_degrees) {
  ShadingNormals out;
  const size_t faces = s.face_count();
  if (!(crease_degrees > 0) || faces == 0) return out;
  const double cos_crease = std::cos(std::min(crease_degrees, 180.0) * std::numbers::pi / 180);
  // Newell normals: twice the face's area times its unit normal (false edges cancel).
  std::vector<Vec3> area_normal(faces), normal(faces);
  parallel_for(faces, 4096, [&](size_t begin, size_t end) {
    for (size_t f = begin; f < end; ++f) {
      const std::span<const uint32_t> loop = s.face(f);
      Vec3 n{0, 0, 0};
      for (size_t i = 0; i < loop.size(); ++i) {
        const Vec3 a = s.vertices[loop[i]], b = s.vertices[loop[(i + 1) % loop.size()]];
        n = n +
            Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
      }
      area_normal[f] = n;
      normal[f] = unit(n);
    }
  });
  // The faces around each vertex, in face order (a vertex repeated in one face counts once).
  std::vector<uint32_t> start(s.vertices.size() + 1, 0), around;
  for (size_t f = 0; f < faces; ++f) {
    const std::span<const uint32_t> loop = s.face(f);
    for (size_t i = 0; i < loop.size(); ++i)
      if (std::find(loop.begin(), loop.begin() + i, loop[i]) == loop.begin() + i)
        ++start[loop[i] + 1];
  }
  for (size_t v = 0; v < s.vertices.size(); ++v) start[v + 1] += start[v];
  around.resize(start.back());
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < faces; ++f) {
    const std::span<const uint32_t> loop = s.face(f);
    for (size_t i = 0; i < loop.size(); ++i)
      if (std::find(loop.begin(), loop.begin() + i, loop[i]) == loop.begin() + i)
        around[fill[loop[i]]++] = static_cast<uint32_t>(f);
  }
  out.corner.resize(s.face_vertices.size());
  parallel_for(faces, 1024, [&](size_t begin, size_t end) {
    for (size_t f = begin; f < end; ++f) {
      const size_t first = s.face_start[f];
      const std::span<const uint32_t> loop = s.face(f);
      for (size_t i = 0; i < loop.size(); ++i) {
        Vec3 sum{0, 0, 0};
        for (uint32_t k = start[loop[i]]; k < start[loop[i] + 1]; ++k) {
          const uint32_t g = around[k];
          if (dot(normal[g], normal[f]) >= cos_crease) sum = sum + area_normal[g];
        }
        const Vec3 n = dot(sum, sum) > 0 ? unit(sum) : normal[f];
        out.corner[first + i] = {static_cast<float>(n.x), static_cast<float>(n.y),
                                 static_cast<float>(n.z)};
      }
    }
  });
  return out;
}

Vec3 smooth_normal(const Solid& s, const ShadingNormals& normals, const Bvh::Tri& tri, Vec3 point) {
  const Vec3 geometric = unit(cross(tri.b - tri.a, tri.c - tri.a));
  if (normals.empty() || tri.face >= s.face_count()) return geometric;
  const std::span<const uint32_t> loop = s.face(tri.face);
  // The BVH reads a face of sign −1 backwards (its leaf's own orientation, bvh.cpp): position i
  // of the fan is entry at(i) of the stored list.
  const bool reversed = s.face_sign[tri.face] < 0;
  const size_t n = loop.size();
  const auto at = [&](size_t i) { return reversed ? n - 1 - i : i; };
  // The fan triangle's corners: v0 and the k with v_k = b, v_k+1 = c.
  size_t k = 0;
  for (size_t i = 1; i + 1 < n && k == 0; ++i)
    if (s.vertices[loop[at(i)]] == tri.b && s.vertices[loop[at(i + 1)]] == tri.c) k = i;
  if (k == 0 || !(s.vertices[loop[at(0)]] == tri.a)) return geometric;
  const Vec3 e0 = tri.b - tri.a, e1 = tri.c - tri.a, e2 = point - tri.a;
  const double d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1);
  const double d20 = dot(e2, e0), d21 = dot(e2, e1), denom = d00 * d11 - d01 * d01;
  if (!(denom > 0)) return geometric;
  const double wb = std::clamp((d11 * d20 - d01 * d21) / denom, 0.0, 1.0);
  const double wc = std::clamp((d00 * d21 - d01 * d20) / denom, 0.0, 1.0 - wb);
  const double wa = 1 - wb - wc;
  const size_t first = s.face_start[tri.face];
  const auto corner = [&](size_t i) {
    const std::array<float, 3>& c = normals.corner[first + i];
    return Vec3{c[0], c[1], c[2]};
  };
  const Vec3 m = unit(wa * corner(at(0)) + wb * corner(at(k)) + wc * corner(at(k + 1)));
  if (!(dot(m, m) > 0)) return geometric;
  return dot(m, geometric) < 0 ? -1.0 * m : m;
}

}  // namespace cover
