#include "solid/transform.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "solid/errors.h"
#include "solid/parallel.h"

namespace cover {

Affine make_trs(Eigen::Vector3d scale, Eigen::Vector3d axis, double degrees,
                Eigen::Vector3d translate) {
  Affine s = Affine::Identity();
  s.diagonal().head<3>() = scale;
  Affine r = Affine::Identity();
  if (degrees != 0) {
    r.topLeftCorner<3, 3>() =
        Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized()).toRotationMatrix();
  }
  Affine t = Affine::Identity();
  t.topRightCorner<3, 1>() = translate;
  return t * r * s;
}

void apply_transform(const Affine& m, PolygonMesh& mesh) {
  // Each vertex and each face on its own: chunks in parallel give the same doubles.
  constexpr size_t kGrain = 1 << 15;
  parallel_for(mesh.vertices.size(), kGrain, [&](size_t begin, size_t end) {
    for (size_t v = begin; v < end; ++v) {
      Vec3& p = mesh.vertices[v];
      const Eigen::Vector4d q = m * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
      p = {q.x(), q.y(), q.z()};
    }
  });
  if (m.topLeftCorner<3, 3>().determinant() < 0) {
    parallel_for(mesh.face_count(), kGrain, [&](size_t begin, size_t end) {
      for (size_t f = begin; f < end; ++f)
        std::reverse(mesh.face_vertices.begin() + mesh.face_start[f],
                     mesh.face_vertices.begin() + mesh.face_start[f + 1]);
    });
  }
}

Solid transform_solid(const Affine& m, Solid solid) {
  if (!m.allFinite()) throw InputError("transform: expected finite numbers");
  if (m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1)
    throw InputError("transform: the last row must be 0 0 0 1");
  const Eigen::Matrix3d linear = m.topLeftCorner<3, 3>();
  const double det = linear.determinant();
  if (!(std::abs(det) >= std::numeric_limits<double>::min()) || !std::isfinite(det)) {
    // Singular, or a determinant beyond the doubles: the latter tells by the matrix scaled to
    // entries of at most 1 (scaling by a power of two is exact).
    const double largest = linear.cwiseAbs().maxCoeff();
    const double scaled =
        largest > 0 ? (linear / std::exp2(std::ilogb(largest))).determinant() : 0.0;
    if (scaled == 0) throw InputError("transform: singular matrix (it flattens the solid)");
    const int exponent = static_cast<int>(std::lround(
        std::log10(std::abs(scaled)) + 3.0 * std::ilogb(largest) * std::log10(2.0)));
    throw InputError("transform: the determinant, about 1e" + std::to_string(exponent) +
                     ", is beyond the range of normal doubles: volumes would " +
                     (exponent < 0 ? "underflow" : "overflow"));
  }
  for (size_t v = 0; v < solid.vertices.size(); ++v) {
    Vec3& p = solid.vertices[v];
    const Eigen::Vector4d q = m * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
    p = {q.x(), q.y(), q.z()};
    for (int a = 0; a < 3; ++a)
      if (!(std::abs(p[a]) <= kMaxCoordinate))
        throw InputError("transform: vertex " + std::to_string(v) +
                         " is mapped outside the supported range [-2^64, 2^64]");
  }
  if (det < 0)
    for (size_t f = 0; f < solid.face_count(); ++f)
      std::reverse(solid.face_vertices.begin() + solid.face_start[f],
                   solid.face_vertices.begin() + solid.face_start[f + 1]);
  for (Leaf& leaf : solid.leaves) {
    leaf.bbox = Bbox{};  // over the vertices of its faces, as make_leaf's face_bbox
    for (uint32_t f = leaf.first_face; f < leaf.first_face + leaf.face_count; ++f)
      for (uint32_t v : solid.face(f)) leaf.bbox.add(solid.vertices[v]);
  }
  return solid;
}

}  // namespace cover
