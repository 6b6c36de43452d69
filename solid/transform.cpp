#include "cover/solid/transform.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>

#include "cover/solid/errors.h"
#include "cover/solid/parallel.h"

namespace cover {

namespace {
// The arithmetic is Eigen's 4×4 double product, as it always was: the doubles a scene's
// transforms produce do not change with the type that carries them.
using Matrix4 = Eigen::Matrix4d;

Matrix4 to_eigen(const Transform& t) {
  Matrix4 m = Matrix4::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = t.rows[r][c];
  return m;
}

Transform from_eigen(const Matrix4& m) {
  Transform t;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) t.rows[r][c] = m(r, c);
  return t;
}
}  // namespace

Transform Transform::trs(Vec3 scale, Vec3 axis, double degrees, Vec3 translate) {
  Matrix4 s = Matrix4::Identity();
  s.diagonal().head<3>() = Eigen::Vector3d(scale.x, scale.y, scale.z);
  Matrix4 r = Matrix4::Identity();
  if (degrees != 0) {
    r.topLeftCorner<3, 3>() =
        Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0,
                          Eigen::Vector3d(axis.x, axis.y, axis.z).normalized())
            .toRotationMatrix();
  }
  Matrix4 t = Matrix4::Identity();
  t.topRightCorner<3, 1>() = Eigen::Vector3d(translate.x, translate.y, translate.z);
  return from_eigen(t * r * s);
}

Transform Transform::fit(const Bbox& box, Vec3 centre, double half_size, Vec3 axis,
                         double degrees) {
  const Vec3 c = 0.5 * (box.min + box.max);
  const double ext =
      std::max({box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z});
  const double s = 2 * half_size / ext;
  return trs({s, s, s}, axis, degrees, centre) * translation({-c.x, -c.y, -c.z});
}

Transform Transform::reflection(Vec3 normal) {
  const Eigen::Vector3d n(normal.x, normal.y, normal.z);
  Matrix4 m = Matrix4::Identity();
  m.topLeftCorner<3, 3>() -= 2 * n * n.transpose() / n.squaredNorm();
  return from_eigen(m);
}

Transform Transform::from_matrix(std::span<const double, 16> row_major) {
  if (row_major[12] != 0 || row_major[13] != 0 || row_major[14] != 0 || row_major[15] != 1)
    throw InputError("transform: the last row must be 0 0 0 1");
  Transform t;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) t.rows[r][c] = row_major[4 * r + c];
  return t;
}

Transform Transform::operator*(const Transform& first) const {
  return from_eigen(to_eigen(*this) * to_eigen(first));
}

Vec3 Transform::operator()(Vec3 p) const {
  const Eigen::Vector4d q = to_eigen(*this) * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
  return {q.x(), q.y(), q.z()};
}

double Transform::determinant() const {
  return to_eigen(*this).topLeftCorner<3, 3>().determinant();
}

