#pragma once
// Affine transforms of leaves (docs/cli.md#scenes). Applied once to the vertices, rounded
// to doubles; everything after that is exact on those doubles (docs/design.md#exactness).

#include <Eigen/Core>

#include "solid/polygon_mesh.h"
#include "solid/solid.h"

namespace cover {

/// 4×4 affine matrix acting on column vectors (p' = M·[p;1]); last row is 0 0 0 1.
using Affine = Eigen::Matrix4d;

/// M = T·R·S: scale (per axis) first, then rotation about `axis` (unit length not required,
/// must be non-zero) by `degrees` (right-hand rule), then translation.
Affine make_trs(Eigen::Vector3d scale, Eigen::Vector3d axis, double degrees,
                Eigen::Vector3d translate);

/// Applies `m` to every vertex; when det(m) < 0 every face is reversed so that a closed,
/// outward mesh stays outward (mirroring keeps solids solid).
void apply_transform(const Affine& m, PolygonMesh& mesh);

/// The whole solid mapped by `m` (every leaf, the expression kept): vertices transformed and
/// rounded once more, leaf boxes recomputed; when det(m) < 0 every stored face is reversed, which
/// keeps each leaf outward and the covering's combined orientation (solid.h notation).
/// \throws InputError when m is not affine (last row 0 0 0 1), has a non-finite entry, a
/// singular linear part or one whose determinant (the factor of every volume) is beyond the
/// normal doubles (|det| < 2^-1022 or overflowing: "the determinant, about 1e-600, ..."), or
/// maps a vertex outside ±kMaxCoordinate.
Solid transform_solid(const Affine& m, Solid solid);

}  // namespace cover
