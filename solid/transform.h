#pragma once
// Affine transforms of leaves (docs/cli.md#scenes). Applied once to the vertices, rounded
// to doubles; everything after that is exact on those doubles (docs/design.md#exactness).

#include <array>
#include <span>

#include "cover/solid/polygon_mesh.h"
#include "cover/solid/solid.h"
#include "cover/solid/types.h"

namespace cover {

/// An affine map p' = L·p + t, held as the 3×4 matrix [L | t] by rows (rows[r][3] is t[r]); the
/// implied fourth row is 0 0 0 1. Default: the identity. Products and applications round the
/// same way as the 4×4 double matrix product they stand for.
struct Transform {
  std::array<std::array<double, 4>, 3> rows{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

  /// T·R·S: scale (per axis) first, then rotation about `axis` (unit length not required, must
  /// be non-zero when degrees ≠ 0) by `degrees` (right-hand rule), then translation.
  static Transform trs(Vec3 scale, Vec3 axis, double degrees, Vec3 translate);
  static Transform translation(Vec3 offset) { return trs({1, 1, 1}, {0, 0, 1}, 0, offset); }
  static Transform scaling(Vec3 factors) { return trs(factors, {0, 0, 1}, 0, {0, 0, 0}); }
  /// Rotation by `degrees` about the line through the origin along `axis`.
  static Transform rotation(Vec3 axis, double degrees) {
    return trs({1, 1, 1}, axis, degrees, {0, 0, 0});
  }
  /// Reflection in the plane through the origin with normal `normal` (non-zero):
  /// L = I − 2·n·nᵀ/|n|² (Householder).
  static Transform reflection(Vec3 normal);
  /// Places a model: scales `box` uniformly so that its largest extent becomes 2·half_size,
  /// rotates it by `degrees` about `axis` through its centre and moves that centre to `centre`:
  /// trs(s, axis, degrees, centre) · translation(−box centre). \pre box not empty, with a
  /// positive extent.
  static Transform fit(const Bbox& box, Vec3 centre, double half_size, Vec3 axis = {0, 0, 1},
                       double degrees = 0);
  /// From a 4×4 matrix, row-major. \throws InputError unless its last row is 0 0 0 1.
  static Transform from_matrix(std::span<const double, 16> row_major);

  /// This map after `first`: (a * b)(p) = a(b(p)).
  Transform operator*(const Transform& first) const;
  Vec3 operator()(Vec3 p) const;
  /// det L: the factor of every volume (negative for a mirror).
  double determinant() const;
  friend bool operator==(const Transform&, const Transform&) = default;
};

/// Applies `m` to every vertex; when det(m) < 0 every face is reversed so that a closed,
/// outward mesh stays outward (mirroring keeps solids solid).
void apply_transform(const Transform& m, PolygonMesh& mesh);

/// The whole solid mapped by `m` (every leaf, the expression kept): vertices transformed and
/// rounded once more, leaf boxes recomputed; when det(m) < 0 every stored face is reversed, which
/// keeps each leaf outward and the covering's combined orientation (solid.h notation).
/// \throws InputError when m has a non-finite entry, a singular linear part or one whose
/// determinant (the factor of every volume) is beyond the normal doubles (|det| < 2^-1022 or
/// overflowing: "the determinant, about 1e-600, ..."), or maps a vertex outside ±kMaxCoordinate.
Solid transform_solid(const Transform& m, Solid solid);

}  // namespace cover
