#include "solid/transform.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <numbers>

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
  for (Vec3& p : mesh.vertices) {
    const Eigen::Vector4d q = m * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
    p = {q.x(), q.y(), q.z()};
  }
  if (m.topLeftCorner<3, 3>().determinant() < 0) {
    for (size_t f = 0; f < mesh.face_count(); ++f)
      std::reverse(mesh.face_vertices.begin() + mesh.face_start[f],
                   mesh.face_vertices.begin() + mesh.face_start[f + 1]);
  }
}

}  // namespace cover