void apply_transform(const Transform& t, PolygonMesh& mesh) {
  // Each vertex and each face on its own: chunks in parallel give the same doubles.
  constexpr size_t kGrain = 1 << 15;
  const Matrix4 m = to_eigen(t);
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

namespace {

/// The scale s = |det L|^(1/3) of a similarity L = s·Q (Q orthogonal, checked to 1e-9 relative:
/// a rotation's doubles are orthogonal only to rounding); throws naming `kind` otherwise.
double similarity_scale(const Matrix4& m, double det, const char* kind) {
  const Eigen::Matrix3d linear = m.topLeftCorner<3, 3>();
  const double s = std::cbrt(std::abs(det));
  const Eigen::Matrix3d gram = linear.transpose() * linear / (s * s);
  if (!gram.isApprox(Eigen::Matrix3d::Identity(), 1e-9))
    throw InputError(std::string("transform: ") + kind +
                     " leaves take rigid motions and uniform scales only (this one stretches "
                     "unevenly)");
  return s;
}

/// Field leaves take similarities only (similarity_scale): skeleton points are mapped, lengths
/// (r_T, R, a circle's radius) multiplied by s = |det L|^(1/3), a circle's normal mapped by L
/// (L⁻ᵀ ∝ L for a similarity), a mesh skeleton's hierarchy rebuilt. A blend keeps its first
/// primitive's threshold (solid/field_leaf.h).
void transform_fields(const Matrix4& m, double det, Solid& solid) {
  const double s = similarity_scale(m, det, "field");
  auto map = [&](Vec3& p, double w) {
    const Eigen::Vector4d q = m * Eigen::Vector4d(p.x, p.y, p.z, w);
    p = {q.x(), q.y(), q.z()};
    for (int a = 0; a < 3; ++a)
      if (!(std::abs(p[a]) <= kMaxCoordinate))
        throw InputError(
            "transform: a field skeleton is mapped outside the supported range "
            "[-2^64, 2^64]");
  };
  const double inf = std::numeric_limits<double>::infinity();
  for (FieldLeaf& field : solid.fields)
    for (FieldPrimitive& prim : field.primitives) {
      if (prim.kind == SkeletonKind::kCircle) {
        map(prim.points[0], 1.0);
        map(prim.points[1], 0.0);
        prim.circle_radius *= s;
      } else {
        for (Vec3& p : prim.points) map(p, 1.0);
      }
      if (prim.kind == SkeletonKind::kMesh) {
        // A mirror turns the triangles inside out: reverse them to keep them outward.
        if (det < 0)
          for (size_t t = 0; t + 2 < prim.points.size(); t += 3)
            std::swap(prim.points[t + 1], prim.points[t + 2]);
        prim.mesh = index_skeleton_mesh(prim.points);
      }
      prim.radius *= s;
      prim.influence *= s;
      if (!(prim.radius > 0 && prim.radius < prim.influence && prim.influence < inf))
        throw InputError("transform: the scale " + std::to_string(s) +
                         " takes a field primitive's radii out of range");
    }
  for (Leaf& leaf : solid.leaves)
    if (leaf.is_field()) leaf.bbox = field_support_box(solid.fields[leaf.field]);
}

/// Warp leaves take similarities only, as field leaves: M∘w∘M⁻¹ is the warp of the same kind
/// whose frame rows are mapped by Q = L/s (E'(M·p) = s·E(p)), axis point mapped, lengths
/// (ranges, centre, radius) multiplied by s and the twist rate divided by s; the child is
/// transformed by M. The leaf's box: the corners of the old box mapped, the result padded by
/// 1e-9 of its extent plus magnitude (the rounding of the mapped frame and parameters moves the
/// surface by a few ulps of those, far less than the pad).
void transform_warps(const Transform& t, const Matrix4& m, double det, Solid& solid) {
  const double s = similarity_scale(m, det, "warp");
  auto map = [&](const Vec3& p, double w, double scale) {
    const Eigen::Vector4d q = m * Eigen::Vector4d(p.x, p.y, p.z, w) / scale;
    return Vec3{q.x(), q.y(), q.z()};
  };
  for (WarpLeaf& warp : solid.warps) {
    warp.point = map(warp.point, 1.0, 1.0);
    warp.direction = map(warp.direction, 0.0, s);
    warp.toward = map(warp.toward, 0.0, s);
    for (Vec3& row : warp.frame) row = map(row, 0.0, s);
    warp.degrees_per_unit /= s;
    for (double& r : warp.range) r *= s;
    warp.center *= s;
    warp.radius *= s;
    warp.child = std::make_shared<const Solid>(transform_solid(t, *warp.child));
  }
  for (Leaf& leaf : solid.leaves) {
    if (!leaf.is_warp() || leaf.bbox.empty()) continue;
    Bbox box;
    for (int c = 0; c < 8; ++c)
      box.add(
          map({c & 1 ? leaf.bbox.max.x : leaf.bbox.min.x, c & 2 ? leaf.bbox.max.y : leaf.bbox.min.y,
               c & 4 ? leaf.bbox.max.z : leaf.bbox.min.z},
              1.0, 1.0));
    double pad = 0;
    for (int a = 0; a < 3; ++a)
      pad = std::max(
          pad, box.max[a] - box.min[a] + std::max(std::abs(box.min[a]), std::abs(box.max[a])));
    pad *= 1e-9;
    leaf.bbox.min = box.min - Vec3{pad, pad, pad};
    leaf.bbox.max = box.max + Vec3{pad, pad, pad};
  }
}

}  // namespace

Solid transform_solid(const Transform& t, Solid solid) {
  const Matrix4 m = to_eigen(t);
  if (!m.allFinite()) throw InputError("transform: expected finite numbers");
  const Eigen::Matrix3d linear = m.topLeftCorner<3, 3>();
  const double det = linear.determinant();
  if (!(std::abs(det) >= std::numeric_limits<double>::min()) || !std::isfinite(det)) {
    // Singular, or a determinant beyond the doubles: the latter tells by the matrix scaled to
    // entries of at most 1 (scaling by a power of two is exact).
    const double largest = linear.cwiseAbs().maxCoeff();
    const double scaled =
        largest > 0 ? (linear / std::exp2(std::ilogb(largest))).determinant() : 0.0;
    if (scaled == 0) throw InputError("transform: singular matrix (it flattens the solid)");
    const int exponent = static_cast<int>(
        std::lround(std::log10(std::abs(scaled)) + 3.0 * std::ilogb(largest) * std::log10(2.0)));
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
  if (!solid.fields.empty()) transform_fields(m, det, solid);
  if (!solid.warps.empty()) transform_warps(t, m, det, solid);
  for (Leaf& leaf : solid.leaves) {
    if (leaf.is_implicit()) continue;  // transform_fields / transform_warps set its box
    leaf.bbox = Bbox{};                // over the vertices of its faces, as make_leaf's face_bbox
    for (uint32_t f = leaf.first_face; f < leaf.first_face + leaf.face_count; ++f)
      for (uint32_t v : solid.face(f)) leaf.bbox.add(solid.vertices[v]);
  }
  return solid;
}

}  // namespace cover
