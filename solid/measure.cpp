#include "cover/solid/measure.h"

#include <cmath>

namespace cover {
namespace {

Vec3 centre(const PolygonMesh& mesh) {
  Bbox box = face_bbox(mesh);
  if (box.empty()) return {};
  return 0.5 * (box.min + box.max);
}

}  // namespace

double signed_volume(const PolygonMesh& mesh) {
  const Vec3 o = centre(mesh);
  NeumaierSum sum;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    auto face = mesh.face(f);
    if (face.size() < 3) continue;
    const Vec3 a = mesh.vertices[face[0]] - o;
    for (size_t i = 1; i + 1 < face.size(); ++i) {
      const Vec3 b = mesh.vertices[face[i]] - o;
      const Vec3 c = mesh.vertices[face[i + 1]] - o;
      sum.add(dot(a, cross(b, c)) / 6.0);
    }
  }
  return sum.value();
}

double surface_area(const PolygonMesh& mesh) {
  NeumaierSum sum;
  for (size_t f = 0; f < mesh.face_count(); ++f) {
    auto face = mesh.face(f);
    if (face.size() < 3) continue;
    // Newell normal of the whole face (sum of the fan triangles' normals).
    Vec3 n{};
    const Vec3 a = mesh.vertices[face[0]];
    for (size_t i = 1; i + 1 < face.size(); ++i)
      n = n + cross(mesh.vertices[face[i]] - a, mesh.vertices[face[i + 1]] - a);
    const double len = std::sqrt(dot(n, n));
    if (len == 0) continue;
    // Σ signed triangle areas projected on the unit normal = area of the (planar) face.
    sum.add(0.5 * len);
  }
  return sum.value();
}

}  // namespace cover
